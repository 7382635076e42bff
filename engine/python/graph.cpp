// keel Python module — pose-graph files (keel::graph): Graph2D / Graph3D, candidate files, data sets.
#include <fmt/format.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <variant>

#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "candidates.hpp"
#include "datasets/manifest.hpp"
#include "app/files.hpp"
#include "graph/g2o.hpp"
#include "graph/io.hpp"
#include "graph/text_records.hpp"
#include "graph/trajectory.hpp"

namespace keel::python {

namespace {

using graph::PoseGraph2D;
using graph::PoseGraph3D;

int dim_of(const py::object& dim, const char* who) {
  if (dim.is_none()) return 0;
  const int d = int_arg(dim, who, "dim");
  if (d != 2 && d != 3)
    throw std::invalid_argument(fmt::format("{}: dim must be 2, 3 or None (got {})", who, d));
  return d;
}

// Runs a writer: a file that cannot be written (the writers throw std::runtime_error naming the file and what
// failed) becomes WriteError, an OSError in Python; refused values (std::invalid_argument) pass through.
template <class Write>
void written(const Write& write) {
  try {
    write();
  } catch (const std::invalid_argument&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw WriteError(e.what());
  }
}

template <class Graph>
std::string graph_repr(const char* name, const Graph& g) {
  return fmt::format("{}(<{} poses, {} edges>, source='{}')", name, g.poses.size(), g.edges.size(), g.source);
}

const char* kGraphDoc = R"doc(
A {0} pose graph (keel::graph::PoseGraph{0}): the poses of the file (or chained odometry) and its edges.

Convention (every file format is converted to it): an edge (i, j) measures z_ij ~ T_i^-1 T_j, the pose of j in
the frame of i; its residual is r = rho(z^-1 T_i^-1 T_j) ({1}) and `information` is the inverse covariance of
r. Arrays are copies: `poses` can be assigned as a whole ((n, {2}) array), the other properties are read-only.
Make one with keel.read_graph or {0}(poses, edges, measurements, information=None).)doc";

// A pose index for Graph*.gauge_pose: IndexError outside 0 .. n-1.
int gauge_pose_in(std::size_t n, long long k, const char* what) {
  if (k < 0 || static_cast<unsigned long long>(k) >= n)
    throw py::index_error(fmt::format("{}: pose {} is not in the graph ({} poses: 0 .. {})", what, k, n,
                                      static_cast<long long>(n) - 1));
  return static_cast<int>(k);
}

}  // namespace

void bind_graph(py::module_& m) {
  // ---- Graph2D ----
  py::class_<PoseGraph2D>(
      m, "Graph2D",
      fmt::format(fmt::runtime(kGraphDoc), "2D", "2D r = (x_E, y_E, theta_E), theta wrapped to (-pi, pi]", 3)
          .c_str())
      .def(py::init([](const py::object& poses, const py::object& edges, const py::object& measurements,
                       const py::object& information) {
             PoseGraph2D g;
             g.poses = poses2_from_array(poses, "Graph2D");
             g.edges = edges2_from_arrays(edges, measurements, information, "Graph2D",
                                          static_cast<long long>(g.poses.size()));
             g.has_initial_poses = true;
             return g;
           }),
           py::arg("poses"), py::arg("edges"), py::arg("measurements"), py::arg("information") = py::none(),
           "From (n, 3) poses [x, y, theta], (m, 2) edge ids, (m, 3) measurements and (m, 3, 3) information "
           "(None: identity). Edge ids must be integers (an integer dtype: a float array is refused, "
           "TypeError) naming poses 0 .. n-1 (IndexError; OverflowError beyond the C++ int range); each "
           "information matrix must be symmetric and positive definite as read_graph demands (ValueError).")
      .def_property(
          "poses", [](const PoseGraph2D& g) { return poses_to_array(g.poses); },
          [](PoseGraph2D& g, const py::object& a) {
            auto p = poses2_from_array(a, "Graph2D.poses");
            if (!g.poses.empty() && p.size() != g.poses.size())
              throw std::invalid_argument(
                  fmt::format("Graph2D.poses: the graph has {} poses (got {})", g.poses.size(), p.size()));
            g.poses = std::move(p);
          },
          "(n, 3) array of [x, y, theta] (a copy; assign a whole array of the same shape to change them).")
      .def_property_readonly(
          "edges", [](const PoseGraph2D& g) { return edge_ids(g.edges); }, "(m, 2) int64 array [i, j].")
      .def_property_readonly(
          "measurements", [](const PoseGraph2D& g) { return edge_measurements(g.edges); },
          "(m, 3) array of z_ij = [x, y, theta].")
      .def_property_readonly(
          "information", [](const PoseGraph2D& g) { return edge_information(g.edges); },
          "(m, 3, 3) array: the information of each edge's residual over (x, y, theta).")
      .def_property_readonly(
          "num_poses", [](const PoseGraph2D& g) { return g.poses.size(); }, "Number of poses.")
      .def_property_readonly(
          "num_edges", [](const PoseGraph2D& g) { return g.edges.size(); }, "Number of pose-pose edges.")
      .def_property_readonly(
          "num_landmarks", [](const PoseGraph2D& g) { return g.landmarks.size(); },
          "Number of landmarks (iSAM LANDMARK records; kept, solved and written, but not exposed as arrays).")
      .def_readonly("source", &PoseGraph2D::source,
                    "The file the graph was read from ('' if made in Python).")
      .def_readonly("has_initial_poses", &PoseGraph2D::has_initial_poses,
                    "True when the file carried vertex estimates (False: poses chained from the odometry).")
      .def_property(
          "gauge_pose", [](const PoseGraph2D& g) { return g.gauge_pose; },
          [](PoseGraph2D& g, long long k) {
            g.gauge_pose = gauge_pose_in(g.poses.size(), k, "Graph2D.gauge_pose");
          },
          "The pose every solve holds at its input value, and that keel.marginals reports fixed (the gauge; "
          "a "
          "g2o file's FIX line, 0 by default). Assign a pose index 0 .. n-1 (IndexError otherwise); "
          "write_graph writes it as 'FIX k' to g2o (an iSAM .txt file cannot hold it: ValueError).")
      .def(
          "copy", [](const PoseGraph2D& g) { return g; }, "A deep copy.")
      .def("__copy__", [](const PoseGraph2D& g) { return g; })
      .def(
          "__deepcopy__", [](const PoseGraph2D& g, const py::dict&) { return g; }, py::arg("memo"))
      .def("__repr__", [](const PoseGraph2D& g) { return graph_repr("Graph2D", g); });

  // ---- Graph3D ----
  py::class_<PoseGraph3D>(
      m, "Graph3D",
      fmt::format(fmt::runtime(kGraphDoc), "3D", "3D r = (t_E, Log R_E), translation then rotation vector", 7)
          .c_str())
      .def(py::init([](const py::object& poses, const py::object& edges, const py::object& measurements,
                       const py::object& information) {
             PoseGraph3D g;
             g.poses = poses3_from_array(poses, "Graph3D");
             g.edges = edges3_from_arrays(edges, measurements, information, "Graph3D",
                                          static_cast<long long>(g.poses.size()));
             g.has_initial_poses = true;
             return g;
           }),
           py::arg("poses"), py::arg("edges"), py::arg("measurements"), py::arg("information") = py::none(),
           "From (n, 7) poses [x, y, z, qx, qy, qz, qw], (m, 2) edge ids, (m, 7) measurements and (m, 6, 6) "
           "information over (t, phi) (None: identity). Ids and information are checked as in Graph2D.")
      .def_property(
          "poses", [](const PoseGraph3D& g) { return poses_to_array(g.poses); },
          [](PoseGraph3D& g, const py::object& a) {
            auto p = poses3_from_array(a, "Graph3D.poses");
            if (!g.poses.empty() && p.size() != g.poses.size())
              throw std::invalid_argument(
                  fmt::format("Graph3D.poses: the graph has {} poses (got {})", g.poses.size(), p.size()));
            g.poses = std::move(p);
          },
          "(n, 7) array of [x, y, z, qx, qy, qz, qw] with qw >= 0 (a copy; assign a whole array of the same "
          "shape to change them; quaternions are normalised).")
      .def_property_readonly(
          "edges", [](const PoseGraph3D& g) { return edge_ids(g.edges); }, "(m, 2) int64 array [i, j].")
      .def_property_readonly(
          "measurements", [](const PoseGraph3D& g) { return edge_measurements(g.edges); },
          "(m, 7) array of z_ij = [x, y, z, qx, qy, qz, qw].")
      .def_property_readonly(
          "information", [](const PoseGraph3D& g) { return edge_information(g.edges); },
          "(m, 6, 6) array: the information of each edge's residual over (t, phi) (g2o's (t, q_vec) "
          "information is converted on reading).")
      .def_property_readonly(
          "num_poses", [](const PoseGraph3D& g) { return g.poses.size(); }, "Number of poses.")
      .def_property_readonly(
          "num_edges", [](const PoseGraph3D& g) { return g.edges.size(); }, "Number of edges.")
      .def_readonly("source", &PoseGraph3D::source,
                    "The file the graph was read from ('' if made in Python).")
      .def_readonly("has_initial_poses", &PoseGraph3D::has_initial_poses,
                    "True when the file carried vertex estimates (False: poses chained from the odometry).")
      .def_property(
          "gauge_pose", [](const PoseGraph3D& g) { return g.gauge_pose; },
          [](PoseGraph3D& g, long long k) {
            g.gauge_pose = gauge_pose_in(g.poses.size(), k, "Graph3D.gauge_pose");
          },
          "The pose every solve holds at its input value, and that keel.marginals reports fixed (the gauge; "
          "a "
          "g2o file's FIX line, 0 by default). Assign a pose index 0 .. n-1 (IndexError otherwise); "
          "write_graph writes it as 'FIX k' to g2o (an iSAM .txt file cannot hold it: ValueError).")
      .def(
          "copy", [](const PoseGraph3D& g) { return g; }, "A deep copy.")
      .def("__copy__", [](const PoseGraph3D& g) { return g; })
      .def(
          "__deepcopy__", [](const PoseGraph3D& g, const py::dict&) { return g; }, py::arg("memo"))
      .def("__repr__", [](const PoseGraph3D& g) { return graph_repr("Graph3D", g); });

  // ---- Candidates ----
  py::class_<Candidates>(m, "Candidates", R"doc(
Candidate inter-robot loop closures (edge-only g2o files, `keel pcm`): edge k = (i, j) is a pose id i of robot a
and a pose id j of robot b (two id spaces, so i = j is allowed) and measures z ~ (T^a_i)^-1 T^b_j, with the
information of its residual as in a graph's edges. `dim` is 2 or 3; the arrays are as in Graph2D / Graph3D.)doc")
      .def(
          py::init(
              [](const py::object& edges, const py::object& measurements, const py::object& information) {
                Candidates c;
                const Array z = Array::ensure(measurements);
                PyErr_Clear();
                const py::ssize_t cols = z && z.ndim() == 2 ? z.shape(1) : 0;
                if (cols == 7) {
                  c.edges = edges3_from_arrays(edges, measurements, information, "Candidates", -1);
                } else {
                  c.edges = edges2_from_arrays(edges, measurements, information, "Candidates", -1);
                }
                return c;
              }),
          py::arg("edges"), py::arg("measurements"), py::arg("information") = py::none(),
          "From (m, 2) ids [pose of a, pose of b], (m, 3) or (m, 7) measurements (which decides dim) and "
          "(m, d, d) information (None: identity). Ids must be integers >= 0 (TypeError for a float array, "
          "IndexError for a negative id, OverflowError beyond the C++ int range); information as in Graph2D.")
      .def_property_readonly("dim", &Candidates::dim, "2 or 3.")
      .def_property_readonly(
          "edges",
          [](const Candidates& c) { return std::visit([](const auto& e) { return edge_ids(e); }, c.edges); },
          "(m, 2) int64 array [pose of robot a, pose of robot b].")
      .def_property_readonly(
          "measurements",
          [](const Candidates& c) {
            return std::visit([](const auto& e) { return edge_measurements(e); }, c.edges);
          },
          "(m, 3) or (m, 7) array of the measurements z.")
      .def_property_readonly(
          "information",
          [](const Candidates& c) {
            return std::visit([](const auto& e) { return edge_information(e); }, c.edges);
          },
          "(m, 3, 3) or (m, 6, 6) information of each measurement's residual.")
      .def_property_readonly("num_edges", &Candidates::size, "Number of candidates.")
      .def("__len__", &Candidates::size)
      .def_readonly("source", &Candidates::source, "The file they were read from ('' if made in Python).")
      .def("__repr__", [](const Candidates& c) {
        return fmt::format("Candidates(<{} {}D edges>, source='{}')", c.size(), c.dim(), c.source);
      });

  // ---- files ----
  m.def(
      "read_graph",
      [](const std::filesystem::path& file, const py::object& dim_obj) -> py::object {
        const std::string path = file.string();
        const int dim = dim_of(dim_obj, "read_graph");
        std::variant<PoseGraph2D, PoseGraph3D> g;
        {
          py::gil_scoped_release release;
          const std::string text = graph::read_file_text(path);
          const bool is3d = dim == 0 ? app::graph_dimension(text, path) == 3 : dim == 3;
          std::istringstream in(text);
          if (is3d) {
            g = graph::read_pose_graph_3d(in, path);
          } else {
            g = graph::read_pose_graph_2d(in, path);
          }
        }
        return std::visit([](auto& x) { return py::cast(std::move(x)); }, g);
      },
      py::arg("path"), py::arg("dim") = py::none(), R"doc(
Reads a pose graph, g2o or iSAM text; the format is detected from the first record's tag (then the extension)
exactly as keel::graph::read_pose_graph_2d/3d do. dim=None decides the dimension from that same first tag:
VERTEX_SE3:QUAT, EDGE_SE3:QUAT and EDGE3 make a Graph3D, anything else a Graph2D (whose reader then rejects
a malformed or mixed file). dim=2 / dim=3 force the reader; a file of the other dimension raises ParseError
saying so. Errors: ParseError (ValueError) naming file, line and field.)doc");

  m.def(
      "write_graph",
      [](const py::object& g, const std::filesystem::path& file, const py::object& poses) {
        const std::string path = file.string();
        if (py::isinstance<PoseGraph2D>(g)) {
          PoseGraph2D copy = g.cast<PoseGraph2D>();
          if (!poses.is_none()) {
            auto p = poses2_from_array(poses, "write_graph (poses)");
            // read_graph would refuse a file whose vertices and edges disagree: refuse it before writing.
            if (p.size() != copy.poses.size())
              throw std::invalid_argument(fmt::format(
                  "write_graph: poses has {} rows but the graph has {} poses", p.size(), copy.poses.size()));
            copy.poses = std::move(p);
            copy.has_initial_poses = true;
          }
          py::gil_scoped_release release;
          written([&] { graph::write_pose_graph(copy, path); });
        } else if (py::isinstance<PoseGraph3D>(g)) {
          PoseGraph3D copy = g.cast<PoseGraph3D>();
          if (!poses.is_none()) {
            auto p = poses3_from_array(poses, "write_graph (poses)");
            // read_graph would refuse a file whose vertices and edges disagree: refuse it before writing.
            if (p.size() != copy.poses.size())
              throw std::invalid_argument(fmt::format(
                  "write_graph: poses has {} rows but the graph has {} poses", p.size(), copy.poses.size()));
            copy.poses = std::move(p);
            copy.has_initial_poses = true;
          }
          py::gil_scoped_release release;
          written([&] { graph::write_pose_graph(copy, path); });
        } else {
          throw py::type_error("write_graph: graph must be a keel.Graph2D or keel.Graph3D");
        }
      },
      py::arg("graph"), py::arg("path"), py::arg("poses") = py::none(), R"doc(
Writes a graph; the format comes from the extension (.g2o: g2o, .txt: iSAM text, else ValueError), numbers
with %.17g so a read gives back every field to the last bit (angles as theta in (-pi, pi], quaternions with
w >= 0). `poses` ((n, 3) / (n, 7), n the graph's number of poses, else ValueError) replaces the graph's poses
in the file, e.g. a solution. The file is written to a temporary name and renamed; a file that cannot be
written raises OSError naming it.)doc");

  m.def(
      "read_candidates",
      [](const std::filesystem::path& file, const py::object& dim_obj) {
        const std::string path = file.string();
        const int dim = dim_of(dim_obj, "read_candidates");
        Candidates c;
        c.source = path;
        py::gil_scoped_release release;
        const std::string text = graph::read_file_text(path);
        const bool is3d = dim == 0 ? app::graph_dimension(text, path) == 3 : dim == 3;
        std::istringstream in(text);
        if (is3d) {
          c.edges = graph::read_g2o_edges_3d(in, path);
        } else {
          c.edges = graph::read_g2o_edges_2d(in, path);
        }
        return c;
      },
      py::arg("path"), py::arg("dim") = 2, R"doc(
Reads candidate inter-robot loop closures: an edge-only g2o file (every record EDGE_SE2 for dim=2 or
EDGE_SE3:QUAT for dim=3; dim=None: from the first record's tag). ParseError (file, line, field) for a malformed
record, any other tag, or a file without edges.)doc");

  m.def(
      "write_candidates",
      [](const Candidates& c, const std::filesystem::path& file) {
        const std::string path = file.string();
        py::gil_scoped_release release;
        written([&] { std::visit([&](const auto& e) { graph::write_g2o_edges(e, path); }, c.edges); });
      },
      py::arg("candidates"), py::arg("path"),
      "Writes candidates as an edge-only g2o file (%.17g, atomically); read_candidates gives them back to "
      "the last bit. OSError when the file cannot be written.");

  m.def(
      "read_poses",
      [](const std::filesystem::path& file, const py::object& dim_obj) {
        const std::string path = file.string();
        const int dim = int_arg(dim_obj, "read_poses", "dim");
        if (dim == 2) {
          std::vector<lie::SE2> p;
          {
            py::gil_scoped_release release;
            p = graph::read_poses_2d(path);
          }
          return poses_to_array(p);
        }
        if (dim == 3) {
          std::vector<lie::SE3> p;
          {
            py::gil_scoped_release release;
            p = graph::read_poses_3d(path);
          }
          return poses_to_array(p);
        }
        throw std::invalid_argument(fmt::format("read_poses: dim must be 2 or 3 (got {})", dim));
      },
      py::arg("path"), py::arg("dim") = 2, R"doc(
Reads a pose list `id x y theta` (dim=2) or `id x y z qx qy qz qw` (dim=3), ids contiguous from 0 in any order
(the derived ground-truth files of the data sets) -> (n, 3) / (n, 7) array.)doc");

  m.def(
      "dataset_file",
      [](const std::string& name, const std::string& path) {
        return datasets::resolve_dataset_file(name, path).string();
      },
      py::arg("name"), py::arg("path"), R"doc(
The verified local copy of a data-set file listed in datasets/manifest.toml (sha256-checked), e.g.
keel.dataset_file("manhattan3500", "isam/manhattanOlson3500.txt"). Looks in $KEEL_DATASETS/<name>/,
<repo>/datasets/cache/<name>/ and <repo>/../shared/datasets/<name>/, <repo> being the nearest ancestor of the
current directory holding datasets/manifest.toml. Raises DatasetError (a RuntimeError) listing every place
tried and what was wrong there.)doc");
}

}  // namespace keel::python
