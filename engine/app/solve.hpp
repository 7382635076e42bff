// keel::app — the batch maximum-likelihood solve of a user's pose graph (thesis eq. 2.1; keel.pgo, Ceres),
// shared by `keel solve`, `keel marginals` and Python's keel.solve, so that the same inputs give
// bit-identical results everywhere.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "graph/io.hpp"
#include "graph/pose_graph.hpp"
#include "pgo/certified.hpp"
#include "pgo/optimize.hpp"
#include "pgo/options.hpp"

namespace keel::app {

/// A graph file read by content: 2D or 3D (graph_dimension), g2o or iSAM.
using AnyGraph = std::variant<graph::PoseGraph2D, graph::PoseGraph3D>;
/// Reads a pose-graph file as the dimension of its first record says. Throws graph::ParseError naming file,
/// line and field.
/// `information` as in graph::InformationCheck (diagonal_blocks for the certified solve's isotropic model).
[[nodiscard]] AnyGraph read_graph(
    const std::filesystem::path& file,
    graph::InformationCheck information = graph::InformationCheck::positive_definite);
/// A graph file read once: the graph and the format its records are in (graph::detect_graph_format; g2o when
/// nothing says otherwise), so that a pipe, which cannot be read twice, needs no second look for its format.
struct GraphInput {
  AnyGraph graph;
  graph::GraphFormat format = graph::GraphFormat::g2o;
};
[[nodiscard]] GraphInput read_graph_input(
    const std::filesystem::path& file,
    graph::InformationCheck information = graph::InformationCheck::positive_definite);

/// The options of `keel solve` and Python's keel.solve: pgo's defaults with only these fields set.
struct SolveOptions {
  std::string init =
      "odometry";               // a pgo::InitialGuess name ('-' may stand for '_': "as-read"), or "supplied"
  std::string robust = "none";  // a pgo::RobustKernel name, on the loop closures
  double robust_parameter = 5.0;  // Huber/Cauchy a or DCS φ (> 0)
  std::uint64_t seed = 0;         // of init = "random"
  unsigned threads = 1;           // Ceres threads (the last bits of a result depend on it); 0 = all cores
  int max_iterations = 100;       // trust-region iterations (≥ 0)
  // certify = true: the certified solve of the isotropic model instead (pgo::solve_certified; init, robust,
  // seed, threads and max_iterations do not apply).
  bool certify = false;
  double gap_tolerance = 1e-6;  // relative duality gap that counts as certified
  int max_rank = 10;            // the staircase's last rank
  double time_limit_s = 0.0;    // wall-time limit of the certified solve (0: none)
  /// pgo::Options with these fields set. Throws std::invalid_argument for an unknown name or an invalid
  /// value.
  [[nodiscard]] pgo::Options pgo_options() const;
  /// pgo::CertifiedOptions with gap_tolerance, max_rank and time_limit_s set, checked
  /// (CertifiedOptions::validate, and max_rank >= 2, the smallest dimension; a rank below a 3D graph's d = 3
  /// is refused once the graph is read). Throws std::invalid_argument.
  [[nodiscard]] pgo::CertifiedOptions certified_options() const;
};

template <class Graph>
struct Solution {
  Graph graph;                         // the input with the solution as its estimate (poses; 2D: landmarks)
  pgo::Summary summary;                // the solver's summary (termination, costs, iterations, times)
  std::vector<pgo::EdgeReport> edges;  // per edge: χ² and kernel weight at the solution
  double solve_time_s = 0.0;           // wall time of pgo::optimize (initial estimate, set-up, solve)
};
using Solution2 = Solution<graph::PoseGraph2D>;
using Solution3 = Solution<graph::PoseGraph3D>;

/// The certified solve (pgo::solve_certified) and, at its estimate, the anisotropic maximum-likelihood cost
/// of eq. 2.1 that `solve` minimizes (the two problems differ; both costs are reported).
template <class Graph>
struct CertifiedSolution {
  Graph graph;  // the input with the certified estimate as its poses
  pgo::CertifiedSummary summary;
  double anisotropic_cost = 0.0;  // ½ Σ rᵀΩr at the certified estimate (pgo::evaluate); NaN when some Ω is
                                  // not positive definite (graph.indefinite_information > 0)
  double solve_time_s = 0.0;
};
using CertifiedSolution2 = CertifiedSolution<graph::PoseGraph2D>;
using CertifiedSolution3 = CertifiedSolution<graph::PoseGraph3D>;
/// Throws std::invalid_argument for invalid options, a disconnected graph, landmarks or weights that are not
/// positive.
[[nodiscard]] CertifiedSolution2 solve_certified(const graph::PoseGraph2D& g, const SolveOptions& options);
[[nodiscard]] CertifiedSolution3 solve_certified(const graph::PoseGraph3D& g, const SolveOptions& options);

/// Solves the graph from the initial guess of `options` (or `initial`, with init = "supplied"), the graph's
/// gauge pose (g.gauge_pose, pose 0 unless a g2o FIX line names another) held constant at its initial value
/// (the as-read pose: the odometry chain starts from it). A solver failure is reported in
/// summary.termination, not thrown; invalid options and graphs throw std::invalid_argument.
[[nodiscard]] Solution2 solve(const graph::PoseGraph2D& g, const SolveOptions& options = {},
                              const pgo::Estimate2D* initial = nullptr);
[[nodiscard]] Solution3 solve(const graph::PoseGraph3D& g, const SolveOptions& options = {},
                              const pgo::Estimate3D* initial = nullptr);

}  // namespace keel::app
