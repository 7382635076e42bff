// keel Python module — pairwise consistency (thesis eq. 2.4), maximum clique and PCM selection (§2.5).
#include <fmt/format.h>

#include <climits>
#include <cmath>
#include <optional>
#include <tuple>
#include <variant>

#include "bindings.hpp"
#include "candidates.hpp"
#include "app/pcm.hpp"
#include "pcm/clique.hpp"
#include "pcm/consistency.hpp"
#include "pcm/selection.hpp"

namespace keel::python {

namespace {

struct PcmSelection {
  std::vector<int> selected;
  double gamma = 0.0;
  pcm::CliqueResult search;
  double time_s = 0.0;
};

pcm::ConsistencyMatrix q_from_array(const py::object& in, int dof) {
  const Array a = numeric_array(in, "pcm_select", "Q");
  if (a.ndim() != 2 || a.shape(0) != a.shape(1))
    throw std::invalid_argument("pcm_select: Q must be a square (n, n) float array");
  pcm::ConsistencyMatrix Q;
  Q.n = static_cast<int>(a.shape(0));
  Q.dof = dof;
  Q.q.assign(a.data(), a.data() + a.size());
  return Q;
}

// time_limit_s: None (no limit) or a number of seconds > 0 (the engine reads 0, a negative number or NaN as
// "no limit", which a caller who gave one did not mean).
pcm::CliqueOptions clique_options(const std::optional<double>& time_limit_s, const char* who) {
  pcm::CliqueOptions o;
  if (time_limit_s) {
    if (!(*time_limit_s > 0.0))
      throw std::invalid_argument(fmt::format(
          "{}: time_limit_s must be > 0 seconds or None for no limit (got {})", who, *time_limit_s));
    o.time_limit_s = *time_limit_s;
  }
  return o;
}

// An (n, n) adjacency of bools, or of numbers that are exactly 0 or 1: anything else (NaN, 0.5, 2, a
// string) is refused instead of being read as true.
std::vector<std::vector<bool>> adjacency_rows(const py::object& in) {
  const py::array raw = py::array::ensure(in);
  if (!raw) PyErr_Clear();
  const char kind = raw ? raw.dtype().kind() : 'O';
  if (!raw || (kind != 'b' && kind != 'f' && kind != 'i' && kind != 'u' && raw.size() > 0))
    throw py::type_error(
        fmt::format("max_clique: adjacency must be an (n, n) array of bool or 0/1 (got {}{})", type_name(in),
                    raw ? " of dtype " + py::str(raw.dtype()).cast<std::string>() : ""));
  if (raw.ndim() != 2 || raw.shape(0) != raw.shape(1))
    throw std::invalid_argument("max_clique: adjacency must be a square (n, n) array of bool or 0/1");
  const Array a = Array::ensure(raw);  // bool and integers convert exactly
  if (!a) {
    PyErr_Clear();
    throw py::type_error("max_clique: adjacency must be an (n, n) array of bool or 0/1");
  }
  const auto n = static_cast<std::size_t>(a.shape(0));
  std::vector<std::vector<bool>> rows(n, std::vector<bool>(n));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (py::ssize_t j = 0; j < a.shape(1); ++j) {
      const double x = r(i, j);
      if (x != 0.0 && x != 1.0)
        throw std::invalid_argument(
            fmt::format("max_clique: adjacency[{}, {}] = {} is neither 0 nor 1 (nor a bool)", i, j, x));
      rows[i][j] = x == 1.0;
    }
  return rows;
}

// Candidate k = (i, j) names pose i of graph_a and pose j of graph_b: IndexError otherwise (ids out of range
// are IndexError throughout the module).
template <class Edge, class Graph>
void check_candidate_ids(const std::vector<Edge>& edges, const Graph& a, const Graph& b) {
  for (std::size_t k = 0; k < edges.size(); ++k)
    for (const auto& [id, g, name, col] :
         {std::tuple{edges[k].i, &a, "graph_a", 0}, std::tuple{edges[k].j, &b, "graph_b", 1}})
      if (id < 0 || static_cast<std::size_t>(id) >= g->poses.size())
        throw std::out_of_range(fmt::format(
            "consistency_matrix: candidates.edges[{}, {}] = {} is not a pose of {} (it has {} poses)", k, col,
            id, name, g->poses.size()));
}

}  // namespace

void bind_pcm(py::module_& m) {
  py::class_<pcm::CliqueResult>(m, "CliqueResult", "The result of keel.max_clique (pcm::CliqueResult).")
      .def_readonly("clique", &pcm::CliqueResult::clique, "Sorted vertex ids of the largest clique found.")
      .def_readonly("upper_bound", &pcm::CliqueResult::upper_bound, "No clique is larger than this.")
      .def_property_readonly(
          "status", [](const pcm::CliqueResult& r) { return std::string(keel::core::to_string(r.status)); },
          "'optimal' (proven maximum), 'unproven' (heuristic), 'node_limit' or 'time_limit' "
          "(core::SearchStatus).")
      .def_property_readonly("proven_optimal", &pcm::CliqueResult::proven_optimal, "status == 'optimal'.")
      .def_property_readonly(
          "gap", &pcm::CliqueResult::gap,
          "upper_bound - len(clique): how much larger a clique could still be (0 iff optimal).")
      .def_readonly("nodes_explored", &pcm::CliqueResult::nodes_explored, "Branch-and-bound calls.")
      .def_readonly("time_s", &pcm::CliqueResult::time_s, "Search wall time in seconds.")
      .def("__repr__", [](const pcm::CliqueResult& r) {
        return fmt::format("CliqueResult(size={}, upper_bound={}, status='{}')", r.clique.size(),
                           r.upper_bound, keel::core::to_string(r.status));
      });

  py::class_<PcmSelection>(m, "PcmSelection", "The result of keel.pcm_select (pcm::Selection of select_pcm).")
      .def_readonly("selected", &PcmSelection::selected, "Sorted indices of the selected candidates.")
      .def_readonly("gamma", &PcmSelection::gamma, "The consistency threshold used (squared distance).")
      .def_property_readonly(
          "status", [](const PcmSelection& s) { return std::string(keel::core::to_string(s.search.status)); },
          "The clique search's core::SearchStatus: 'optimal', 'unproven', 'node_limit' or 'time_limit'.")
      .def_property_readonly(
          "upper_bound", [](const PcmSelection& s) { return s.search.upper_bound; },
          "Proven bound on the size of a consistent set (exact: branch and bound; heuristic: max core + 1).")
      .def_property_readonly(
          "gap", [](const PcmSelection& s) { return s.search.gap(); },
          "upper_bound - len(selected): 0 iff the selection is proven maximum.")
      .def_readonly("time_s", &PcmSelection::time_s, "Wall time of thresholding Q plus the clique search.")
      .def("__repr__", [](const PcmSelection& s) {
        return fmt::format("PcmSelection(size={}, gamma={:.17g}, status='{}')", s.selected.size(), s.gamma,
                           keel::core::to_string(s.search.status));
      });

  m.def(
      "consistency_matrix",
      [](const py::object& ga, const py::object& gb, const Candidates& c, const std::string& composition,
         const py::object& threads) {
        app::PcmOptions o;  // of which app::consistency uses local, composition and threads
        o.composition = pcm::composition_from_string(composition);
        o.threads = static_cast<unsigned>(uint_arg(threads, "consistency_matrix", "threads", UINT_MAX));
        pcm::ConsistencyMatrix Q;
        if (py::isinstance<graph::PoseGraph2D>(ga) && py::isinstance<graph::PoseGraph2D>(gb) &&
            c.dim() == 2) {
          const auto& a = ga.cast<const graph::PoseGraph2D&>();
          const auto& b = gb.cast<const graph::PoseGraph2D&>();
          check_candidate_ids(std::get<0>(c.edges), a, b);
          py::gil_scoped_release release;
          Q = app::consistency(a, b, std::get<0>(c.edges), o).q;
        } else if (py::isinstance<graph::PoseGraph3D>(ga) && py::isinstance<graph::PoseGraph3D>(gb) &&
                   c.dim() == 3) {
          const auto& a = ga.cast<const graph::PoseGraph3D&>();
          const auto& b = gb.cast<const graph::PoseGraph3D&>();
          check_candidate_ids(std::get<1>(c.edges), a, b);
          py::gil_scoped_release release;
          Q = app::consistency(a, b, std::get<1>(c.edges), o).q;
        } else {
          throw py::type_error(
              "consistency_matrix: graph_a, graph_b and candidates must all be 2D (Graph2D) or all 3D "
              "(Graph3D)");
        }
        // NaN in Q (graphs or candidates whose numbers overflow) raises instead of reaching pcm_select.
        for (std::size_t k = 0; k < Q.q.size(); ++k)
          if (std::isnan(Q.q[k]))
            throw NonFiniteResult(
                fmt::format("consistency_matrix: Q[{}, {}] is NaN: the graphs' or the candidates' "
                            "numbers overflow double precision",
                            k / static_cast<std::size_t>(Q.n), k % static_cast<std::size_t>(Q.n)));
        Array out({static_cast<py::ssize_t>(Q.n), static_cast<py::ssize_t>(Q.n)});
        std::copy(Q.q.begin(), Q.q.end(), out.mutable_data());
        return out;
      },
      py::arg("graph_a"), py::arg("graph_b"), py::arg("candidates"), py::arg("composition") = "joint",
      py::arg("threads") = 1, R"doc(
The n x n matrix Q of pairwise consistency (thesis section 2.4.1, eq. 2.4; section 2.6): q_uv is the SQUARED
Mahalanobis distance of the loop error eps_uv = Log(z_u^-1 x^a_ij z_v x^b_lk) of candidates u and v (zero
diagonal; q_uv ~ q_vu to first order only). Steps, with the engine's defaults:
  1. merge::solve_local on each graph (pgo defaults, init='odometry', one solver thread) and a CHOLMOD
     factorization of its information at the solution (pose 0 fixed);
  2. each candidate's information is turned into the covariance of its left perturbation
     (pcm::left_covariance_from_information: Sigma = Ad(z) Omega^-1 Ad(z)^T);
  3. merge::local_maps: the joint marginal of the poses the candidates touch;
  4. pcm::consistency_matrix with `composition` 'joint' (relative poses with their cross-covariance, thesis
     ch. 5) or 'independent' (cross-covariance dropped), `threads` workers (the result does not depend on it).
For inliers q_uv ~ chi2(dof), dof = 3 (2D) or 6 (3D).)doc");

  m.def(
      "consistency_threshold",
      [](double p, const py::object& dof) {
        return pcm::consistency_threshold(p, int_arg(dof, "consistency_threshold", "dof"));
      },
      py::arg("p"), py::arg("dof"),
      "gamma(p) = F^-1_chi2(dof)(1 - p): a pair is consistent when its squared distance has a chi2 tail "
      "probability of at least p (larger p is stricter). p in (0, 1), else ValueError.");

  m.def(
      "pcm_select",
      [](const py::object& q, double p, const std::optional<double>& gamma, const py::object& dof_obj,
         const std::string& algorithm, const std::optional<double>& time_limit_s) {
        const int dof = int_arg(dof_obj, "pcm_select", "dof");
        pcm::ConsistencyMatrix Q = q_from_array(q, dof);
        const pcm::CliqueAlgorithm alg = pcm::clique_algorithm_from_string(algorithm);
        const pcm::CliqueOptions o = clique_options(time_limit_s, "pcm_select");
        PcmSelection out;
        py::gil_scoped_release release;
        out.gamma = gamma ? *gamma : pcm::consistency_threshold(p, dof);
        pcm::Selection s = pcm::select_pcm(Q, out.gamma, alg, o);
        out.selected = std::move(s.selected);
        out.time_s = s.time_s;
        if (s.search) out.search = std::move(*s.search);
        return out;
      },
      py::arg("Q"), py::arg("p") = 0.11, py::arg("gamma") = py::none(), py::arg("dof") = 3,
      py::arg("algorithm") = "exact", py::arg("time_limit_s") = py::none(), R"doc(
PCM (thesis eq. 2.5, section 2.5): the largest set of pairwise-consistent candidates = the maximum clique of
the consistency graph with edge {u, v} iff q_uv <= gamma and q_vu <= gamma (pcm::select_pcm).
gamma = consistency_threshold(p, dof) unless given. algorithm: 'exact' (branch and bound), 'heuristic'
(Pattabiraman et al.'s, the thesis's PCM-HeuPatt) or 'brute_force' (<= 32 candidates). time_limit_s: exact
search only (> 0 seconds, else ValueError); then status may be 'time_limit'. Q: NaN or negative off-diagonal
entries raise ValueError, a non-numeric array TypeError; +inf means never consistent. dof: an integer.)doc");

  m.def(
      "max_clique",
      [](const py::object& adjacency, const std::string& algorithm,
         const std::optional<double>& time_limit_s) {
        const std::vector<std::vector<bool>> rows = adjacency_rows(adjacency);
        const pcm::CliqueAlgorithm alg = pcm::clique_algorithm_from_string(algorithm);
        const pcm::CliqueOptions o = clique_options(time_limit_s, "max_clique");
        py::gil_scoped_release release;
        return pcm::maximum_clique(pcm::ConsistencyGraph::from_matrix(rows), alg, o);
      },
      py::arg("adjacency"), py::arg("algorithm") = "exact", py::arg("time_limit_s") = py::none(), R"doc(
Maximum clique of an undirected graph given by a symmetric (n, n) bool / 0-1 adjacency matrix (the diagonal is
ignored; an asymmetric matrix, or an entry that is not exactly 0 or 1 (NaN, 0.5), raises ValueError naming the
entry; a non-numeric array TypeError). algorithm: 'exact', 'heuristic' or
'brute_force' (pcm::CliqueAlgorithm); time_limit_s limits the exact search. Returns a CliqueResult.)doc");
}

}  // namespace keel::python
