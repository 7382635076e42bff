// The metrics of Tables 2.1–2.2 and one data set with every method; see merge.hpp.
#include "study/ch2/merge_eval.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/names.hpp"
#include "core/timing.hpp"

namespace keel::study::ch2 {

using namespace keel::pcm;  // consistency metric and selection methods
using namespace keel::sim;  // scenarios and candidates
using graph::PoseGraphOf;

namespace {

using core::Clock;
using core::seconds_since;

// Throws std::invalid_argument with the formatted message, prefixed "pcm::".
template <class... A>
[[noreturn]] void fail(fmt::format_string<A...> format, A&&... args) {
  throw std::invalid_argument(fmt::format("pcm::{}", fmt::format(format, std::forward<A>(args)...)));
}

template <class G>
TrajectoryError absolute_impl(const std::vector<G>& est, const std::vector<G>& ref) {
  if (est.size() != ref.size() || est.empty())
    fail("absolute_error: the estimate has {} poses and the reference {} (need equal, non-zero sizes)",
         est.size(), ref.size());
  TrajectoryError e;
  for (std::size_t i = 0; i < est.size(); ++i) {
    e.translation_mse += (est[i].translation() - ref[i].translation()).squaredNorm();
    e.rotation += rotation_error(est[i], ref[i]);
  }
  e.count = static_cast<int>(est.size());
  e.translation_mse /= e.count;
  e.rotation /= e.count;
  return e;
}

template <class G>
TrajectoryError relative_impl(const std::vector<G>& est, const std::vector<G>& ref) {
  if (est.size() != ref.size() || est.size() < 2)
    fail("relative_error: the estimate has {} poses and the reference {} (need equal sizes, at least 2)",
         est.size(), ref.size());
  std::vector<G> de, dr;
  for (std::size_t i = 0; i + 1 < est.size(); ++i) {
    de.push_back(est[i].inverse() * est[i + 1]);
    dr.push_back(ref[i].inverse() * ref[i + 1]);
  }
  return absolute_impl(de, dr);
}

// Count-weighted mean of two errors (the poses of both robots taken together).
TrajectoryError combine(const TrajectoryError& x, const TrajectoryError& y) {
  TrajectoryError e;
  e.count = x.count + y.count;
  if (e.count == 0) return e;
  e.translation_mse = (x.translation_mse * x.count + y.translation_mse * y.count) / e.count;
  e.rotation = (x.rotation * x.count + y.rotation * y.count) / e.count;
  return e;
}

template <class G>
MergeMetrics evaluate_impl(const MergeResult<G>& r, const MergeResult<G>& ref, const TwoRobotScenario<G>& s,
                           const std::vector<int>& selection, const std::vector<CandidateLabel>& labels) {
  if (r.poses_a.size() != s.truth_a.size() || r.poses_b.size() != s.truth_b.size())
    fail("evaluate_merge: the merged result has {} + {} poses, the scenario {} + {}", r.poses_a.size(),
         r.poses_b.size(), s.truth_a.size(), s.truth_b.size());
  MergeMetrics m;
  m.map = combine(absolute_impl(r.poses_a, ref.poses_a), absolute_impl(r.poses_b, ref.poses_b));
  m.residual = r.residual;
  m.chi2 = r.chi2;
  m.normalized_chi2 = r.summary.normalized_chi2;
  m.classification = classify(selection, labels);
  m.anchor_translation_sq = (r.anchor_b.translation() - s.true_anchor.translation()).squaredNorm();
  m.anchor_rotation = rotation_error(r.anchor_b, s.true_anchor);
  // Consecutive relative poses are frame-free: b's merged poses (a's frame) against b's local ground truth.
  m.trajectory = combine(relative_impl(r.poses_a, s.truth_a), relative_impl(r.poses_b, s.truth_b));
  return m;
}

template <class G>
MergeDataset<G> run_dataset_impl(const TwoRobotScenario<G>& s, const LocalSolution<G>& a,
                                 const LocalSolution<G>& b, const CandidateOptions& copt,
                                 const std::vector<MergeMethod>& methods, std::uint64_t seed,
                                 std::uint64_t index, bool keep) {
  for (const auto& m : methods) m.validate();
  MergeDataset<G> out;
  out.candidates = generate_candidates(s, copt, seed, index);
  const auto& cands = out.candidates.candidates;
  const auto& labels = out.candidates.labels;

  bool need_joint = false, need_independent = false;
  for (const auto& m : methods)
    if (const auto c = m.composition()) (*c == Composition::joint ? need_joint : need_independent) = true;
  const auto maps = local_maps(a, b, cands);
  out.covariance_time_s = maps.time_s;
  ConsistencyMatrix Q_joint, Q_independent;
  ConsistencyOptions co;
  co.threads = 1;
  if (need_joint) {
    co.composition = Composition::joint;
    const auto t0 = Clock::now();
    Q_joint = consistency_matrix(maps.a, maps.b, cands, co);
    out.matrix_time_s = seconds_since(t0);
  }
  if (need_independent) {
    co.composition = Composition::independent;
    const auto t0 = Clock::now();
    Q_independent = consistency_matrix(maps.a, maps.b, cands, co);
    out.matrix_independent_time_s = seconds_since(t0);
  }

  const auto inliers = out.candidates.inliers();
  const auto reference = merge_maps(a, b, cands, inliers);
  // The merged solves by selection. Several methods (and one method at several thresholds) often select the
  // same candidates, and merge_maps of one selection with the default options is one solve (one Ceres thread:
  // the same bits every time), so it runs once. A reused solve keeps its own time_s: each method's solve time
  // is what it would be alone.
  std::map<std::vector<int>, const MergeResult<G>*> solved{{inliers, &reference}};
  std::deque<MergeResult<G>> solves;
  const auto solve_selection = [&](const std::vector<int>& selected) -> const MergeResult<G>& {
    if (const auto it = solved.find(selected); it != solved.end()) return *it->second;
    const MergeResult<G>& r = solves.emplace_back(merge_maps(a, b, cands, selected));
    solved.emplace(selected, &r);
    return r;
  };
  for (const auto& m : methods) {
    MethodOutcome<G> o;
    const ConsistencyMatrix& Q = m.composition() == Composition::joint ? Q_joint : Q_independent;
    MergeResult<G> merged;
    switch (m.kind()) {
      case MergeMethodKind::no_outliers:
        o.selection.selected = inliers;
        merged = reference;
        break;
      case MergeMethodKind::dcs: {
        const auto& dcs = std::get<merge::Dcs>(m.options);
        merged = merge_maps(a, b, cands, out.candidates.all(), MergeOptions::dcs(dcs.phi));
        o.selection.selected = accepted_candidates(merged, dcs.accept_scale);
        break;
      }
      default:
        o.selection = merge::select(m, Q);
        merged = solve_selection(o.selection.selected);
    }
    o.solve_time_s = merged.time_s;
    o.metrics = evaluate_impl(merged, reference, s, o.selection.selected, labels);
    if (keep) o.merged = std::move(merged);
    out.methods.push_back(std::move(o));
  }
  return out;
}

}  // namespace

double rotation_error(const lie::SE2& estimate, const lie::SE2& reference) {
  const double d = (reference.so2().inverse() * estimate.so2()).angle();  // wrapped to (−π, π]
  return std::sqrt(2.0) * std::abs(d);
}
double rotation_error(const lie::SE3& estimate, const lie::SE3& reference) {
  return std::sqrt(2.0) * (reference.so3().inverse() * estimate.so3()).log().norm();
}

TrajectoryError absolute_error(const std::vector<lie::SE2>& estimate,
                               const std::vector<lie::SE2>& reference) {
  return absolute_impl(estimate, reference);
}
TrajectoryError absolute_error(const std::vector<lie::SE3>& estimate,
                               const std::vector<lie::SE3>& reference) {
  return absolute_impl(estimate, reference);
}
TrajectoryError relative_error(const std::vector<lie::SE2>& estimate,
                               const std::vector<lie::SE2>& reference) {
  return relative_impl(estimate, reference);
}
TrajectoryError relative_error(const std::vector<lie::SE3>& estimate,
                               const std::vector<lie::SE3>& reference) {
  return relative_impl(estimate, reference);
}

Classification classify(const std::vector<int>& selected, const std::vector<CandidateLabel>& labels) {
  const int n = static_cast<int>(labels.size());
  std::vector<char> chosen(static_cast<std::size_t>(n), 0);
  for (int k : selected) {
    if (k < 0 || k >= n) fail("classify: selected index {} out of range ({} labels)", k, n);
    if (chosen[k]) fail("classify: index {} is selected twice", k);
    chosen[k] = 1;
  }
  Classification c;
  for (int k = 0; k < n; ++k) {
    const bool in = labels[k].is_inlier();
    if (chosen[k])
      (in ? c.tp : c.fp)++;
    else
      (in ? c.fn : c.tn)++;
  }
  return c;
}

MergeMetrics evaluate_merge(const MergeResult2& result, const MergeResult2& reference,
                            const TwoRobotScenario2& scenario, const std::vector<int>& selection,
                            const std::vector<CandidateLabel>& labels) {
  return evaluate_impl(result, reference, scenario, selection, labels);
}
MergeMetrics evaluate_merge(const MergeResult3& result, const MergeResult3& reference,
                            const TwoRobotScenario3& scenario, const std::vector<int>& selection,
                            const std::vector<CandidateLabel>& labels) {
  return evaluate_impl(result, reference, scenario, selection, labels);
}

MergeDataset2 run_merge_dataset(const TwoRobotScenario2& scenario, const LocalSolution2& a,
                                const LocalSolution2& b, const CandidateOptions& candidates,
                                const std::vector<MergeMethod>& methods, std::uint64_t seed,
                                std::uint64_t index, bool keep_solutions) {
  return run_dataset_impl(scenario, a, b, candidates, methods, seed, index, keep_solutions);
}
MergeDataset3 run_merge_dataset(const TwoRobotScenario3& scenario, const LocalSolution3& a,
                                const LocalSolution3& b, const CandidateOptions& candidates,
                                const std::vector<MergeMethod>& methods, std::uint64_t seed,
                                std::uint64_t index, bool keep_solutions) {
  return run_dataset_impl(scenario, a, b, candidates, methods, seed, index, keep_solutions);
}

}  // namespace keel::study::ch2
