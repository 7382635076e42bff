// The chapter-2 studies behind the experiments (§2.7.2–2.7.3): the pieces every two-robot experiment shares —
// the measurement regime of a scenario, the local maps solved once, the data sets run in parallel, per-method
// summaries over the data sets — and the calibration of Q on a scenario's pool of true loop closures. The
// studies of tables.hpp read their options (study/ch2/config.hpp), call these, and record what comes back.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/statistics.hpp"
#include "study/ch2/merge_eval.hpp"
#include "repro/run.hpp"
#include "sim/two_robot.hpp"

namespace keel::core {
class Progress;
}  // namespace keel::core
namespace keel::repro {
class Results;
}  // namespace keel::repro

namespace keel::study::ch2 {

// A method of a study with its display label (figures and tables).
struct StudyMethod {
  MergeMethod method;
  std::string label;
};
[[nodiscard]] std::vector<MergeMethod> methods_of(const std::vector<StudyMethod>& methods);
// Index of the method named `name`; throws std::invalid_argument naming `who` and the unknown method.
[[nodiscard]] std::size_t method_index(const std::vector<StudyMethod>& methods, std::string_view name,
                                       std::string_view who);

// Which measurements a scenario carries: the dataset's own, or every measurement (both local graphs, the pool
// and the aliased groups' noise) redrawn about the ground truth with the residual noise scaled by
// `noise_scale` (sim::resample_measurements, keeping the declared information).
struct MeasurementRegime {
  std::string name;   // metric prefix
  std::string label;  // for figures
  bool resampled = false;
  double noise_scale = 1.0;  // s (> 0); 1 for the dataset's own measurements
  std::uint64_t resample_seed =
      0;                  // streams (seed, 0/1/2) of the resampling; keep apart from candidate streams
  void validate() const;  // throws std::invalid_argument naming the field
};
// The regime's scenario (base resampled when asked) and its candidate options (aliased groups drawn with the
// regime's noise scale).
template <class G>
[[nodiscard]] sim::TwoRobotScenario<G> apply_regime(const sim::TwoRobotScenario<G>& base,
                                                    const MeasurementRegime& regime);
[[nodiscard]] sim::CandidateOptions apply_regime(const sim::CandidateOptions& candidates,
                                                 const MeasurementRegime& regime);

// §2.6 step i for both robots of a scenario: each local map solved and its information factorized once.
template <class G>
struct LocalPair {
  LocalSolution<G> a, b;
};
template <class G>
[[nodiscard]] LocalPair<G> solve_local_pair(const sim::TwoRobotScenario<G>& scenario,
                                            const LocalSolveOptions& options = {});
// Records what Tables 2.1/2.2 report about the local maps: timings local.{a,b}.{solve,factorization}; metrics
// scenario.pool, scenario.robot_{a,b}.poses, scenario.robot_{a,b}.loop_closures, local.{a,b}.normalized_chi2.
template <class G>
void record_local_pair(repro::Results& results, const sim::TwoRobotScenario<G>& scenario,
                       const LocalPair<G>& local);

// Data sets 0 … count−1 of a scenario with every method (run_merge_dataset), one sharded trial loop on the
// context's threads. Data set i draws its candidates from the context's stream i, so the result does not
// depend on the thread count; `keep` (if < count) keeps that data set's merged solutions for figures.
// `progress` (may be null) advances once per data set.
template <class G>
[[nodiscard]] std::vector<MergeDataset<G>> run_merge_datasets(
    const sim::TwoRobotScenario<G>& scenario, const LocalPair<G>& local,
    const sim::CandidateOptions& candidates, const std::vector<MergeMethod>& methods,
    const repro::RunContext& context, std::size_t count,
    std::size_t keep = std::numeric_limits<std::size_t>::max(), core::Progress* progress = nullptr);

// Data set `index` with each of several method lists, in parallel: sweep[k] = run_merge_dataset(…,
// method_sets[k], streams.seed(), streams.index(index)) — the same candidates for every list (a sweep of a
// method's parameter on one data set).
template <class G>
[[nodiscard]] std::vector<MergeDataset<G>> run_method_sweep(
    const sim::TwoRobotScenario<G>& scenario, const LocalPair<G>& local,
    const sim::CandidateOptions& candidates, const std::vector<std::vector<MergeMethod>>& method_sets,
    const repro::RunContext& context, std::size_t index, core::Progress* progress = nullptr);

// Method k over the data sets (Tables 2.1/2.2): per-data-set columns, classifications pooled.
struct MethodSummary {
  // Per data set, by name: trans_mse, rot_mse (merged map vs ground truth), rel_pose_trans_mse, rel_pose_rot
  // (the anchor), traj_trans_mse, traj_rot (trajectory), residual, chi2 (normalized χ²), selected, tp, fp,
  // raw_size and violations (the densest-subgraph selector's rounding before its repair; 0 for the others),
  // selection_time_s, solve_time_s.
  std::map<std::string, std::vector<double>, std::less<>> columns;
  Classification pooled;  // TP/FP/FN/TN summed over the data sets
  double accepted_aliased = 0.0,
         accepted_random = 0.0;   // accepted outliers by kind, totals over the data sets
  double empty_selections = 0.0;  // data sets whose selection is empty (b's anchor is then unconstrained)
  // The column `name`; throws std::invalid_argument naming the valid columns.
  [[nodiscard]] const std::vector<double>& column(std::string_view name) const;
  [[nodiscard]] core::MeanStd stats(std::string_view name) const { return core::mean_std(column(name)); }
  [[nodiscard]] double mean(std::string_view name) const { return stats(name).mean; }
};
template <class G>
[[nodiscard]] MethodSummary summarize_method(const std::vector<MergeDataset<G>>& runs, std::size_t k);

// Timings dataset.{cov_extraction,matrix,matrix_independent}.{mean,max} over the data sets (never diffed).
template <class G>
void record_dataset_timings(repro::Results& results, const std::vector<MergeDataset<G>>& runs);

// The matrices Q (eq. 2.4, joint composition) that the PCM methods of run_merge_datasets select from, for
// data sets 0 … count−1: data set i draws its candidates from streams (seed, index_base + i) as
// run_merge_datasets does with a context's streams, so for the experiment's seed they are that experiment's
// data sets. Serial (one data set after another); bench_clique's family of real consistency graphs is built
// from it.
template <class G>
[[nodiscard]] std::vector<pcm::ConsistencyMatrix> dataset_consistency_matrices(
    const sim::TwoRobotScenario<G>& scenario, const LocalPair<G>& local,
    const sim::CandidateOptions& candidates, std::uint64_t seed, std::size_t count,
    std::uint64_t index_base = 0);

// Data sets on which methods `i` and `j` selected the same candidates, and on which `i`'s clique search was
// proven optimal.
template <class G>
[[nodiscard]] std::size_t same_selections(const std::vector<MergeDataset<G>>& runs, std::size_t i,
                                          std::size_t j);
template <class G>
[[nodiscard]] std::size_t proven_optimal(const std::vector<MergeDataset<G>>& runs, std::size_t i);

// Mean over a scenario's pool of rᵀ Ω r / dof, r = graph::edge_residual of each pool edge at its true value
// X = (T^a_i)⁻¹ T_ab T^b_k: 1 for measurements with the stated noise, s² for measurements redrawn at scale s.
template <class G>
[[nodiscard]] double pool_chi2_at_truth(const sim::TwoRobotScenario<G>& scenario);

// The calibration of Q on a scenario's whole pool (every ordered pair of true loop closures): the fraction of
// ordered pairs with q > γ for each γ, and the mean q. A calibrated metric fails γ(p) at rate p and has mean
// q = dof.
struct PoolCalibration {
  std::vector<double> fail;  // one per γ
  double q_mean = 0.0;
};
[[nodiscard]] PoolCalibration pool_calibration(const LocalPair<lie::SE2>& local,
                                               const sim::TwoRobotScenario2& scenario,
                                               pcm::Composition composition,
                                               const std::vector<double>& gammas);

}  // namespace keel::study::ch2
