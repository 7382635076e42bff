// keel::app — a robust back end for one robot's graph (the single-robot case of Kimera-RPGO): its odometry
// (every edge between consecutive poses, i → i + 1) is trusted and every other edge is a candidate loop
// closure. The candidates' pairwise consistency is measured in the odometry map with the joint marginals
// (thesis eq. 2.4; the one-map form of pcm::consistency_matrix, whose two relative poses per loop are
// correlated), the largest consistent set is selected (eq. 2.5), and the odometry with the selected closures
// is solved by the certified solver (app::solve_certified), whose certificate or proven gap comes with the
// answer.
#pragma once

#include <vector>

#include "app/progress.hpp"
#include "app/solve.hpp"
#include "graph/pose_graph.hpp"
#include "merge/merge.hpp"
#include "pcm/clique.hpp"
#include "pcm/consistency.hpp"
#include "pcm/selection.hpp"
#include "pgo/certified.hpp"

namespace keel::app {

struct RobustOptions {
  double p =
      0.11;  // γ = F⁻¹_χ²(dof)(1 − p), the consistency threshold (thesis §2.7: PCM-Exact-11 %), in (0, 1)
  pcm::Composition composition = pcm::Composition::joint;  // the relative poses from the joint marginals
  pcm::CliqueAlgorithm algorithm = pcm::CliqueAlgorithm::exact;
  double time_limit_s = 0.0;  // exact clique search limit (s, >= 0); 0: none (the result says if it stopped)
  merge::LocalSolveOptions local;  // the odometry map's solve (odometry initial guess, pose 0 fixed)
  pgo::CertifiedOptions solve;     // the certified solve of the odometry and the selected closures
  unsigned threads = 1;            // consistency matrix; 0 = keel::core::default_threads()
  // Throws std::invalid_argument naming the field (including the nested options' own checks).
  void validate() const;
};

template <class G>
struct RobustRun {
  RobustOptions options;             // what the run was asked
  graph::PoseGraphOf<G> odometry;    // the trusted chain: the input's poses and its edges i → i + 1
  std::vector<int> candidate_edges;  // candidate k is the input's edge candidate_edges[k]
  std::vector<pcm::InterRobotMeasurement<G>> candidates;  // pose_a = i, pose_b = j of that edge
  pcm::ConsistencyMatrix q;                               // n = 0 when the graph has no loop closure
  double gamma = 0.0;
  pcm::Selection selection;        // selection.search holds the clique search (status, bound)
  graph::PoseGraphOf<G> selected;  // the odometry and the selected closures, as the input gave them
  CertifiedSolution<graph::PoseGraphOf<G>>
      solved;  // `selected` solved with its certificate (app::solve_certified)
  double odometry_time_s = 0.0, marginals_time_s = 0.0, consistency_time_s = 0.0;
};
using RobustRun2 = RobustRun<lie::SE2>;
using RobustRun3 = RobustRun<lie::SE3>;

/// The pipeline above. Throws std::invalid_argument for invalid options, a graph whose odometry does not
/// chain every pose (pose k without an edge from k − 1, naming k), a loop closure whose information is not
/// positive definite (naming its line), or a candidate set whose joint marginal would not fit in memory
/// (dense, (dof · poses touched)² numbers: over 2 GiB); std::runtime_error when a solve fails.
[[nodiscard]] RobustRun2 robust(const graph::PoseGraph2D& graph, const RobustOptions& options = {},
                                const Progress& progress = {});
[[nodiscard]] RobustRun3 robust(const graph::PoseGraph3D& graph, const RobustOptions& options = {},
                                const Progress& progress = {});

}  // namespace keel::app
