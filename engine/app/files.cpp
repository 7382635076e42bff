#include "app/files.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <utility>

#include "core/timing.hpp"
#include "graph/g2o.hpp"
#include "graph/io.hpp"
#include "graph/parse_error.hpp"
#include "graph/text_records.hpp"
#include "pgo/optimize.hpp"

namespace keel::app {

namespace {

// Union–find over the variables (poses, then landmarks).
struct Components {
  std::vector<int> parent;
  explicit Components(int n) : parent(static_cast<std::size_t>(n)) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  int find(int v) {
    while (parent[static_cast<std::size_t>(v)] != v) {
      parent[static_cast<std::size_t>(v)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
      v = parent[static_cast<std::size_t>(v)];
    }
    return v;
  }
  void join(int a, int b) { parent[static_cast<std::size_t>(find(a))] = find(b); }
};

// Counts, duplicates, noise levels of the edges; `dof` 3 (2D: x, y, θ) or 6 (3D: t, φ).
template <class Edge>
void summarize_edges(const std::vector<Edge>& edges, int translation_dims, GraphSummary& s, Components& cc) {
  std::set<std::pair<int, int>> seen;
  double st_min = std::numeric_limits<double>::infinity(), st_max = 0.0;
  double sr_min = std::numeric_limits<double>::infinity(), sr_max = 0.0;
  for (const auto& e : edges) {
    (std::abs(e.i - e.j) == 1 ? s.odometry : s.loop_closures) += 1;
    if (!seen.insert({std::min(e.i, e.j), std::max(e.i, e.j)}).second) ++s.duplicate_edges;
    const auto& W = e.information;
    const bool cross = (W - decltype(W)(W.diagonal().asDiagonal())).cwiseAbs().maxCoeff() > 0.0;
    if (cross) ++s.cross_term_edges;
    const auto cov = W.inverse().eval();
    for (int k = 0; k < W.rows(); ++k) {
      const double sigma = std::sqrt(cov(k, k));
      if (k < translation_dims) {
        st_min = std::min(st_min, sigma);
        st_max = std::max(st_max, sigma);
      } else {
        sr_min = std::min(sr_min, sigma);
        sr_max = std::max(sr_max, sigma);
      }
    }
    Eigen::SelfAdjointEigenSolver<std::decay_t<decltype(W)>> eig(W, Eigen::EigenvaluesOnly);
    s.condition_max = std::max(s.condition_max, eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff());
    cc.join(e.i, e.j);
  }
  if (!edges.empty()) {
    s.sigma_translation_min = st_min;
    s.sigma_translation_max = st_max;
    s.sigma_rotation_min = sr_min;
    s.sigma_rotation_max = sr_max;
  }
}

void count_components(GraphSummary& s, Components& cc, int variables) {
  std::map<int, int> size;
  for (int v = 0; v < variables; ++v) ++size[cc.find(v)];
  s.components = static_cast<int>(size.size());
  for (const auto& [root, n] : size) s.largest_component = std::max(s.largest_component, n);
}

}  // namespace

int graph_dimension(std::string_view text, const std::string& name) {
  graph::detail::RecordScanner sc(text, name);
  if (!sc.next()) return 2;
  const std::string_view tag = sc.tag();
  return (tag == "EDGE_SE3:QUAT" || tag == "VERTEX_SE3:QUAT" || tag == "EDGE3") ? 3 : 2;
}

int graph_dimension(const std::filesystem::path& file) {
  return graph_dimension(graph::detail::read_file_text(file), file.string());
}

GraphSummary summarize(const std::filesystem::path& file) {
  GraphSummary s;
  s.file = file.string();
  s.dimension = graph_dimension(file);
  const auto format = graph::detect_graph_format(graph::detail::read_file_text(file), file);
  s.format = format ? std::string(graph::to_string(*format)) : "unknown";
  if (s.dimension == 2) {
    const auto g = graph::read_pose_graph_2d(file);
    s.poses = static_cast<int>(g.poses.size());
    s.edges = static_cast<int>(g.edges.size());
    s.landmarks = static_cast<int>(g.landmarks.size());
    s.landmark_measurements = static_cast<int>(g.landmark_measurements.size());
    s.has_initial_poses = g.has_initial_poses;
    Components cc(s.poses + s.landmarks);
    summarize_edges(g.edges, 2, s, cc);
    for (const auto& m : g.landmark_measurements) cc.join(m.pose, s.poses + m.landmark);
    count_components(s, cc, s.poses + s.landmarks);
  } else {
    const auto g = graph::read_pose_graph_3d(file);
    s.poses = static_cast<int>(g.poses.size());
    s.edges = static_cast<int>(g.edges.size());
    s.has_initial_poses = g.has_initial_poses;
    Components cc(s.poses);
    summarize_edges(g.edges, 3, s, cc);
    count_components(s, cc, s.poses);
  }
  return s;
}

sim::CandidateSet2 split_files(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& ground_truth,
                               const SplitFilesOptions& options, const std::filesystem::path& dir) {
  const auto scenario = sim::split_two_robots(graph, ground_truth, options.split);
  auto set = sim::generate_candidates(scenario, options.candidates, options.seed, 0);
  std::filesystem::create_directories(dir);
  // The local graphs with vertices: the input's poses re-expressed (split_two_robots), or chained odometry.
  auto with_poses = [](graph::PoseGraph2D g) {
    if (g.poses.empty()) {
      pgo::Options o;
      o.initial_guess = pgo::InitialGuess::odometry;
      g.poses = pgo::initial_estimate(g, o).poses;
    }
    return g;
  };
  graph::write_pose_graph(with_poses(scenario.robot_a), dir / "a.g2o");
  graph::write_pose_graph(with_poses(scenario.robot_b), dir / "b.g2o");
  std::vector<graph::Edge2> edges;
  std::string labels = "# candidate kind group (written by keel split; inlier = a true loop closure)\n";
  for (std::size_t k = 0; k < set.candidates.size(); ++k) {
    const auto& c = set.candidates[k];
    edges.push_back({c.pose_a, c.pose_b, c.z, set.information[k], 0});
    labels += fmt::format("{} {} {}\n", k, sim::to_string(set.labels[k].kind), set.labels[k].group);
  }
  graph::write_g2o_edges(edges, dir / "candidates.g2o");
  graph::detail::write_file_atomically(dir / "labels.txt", labels);
  const auto& T = scenario.true_anchor;
  graph::detail::write_file_atomically(
      dir / "truth.txt",
      fmt::format("# T_ab: x y theta of robot b's frame in robot a's frame\n{} {} {}\n",
                  graph::detail::fmt17(T.translation().x()), graph::detail::fmt17(T.translation().y()),
                  graph::detail::fmt17(T.angle())));
  return set;
}

std::vector<bool> read_labels(const std::filesystem::path& file) {
  const std::string text = graph::detail::read_file_text(file);
  graph::detail::RecordScanner sc(text, file.string(), "label");
  static constexpr std::array<const char*, 3> kNames = {"candidate", "kind", "group"};
  std::vector<bool> inlier;
  while (sc.next()) {
    sc.expect(kNames);
    const int k = sc.id(1);
    if (k != static_cast<int>(inlier.size())) {
      sc.fail_field(
          1, fmt::format("expected candidate {} (labels list the candidates in order)", inlier.size()));
    }
    const std::string kind(sc.field(2));
    try {
      inlier.push_back(sim::measurement_label_from_string(kind) == sim::MeasurementLabel::inlier);
    } catch (const std::invalid_argument& e) {
      sc.fail_field(2, e.what());
    }
  }
  if (inlier.empty()) graph::detail::fail_at(file.string(), 0, "no label");
  return inlier;
}

}  // namespace keel::app
