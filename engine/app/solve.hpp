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

/// The back ends of `keel solve` and Python's keel.solve, each holding its solver's own options.
///
/// The anisotropic maximum-likelihood solve of eq. 2.1 (pgo::optimize). Its defaults are pgo's with the
/// odometry chain as the initial guess; constant_poses is not read: solve() holds the graph's gauge pose.
struct MaximumLikelihood {
  pgo::Options options = defaults();
  [[nodiscard]] static pgo::Options defaults();
  /// options.validate(). Throws std::invalid_argument naming the field.
  void validate() const;
};
/// The certified solve of the isotropic model (pgo::solve_certified): chordal initialization, Riemannian
/// staircase, certificate; pgo's defaults.
struct Certified {
  pgo::CertifiedOptions options;
  /// options.validate(), and max_rank >= 2, the smallest dimension d (a rank below a 3D graph's d = 3 is
  /// refused once the graph is read). Throws std::invalid_argument naming the field.
  void validate() const;
};
using SolveBackend = std::variant<MaximumLikelihood, Certified>;

/// The information matrices a back end reads: all of each (positive definite) for the anisotropic solve,
/// the translation and rotation blocks for the certified solve's isotropic model.
[[nodiscard]] graph::InformationCheck information_check(const SolveBackend& backend);

/// An initial guess by name, '-' standing for '_' ("as-read"). Throws std::invalid_argument for an unknown
/// name.
[[nodiscard]] pgo::InitialGuess initial_guess_from_name(std::string name);

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
/// of eq. 2.1 that `solve` minimizes (pgo::certified_solution; the two problems differ, both costs are
/// reported).
template <class Graph>
using CertifiedSolution = pgo::CertifiedSolution<Graph>;
using CertifiedSolution2 = CertifiedSolution<graph::PoseGraph2D>;
using CertifiedSolution3 = CertifiedSolution<graph::PoseGraph3D>;
/// Throws std::invalid_argument for invalid options, a disconnected graph, landmarks or weights that are not
/// positive.
[[nodiscard]] CertifiedSolution2 solve_certified(const graph::PoseGraph2D& g, const Certified& backend = {});
[[nodiscard]] CertifiedSolution3 solve_certified(const graph::PoseGraph3D& g, const Certified& backend = {});

/// Solves the graph from the initial guess of `backend` (or `initial`, with InitialGuess::supplied), the
/// graph's gauge pose (g.gauge_pose, pose 0 unless a g2o FIX line names another) held constant at its initial
/// value (the as-read pose: the odometry chain starts from it). A solver failure is reported in
/// summary.termination, not thrown; invalid options and graphs throw std::invalid_argument.
[[nodiscard]] Solution2 solve(const graph::PoseGraph2D& g, const MaximumLikelihood& backend = {},
                              const pgo::Estimate2D* initial = nullptr);
[[nodiscard]] Solution3 solve(const graph::PoseGraph3D& g, const MaximumLikelihood& backend = {},
                              const pgo::Estimate3D* initial = nullptr);

}  // namespace keel::app
