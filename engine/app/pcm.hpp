// keel::app — the two-robot map merging of thesis §2.6 on a user's files, shared by `keel pcm` and the Python
// module: the local solves and joint marginals (steps i–ii), the consistency matrix Q of eq. 2.4 (step ii),
// the maximum clique of eq. 2.5 (step iii) and, optionally, the merged solve with the selected candidates
// (iv).
#pragma once

#include <optional>
#include <vector>

#include "app/progress.hpp"
#include "graph/pose_graph.hpp"
#include "merge/merge.hpp"
#include "pcm/clique.hpp"
#include "pcm/consistency.hpp"
#include "pcm/selection.hpp"

namespace keel::app {

struct PcmOptions {
  double p =
      0.11;  // γ = F⁻¹_χ²(dof)(1 − p), the consistency threshold (thesis §2.7: PCM-Exact-11 %), in (0, 1)
  pcm::Composition composition = pcm::Composition::joint;  // x̂_ij from the joint marginals (eq. 2.4)
  pcm::CliqueAlgorithm algorithm = pcm::CliqueAlgorithm::exact;
  double time_limit_s = 0.0;          // exact clique search limit (s, >= 0); 0: none (the result says if it
                                      // stopped)
  merge::LocalSolveOptions local;     // the two local solves (odometry initial guess, pose 0 fixed)
  bool merge = false;                 // also solve the merged two-robot graph with the selected candidates
  merge::MergeOptions merge_options;  // of that solve
  unsigned threads = 1;               // consistency matrix; 0 = keel::core::default_threads()
  // Throws std::invalid_argument naming the field (including the nested options' own checks).
  void validate() const;
};

/// Steps i–ii: the solved local maps, the candidates and their consistency matrix.
template <class G>
struct Consistency {
  merge::LocalSolution<G> a, b;                           // the solved local maps
  std::vector<pcm::InterRobotMeasurement<G>> candidates;  // with left covariances (consistency.hpp)
  pcm::ConsistencyMatrix q;
  double marginals_time_s = 0.0, consistency_time_s = 0.0;
};

/// Steps i–iv: Consistency, then the threshold, the selection and (PcmOptions::merge) the merged solve.
template <class G>
struct PcmRun : Consistency<G> {
  double gamma = 0.0;
  pcm::Selection selection;  // selection.search holds the clique search (status, bound)
  std::optional<merge::MergeResult<G>> merged;
};
using PcmRun2 = PcmRun<lie::SE2>;
using PcmRun3 = PcmRun<lie::SE3>;

/// The candidate edges as keel.pcm needs them: each id checked against its robot (the message names the
/// candidate index and source line), the left covariance from the residual information
/// (pcm::left_covariance_from_information). Throws std::invalid_argument for an empty list, an id out of
/// range or an information that is not positive definite.
[[nodiscard]] std::vector<pcm::InterRobotMeasurement2> inter_robot_candidates(
    const graph::PoseGraph2D& a, const graph::PoseGraph2D& b, const std::vector<graph::Edge2>& edges);
[[nodiscard]] std::vector<pcm::InterRobotMeasurement3> inter_robot_candidates(
    const graph::PoseGraph3D& a, const graph::PoseGraph3D& b, const std::vector<graph::Edge3>& edges);

/// §2.6 steps i–ii on two robots' graphs and a candidate list whose edges measure z ≈ (T^a_i)⁻¹ T^b_j with
/// residual information Ω (graph::read_g2o_edges_*); of the options only local, composition and threads are
/// used. Throws like pcm(); std::runtime_error when a solve fails or a local map is not connected.
[[nodiscard]] Consistency<lie::SE2> consistency(const graph::PoseGraph2D& a, const graph::PoseGraph2D& b,
                                                const std::vector<graph::Edge2>& candidates,
                                                const PcmOptions& options = {},
                                                const Progress& progress = {});
[[nodiscard]] Consistency<lie::SE3> consistency(const graph::PoseGraph3D& a, const graph::PoseGraph3D& b,
                                                const std::vector<graph::Edge3>& candidates,
                                                const PcmOptions& options = {},
                                                const Progress& progress = {});

/// §2.6 steps i–iii (and iv with options.merge). Throws std::invalid_argument for invalid options, a
/// candidate naming a pose its robot does not have (candidate index and source line), or an information that
/// is not positive definite; std::runtime_error when a solve fails or a local map is not connected.
[[nodiscard]] PcmRun2 pcm(const graph::PoseGraph2D& a, const graph::PoseGraph2D& b,
                          const std::vector<graph::Edge2>& candidates, const PcmOptions& options = {},
                          const Progress& progress = {});
[[nodiscard]] PcmRun3 pcm(const graph::PoseGraph3D& a, const graph::PoseGraph3D& b,
                          const std::vector<graph::Edge3>& candidates, const PcmOptions& options = {},
                          const Progress& progress = {});

/// The merged map as one graph: a's poses keep their ids 0 … n_a − 1, b's become n_a … n_a + n_b − 1, both in
/// a's frame; the edges of both local graphs, then the selected candidates. Throws std::invalid_argument when
/// the run has no merged solve.
[[nodiscard]] graph::PoseGraph2D merged_graph(const PcmRun2& run);
[[nodiscard]] graph::PoseGraph3D merged_graph(const PcmRun3& run);

/// A selection scored against ground-truth labels (true = inlier).
struct SelectionScore {
  int true_positives = 0, false_positives = 0;
  double tpr = 1.0;  // true positives / inliers (1 without inliers)
  double fpr = 0.0;  // false positives / outliers (0 without outliers)
};
/// Throws std::invalid_argument when a selected index has no label.
[[nodiscard]] SelectionScore score_selection(const std::vector<int>& selected,
                                             const std::vector<bool>& inlier);

}  // namespace keel::app
