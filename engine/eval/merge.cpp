// Robust multi-robot map merging (thesis §2.6) and the metrics of Tables 2.1–2.2; see merge.hpp.
#include "eval/merge.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "core/names.hpp"
#include "core/timing.hpp"
#include "cov/information.hpp"
#include "pgo/multi_robot.hpp"

namespace keel::eval {

using namespace keel::pcm;  // consistency metric and selection methods
using namespace keel::sim;  // scenarios and candidates

namespace {

using core::Clock;
using core::seconds_since;

// Throws std::invalid_argument with the formatted message, prefixed "pcm::".
template <class... A>
[[noreturn]] void fail(fmt::format_string<A...> format, A&&... args) {
  throw std::invalid_argument(fmt::format("pcm::{}", fmt::format(format, std::forward<A>(args)...)));
}

template <class G>
struct Types;
template <>
struct Types<lie::SE2> {
  using Multi = pgo::MultiRobotGraph2D;
  using InterEdge = pgo::InterRobotEdge2;
  using MultiEstimate = pgo::MultiRobotEstimate2D;
};
template <>
struct Types<lie::SE3> {
  using Multi = pgo::MultiRobotGraph3D;
  using InterEdge = pgo::InterRobotEdge3;
  using MultiEstimate = pgo::MultiRobotEstimate3D;
};

template <class G>
LocalSolution<G> solve_local_impl(const PoseGraphOf<G>& graph, const LocalSolveOptions& o) {
  o.validate();
  LocalSolution<G> out;
  out.graph = graph;
  auto t0 = Clock::now();
  auto solved = pgo::optimize(graph, o.solver);
  out.solve_time_s = seconds_since(t0);
  if (solved.summary.termination == pgo::Termination::failure)
    throw std::runtime_error(fmt::format("pcm::solve_local: the local solve of {} failed: {}",
                                         graph.source.empty() ? std::string("the graph") : graph.source,
                                         solved.summary.message));
  out.summary = solved.summary;
  out.poses = std::move(solved.estimate.poses);
  t0 = Clock::now();
  const auto info =
      cov::information_matrix(graph, out.poses);  // gauge: pose 0 fixed (cov::GaugeOptions default)
  out.covariance = std::make_shared<const cov::MarginalCovariance>(info);
  out.factorization_time_s = seconds_since(t0);
  return out;
}

template <class G>
void check_candidate(const std::vector<InterRobotMeasurement<G>>& candidates, int k, int na, int nb,
                     const char* where) {
  const auto& c = candidates[static_cast<std::size_t>(k)];
  if (c.pose_a < 0 || c.pose_a >= na)
    fail("{}: candidate {} touches pose {} of robot a, which has {} poses", where, k, c.pose_a, na);
  if (c.pose_b < 0 || c.pose_b >= nb)
    fail("{}: candidate {} touches pose {} of robot b, which has {} poses", where, k, c.pose_b, nb);
}

template <class G>
LocalMaps<G> local_maps_impl(const LocalSolution<G>& a, const LocalSolution<G>& b,
                             const std::vector<InterRobotMeasurement<G>>& candidates) {
  if (!a.covariance || !b.covariance) fail("local_maps: a local solution has no factorized covariance");
  const int na = static_cast<int>(a.poses.size()), nb = static_cast<int>(b.poses.size());
  const auto t0 = Clock::now();
  LocalMaps<G> out;
  for (int k = 0; k < static_cast<int>(candidates.size()); ++k) {
    check_candidate(candidates, k, na, nb, "local_maps");
    out.a.ids.push_back(candidates[k].pose_a);
    out.b.ids.push_back(candidates[k].pose_b);
  }
  for (auto* ids : {&out.a.ids, &out.b.ids}) {
    std::sort(ids->begin(), ids->end());
    ids->erase(std::unique(ids->begin(), ids->end()), ids->end());
  }
  out.a.poses = a.poses;
  out.b.poses = b.poses;
  if (!out.a.ids.empty()) out.a.joint = a.covariance->joint(out.a.ids);
  if (!out.b.ids.empty()) out.b.joint = b.covariance->joint(out.b.ids);
  out.time_s = seconds_since(t0);
  return out;
}

template <class G>
MergeResult<G> merge_impl(const LocalSolution<G>& a, const LocalSolution<G>& b,
                          const std::vector<InterRobotMeasurement<G>>& candidates,
                          const std::vector<int>& selected, const MergeOptions& o) {
  using T = Types<G>;
  o.validate();
  const int n = static_cast<int>(candidates.size());
  const int na = static_cast<int>(a.poses.size()), nb = static_cast<int>(b.poses.size());
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  typename T::Multi g;
  g.robots = {a.graph, b.graph};
  for (int k : selected) {
    if (k < 0 || k >= n) fail("merge_maps: selected candidate {} out of range ({} candidates)", k, n);
    if (seen[k]) fail("merge_maps: candidate {} is selected twice", k);
    seen[k] = 1;
    check_candidate(candidates, k, na, nb, "merge_maps");
    const auto& c = candidates[k];
    typename T::InterEdge e;
    e.robot_a = 0;
    e.pose_a = c.pose_a;
    e.robot_b = 1;
    e.pose_b = c.pose_b;
    e.measurement = c.z;
    e.information = information_from_left_covariance(c.z, c.covariance);
    g.inter_robot_edges.push_back(e);
  }
  typename T::MultiEstimate init;
  init.robots.resize(2);
  init.robots[0].poses = a.poses;
  init.robots[1].poses = b.poses;  // anchors left empty: set by anchor_guess below

  pgo::Options po = o.solver;
  po.initial_guess = pgo::InitialGuess::supplied;
  po.anchor_guess = o.anchor_init == AnchorInit::selected_edges ? pgo::AnchorGuess::inter_robot_edges
                                                                : pgo::AnchorGuess::as_given;

  const auto t0 = Clock::now();
  const auto res = pgo::optimize(g, po, &init);
  MergeResult<G> out;
  out.time_s = seconds_since(t0);
  if (res.summary.termination == pgo::Termination::failure)
    throw std::runtime_error(
        fmt::format("pcm::merge_maps: the merged solve failed: {}", res.summary.message));
  out.selected = selected;
  out.summary = res.summary;
  const G frame = res.estimate.anchors[0].inverse();  // a's anchor (held constant at the identity)
  out.anchor_b = frame * res.estimate.anchors[1];
  for (const auto& T_i : res.estimate.robots[0].poses)
    out.poses_a.push_back(frame * res.estimate.anchors[0] * T_i);
  for (const auto& T_k : res.estimate.robots[1].poses) out.poses_b.push_back(out.anchor_b * T_k);
  auto add = [&](const pgo::EdgeReport& e) {
    out.residual += e.weight * e.chi2;
    out.chi2 += e.chi2;
  };
  for (const auto& robot : res.edges)
    for (const auto& e : robot) add(e);
  if constexpr (std::is_same_v<G, lie::SE2>) {
    for (const auto& robot : res.landmark_edges)
      for (const auto& e : robot) add(e);
  }
  for (const auto& e : res.inter_robot_edges) add(e);
  out.inter_robot = res.inter_robot_edges;
  return out;
}

template <class G>
std::vector<int> accepted_impl(const MergeResult<G>& r, double min_scale) {
  if (r.inter_robot.size() != r.selected.size())
    fail("accepted_candidates: the result has {} edge reports for {} selected candidates",
         r.inter_robot.size(), r.selected.size());
  std::vector<int> out;
  for (std::size_t k = 0; k < r.selected.size(); ++k)
    if (r.inter_robot[k].scale >= min_scale) out.push_back(r.selected[k]);
  std::sort(out.begin(), out.end());
  return out;
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
  for (const auto& m : methods) {
    if (m.kind == MergeMethodKind::no_outliers || m.kind == MergeMethodKind::dcs) continue;
    (m.composition == Composition::joint ? need_joint : need_independent) = true;
  }
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
  for (const auto& m : methods) {
    MethodOutcome<G> o;
    const ConsistencyMatrix& Q = m.composition == Composition::joint ? Q_joint : Q_independent;
    MergeResult<G> merged;
    switch (m.kind) {
      case MergeMethodKind::no_outliers:
        o.selection.selected = inliers;
        merged = reference;
        break;
      case MergeMethodKind::dcs:
        merged = merge_maps(a, b, cands, out.candidates.all(), MergeOptions::dcs(m.dcs_phi));
        o.selection.selected = accepted_candidates(merged, m.dcs_accept_scale);
        break;
      default: {
        if (m.kind == MergeMethodKind::scgp) {
          o.selection = select_scgp(Q, m.scgp);
        } else {
          const double gamma = consistency_threshold(m.p, Q.dof);
          if (m.kind == MergeMethodKind::ransac)
            o.selection = select_ransac(Q, gamma);
          else if (m.kind == MergeMethodKind::densest)
            o.selection = select_densest(Q, gamma, m.densest);
          else
            o.selection = select_pcm(
                Q, gamma,
                m.kind == MergeMethodKind::pcm_exact ? CliqueAlgorithm::exact : CliqueAlgorithm::heuristic);
        }
        std::sort(o.selection.selected.begin(), o.selection.selected.end());
        merged = merge_maps(a, b, cands, o.selection.selected);
      }
    }
    o.solve_time_s = merged.time_s;
    o.metrics = evaluate_impl(merged, reference, s, o.selection.selected, labels);
    if (keep) o.merged = std::move(merged);
    out.methods.push_back(std::move(o));
  }
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
pgo::Options LocalSolveOptions::default_solver() {
  pgo::Options o;
  o.initial_guess = pgo::InitialGuess::odometry;
  return o;
}

void LocalSolveOptions::validate() const {
  if (solver.initial_guess != pgo::InitialGuess::as_read &&
      solver.initial_guess != pgo::InitialGuess::odometry)
    fail("LocalSolveOptions: solver.initial_guess must be as_read or odometry (got {})",
         pgo::to_string(solver.initial_guess));
  solver.validate();
}

LocalSolution2 solve_local(const graph::PoseGraph2D& graph, const LocalSolveOptions& options) {
  return solve_local_impl<lie::SE2>(graph, options);
}
LocalSolution3 solve_local(const graph::PoseGraph3D& graph, const LocalSolveOptions& options) {
  return solve_local_impl<lie::SE3>(graph, options);
}

LocalMaps2 local_maps(const LocalSolution2& a, const LocalSolution2& b,
                      const std::vector<InterRobotMeasurement2>& candidates) {
  return local_maps_impl(a, b, candidates);
}
LocalMaps3 local_maps(const LocalSolution3& a, const LocalSolution3& b,
                      const std::vector<InterRobotMeasurement3>& candidates) {
  return local_maps_impl(a, b, candidates);
}

namespace {
constexpr core::NameTable<AnchorInit, 2> kAnchorInitNames{
    "eval::AnchorInit",
    {{{AnchorInit::selected_edges, "selected_edges"}, {AnchorInit::identity, "identity"}}}};
}  // namespace

std::string_view to_string(AnchorInit v) { return kAnchorInitNames.name(v); }
AnchorInit anchor_init_from_string(std::string_view s) { return kAnchorInitNames.parse(s); }

MergeOptions MergeOptions::dcs(double dcs_phi) {
  MergeOptions o;
  o.solver.robust_kernel = pgo::RobustKernel::dcs;
  o.solver.robust_parameter = dcs_phi;
  o.solver.robust_scope = pgo::RobustScope::loop_closures;
  o.anchor_init = AnchorInit::identity;
  return o;
}

void MergeOptions::validate() const { solver.validate(); }

MergeResult2 merge_maps(const LocalSolution2& a, const LocalSolution2& b,
                        const std::vector<InterRobotMeasurement2>& candidates,
                        const std::vector<int>& selected, const MergeOptions& options) {
  return merge_impl(a, b, candidates, selected, options);
}
MergeResult3 merge_maps(const LocalSolution3& a, const LocalSolution3& b,
                        const std::vector<InterRobotMeasurement3>& candidates,
                        const std::vector<int>& selected, const MergeOptions& options) {
  return merge_impl(a, b, candidates, selected, options);
}

std::vector<int> accepted_candidates(const MergeResult2& result, double min_scale) {
  return accepted_impl(result, min_scale);
}
std::vector<int> accepted_candidates(const MergeResult3& result, double min_scale) {
  return accepted_impl(result, min_scale);
}

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

namespace {
constexpr core::NameTable<MergeMethodKind, 7> kMergeMethodKindNames{
    "eval::MergeMethodKind",
    {{{MergeMethodKind::no_outliers, "no_outliers"},
      {MergeMethodKind::dcs, "dcs"},
      {MergeMethodKind::scgp, "scgp"},
      {MergeMethodKind::ransac, "ransac"},
      {MergeMethodKind::pcm_exact, "pcm_exact"},
      {MergeMethodKind::pcm_heuristic, "pcm_heuristic"},
      {MergeMethodKind::densest, "densest"}}}};
}  // namespace

std::string_view to_string(MergeMethodKind v) { return kMergeMethodKindNames.name(v); }
MergeMethodKind merge_method_kind_from_string(std::string_view s) { return kMergeMethodKindNames.parse(s); }

MergeMethod MergeMethod::make(std::string name, MergeMethodKind kind, double p,
                              pcm::Composition composition) {
  MergeMethod m;
  m.name = std::move(name);
  m.kind = kind;
  m.p = p;
  m.composition = composition;
  return m;
}

void MergeMethod::validate() const {
  if (name.empty()) fail("MergeMethod: name must not be empty");
  if ((kind == MergeMethodKind::ransac || kind == MergeMethodKind::pcm_exact ||
       kind == MergeMethodKind::pcm_heuristic || kind == MergeMethodKind::densest) &&
      !(p > 0.0 && p < 1.0))
    fail("MergeMethod '{}': p must be in (0, 1) (got {:g})", name, p);
  if (kind == MergeMethodKind::scgp) scgp.validate();
  if (kind == MergeMethodKind::densest) densest.validate();
  if (kind == MergeMethodKind::dcs) {
    if (!(std::isfinite(dcs_phi) && dcs_phi > 0.0))
      fail("MergeMethod '{}': dcs_phi must be finite and > 0 (got {:g})", name, dcs_phi);
    if (!(dcs_accept_scale > 0.0 && dcs_accept_scale <= 1.0))
      fail("MergeMethod '{}': dcs_accept_scale must be in (0, 1] (got {:g})", name, dcs_accept_scale);
  }
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

}  // namespace keel::eval
