// The accuracy metrics of §2.7.2–2.7.3 (Tables 2.1 and 2.2) and one data set of those tables with every
// method: candidates drawn from a scenario (sim), the §2.6 pipeline (keel.merge), metrics against the NO-OUT
// solve.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "merge/merge.hpp"
#include "pcm/selection.hpp"
#include "sim/two_robot.hpp"
#include "core/fields.hpp"

namespace keel::study::ch2 {

using merge::accepted_candidates;
using merge::AnchorInit;
using merge::local_maps;
using merge::LocalMaps;
using merge::LocalSolution;
using merge::LocalSolution2;
using merge::LocalSolution3;
using merge::LocalSolveOptions;
using merge::merge_maps;
using merge::MergeMethod;
using merge::MergeMethodKind;
using merge::MergeOptions;
using merge::MergeResult;
using merge::MergeResult2;
using merge::MergeResult3;
using merge::solve_local;

// ---------------------------------------------------------------------------------------------------------------
// Metrics (thesis §2.7.2 and §2.7.3).

// ‖log(R_refᵀ R)‖_F, the matrix logarithm's Frobenius norm of §2.7.2: √2 |Δθ| in 2D (Δθ wrapped to (−π, π]),
// √2 ‖Log(R_refᵀ R)‖ in 3D.
[[nodiscard]] double rotation_error(const lie::SE2& estimate, const lie::SE2& reference);
[[nodiscard]] double rotation_error(const lie::SE3& estimate, const lie::SE3& reference);

struct TrajectoryError {
  double translation_mse = 0.0;  // (1/n) Σ ‖t − t_ref‖²  (m²)
  double rotation = 0.0;         // ε_rot = (1/n) Σ ‖log(R_refᵀ R)‖_F  (§2.7.2: a mean norm, not squared)
  int count = 0;                 // n
};

// Absolute error of corresponding poses (Table 2.1: the merged map against the NO-OUT solution, both in a's
// frame). Throws std::invalid_argument on a size mismatch or empty input.
[[nodiscard]] TrajectoryError absolute_error(const std::vector<lie::SE2>& estimate,
                                             const std::vector<lie::SE2>& reference);
[[nodiscard]] TrajectoryError absolute_error(const std::vector<lie::SE3>& estimate,
                                             const std::vector<lie::SE3>& reference);
// Error of consecutive relative poses T_i⁻¹ T_{i+1} (Table 2.2 "Traj. MSE": graph correctness, independent of
// the alignment). Needs ≥ 2 poses.
[[nodiscard]] TrajectoryError relative_error(const std::vector<lie::SE2>& estimate,
                                             const std::vector<lie::SE2>& reference);
[[nodiscard]] TrajectoryError relative_error(const std::vector<lie::SE3>& estimate,
                                             const std::vector<lie::SE3>& reference);

// Inlier/outlier classification of a selection against the labels: TPR = TP/(TP+FN), FPR = FP/(FP+TN)
// (Fig. 2.4).
struct Classification {
  int tp = 0, fp = 0, fn = 0, tn = 0;
  // NaN when undefined (no inliers / no outliers among the labels): a rate of 0 would read as a result.
  double tpr() const {
    return tp + fn > 0 ? static_cast<double>(tp) / (tp + fn) : std::numeric_limits<double>::quiet_NaN();
  }
  double fpr() const {
    return fp + tn > 0 ? static_cast<double>(fp) / (fp + tn) : std::numeric_limits<double>::quiet_NaN();
  }
};
// Throws std::invalid_argument for an index out of range or repeated.
[[nodiscard]] Classification classify(const std::vector<int>& selected,
                                      const std::vector<sim::CandidateLabel>& labels);

// Every metric of Tables 2.1 and 2.2 for one merged solve.
struct MergeMetrics {
  TrajectoryError map;    // both robots (a then b) against the reference solve, in a's frame (Table 2.1)
  double residual = 0.0;  // MergeResult::residual
  double chi2 = 0.0;      // MergeResult::chi2
  double normalized_chi2 = 0.0;  // Summary::normalized_chi2
  Classification classification;
  double anchor_translation_sq = 0.0;  // ‖t̂_ab − t_ab‖² against the true anchor (Table 2.2 "Rel. Pose")
  double anchor_rotation = 0.0;        // ‖log(R_abᵀ R̂_ab)‖_F
  TrajectoryError trajectory;  // consecutive relative poses of both robots vs ground truth (Table 2.2)
};
// `selection` is what the method chose (for DCS: accepted_candidates), `labels` those of the candidate set.
[[nodiscard]] MergeMetrics evaluate_merge(const MergeResult2& result, const MergeResult2& reference,
                                          const sim::TwoRobotScenario2& scenario,
                                          const std::vector<int>& selection,
                                          const std::vector<sim::CandidateLabel>& labels);
[[nodiscard]] MergeMetrics evaluate_merge(const MergeResult3& result, const MergeResult3& reference,
                                          const sim::TwoRobotScenario3& scenario,
                                          const std::vector<int>& selection,
                                          const std::vector<sim::CandidateLabel>& labels);

// ---------------------------------------------------------------------------------------------------------------
// One data set of Tables 2.1/2.2 with every method (§2.7): generate the candidates, extract the local
// covariances, build Q, select, merge, and score against the NO-OUT solve of the same data set.

template <class G>
struct MethodOutcome {
  // The candidates the method chose, ascending (DCS: accepted_candidates), with the select_* wall time
  // (threshold + clique for PCM; 0 for NO-OUT and DCS) and, for PCM, the clique search (bound, status).
  pcm::Selection selection;
  MergeMetrics metrics;       // against the NO-OUT solve of the same data set
  double solve_time_s = 0.0;  // merged solve
  MergeResult<G> merged;      // the merged solve, only with keep_solutions
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(selection, metrics, solve_time_s, merged)
};

template <class G>
struct MergeDataset {
  sim::CandidateSet<G> candidates;
  std::vector<MethodOutcome<G>> methods;  // one per method, in the order given
  double covariance_time_s = 0.0;         // local_maps (joint marginals of the touched poses, both robots)
  double matrix_time_s = 0.0;  // consistency_matrix with Composition::joint (0 if no method uses it)
  double matrix_independent_time_s = 0.0;  // with Composition::independent (0 if no method uses it)
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(candidates, methods, covariance_time_s, matrix_time_s, matrix_independent_time_s)
};
using MergeDataset2 = MergeDataset<lie::SE2>;
using MergeDataset3 = MergeDataset<lie::SE3>;

// Data set `index`: candidates from generate_candidates(scenario, candidates, seed, index), then every
// method. The NO-OUT solve is always run (it is the reference of the metrics); a no_outliers method reports
// it. Everything is single-threaded and deterministic (Ceres with one thread), so data sets can run in
// parallel. Throws what the steps throw (std::invalid_argument for invalid methods or options).
[[nodiscard]] MergeDataset2 run_merge_dataset(const sim::TwoRobotScenario2& scenario, const LocalSolution2& a,
                                              const LocalSolution2& b,
                                              const sim::CandidateOptions& candidates,
                                              const std::vector<MergeMethod>& methods, std::uint64_t seed,
                                              std::uint64_t index, bool keep_solutions = false);
[[nodiscard]] MergeDataset3 run_merge_dataset(const sim::TwoRobotScenario3& scenario, const LocalSolution3& a,
                                              const LocalSolution3& b,
                                              const sim::CandidateOptions& candidates,
                                              const std::vector<MergeMethod>& methods, std::uint64_t seed,
                                              std::uint64_t index, bool keep_solutions = false);

}  // namespace keel::study::ch2
