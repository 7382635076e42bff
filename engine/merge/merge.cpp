// Robust multi-robot map merging (thesis §2.6) and the outlier-rejection methods of §2.7; see merge.hpp.
#include "merge/merge.hpp"

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
#include "pgo/types.hpp"

namespace keel::merge {

using namespace keel::pcm;  // consistency metric and selection methods
using graph::PoseGraphOf;

namespace {

using core::Clock;
using core::seconds_since;

// Throws std::invalid_argument with the formatted message, prefixed "merge::".
template <class... A>
[[noreturn]] void fail(fmt::format_string<A...> format, A&&... args) {
  throw std::invalid_argument(fmt::format("merge::{}", fmt::format(format, std::forward<A>(args)...)));
}

template <class G>
LocalSolution<G> solve_local_impl(const PoseGraphOf<G>& graph, const LocalSolveOptions& o) {
  o.validate();
  LocalSolution<G> out;
  out.graph = graph;
  auto t0 = Clock::now();
  auto solved = pgo::optimize(graph, o.solver);
  out.solve_time_s = seconds_since(t0);
  if (solved.summary.termination == pgo::Termination::failure)
    throw std::runtime_error(fmt::format("merge::solve_local: the local solve of {} failed: {}",
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
  using T = pgo::Types<G>;
  o.validate();
  const int n = static_cast<int>(candidates.size());
  const int na = static_cast<int>(a.poses.size()), nb = static_cast<int>(b.poses.size());
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  typename T::MultiGraph g;
  g.robots = {a.graph, b.graph};
  for (int k : selected) {
    if (k < 0 || k >= n) fail("merge_maps: selected candidate {} out of range ({} candidates)", k, n);
    if (seen[k]) fail("merge_maps: candidate {} is selected twice", k);
    seen[k] = 1;
    check_candidate(candidates, k, na, nb, "merge_maps");
    const auto& c = candidates[k];
    typename T::Inter e;
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
        fmt::format("merge::merge_maps: the merged solve failed: {}", res.summary.message));
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
    "merge::AnchorInit",
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

namespace {
constexpr core::NameTable<MergeMethodKind, 7> kMergeMethodKindNames{
    "merge::MergeMethodKind",
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

namespace {
template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;
}  // namespace

MergeMethodKind MergeMethod::kind() const {
  return std::visit(Overloaded{[](const NoOutliers&) { return MergeMethodKind::no_outliers; },
                               [](const Dcs&) { return MergeMethodKind::dcs; },
                               [](const Scgp&) { return MergeMethodKind::scgp; },
                               [](const Ransac&) { return MergeMethodKind::ransac; },
                               [](const Pcm& m) {
                                 return m.algorithm == CliqueAlgorithm::heuristic
                                            ? MergeMethodKind::pcm_heuristic
                                            : MergeMethodKind::pcm_exact;
                               },
                               [](const Densest&) { return MergeMethodKind::densest; }},
                    options);
}

std::optional<double> MergeMethod::p() const {
  if (const auto* m = std::get_if<Ransac>(&options)) return m->p;
  if (const auto* m = std::get_if<Pcm>(&options)) return m->p;
  if (const auto* m = std::get_if<Densest>(&options)) return m->p;
  return std::nullopt;
}

std::optional<Composition> MergeMethod::composition() const {
  if (const auto* m = std::get_if<Scgp>(&options)) return m->composition;
  if (const auto* m = std::get_if<Ransac>(&options)) return m->composition;
  if (const auto* m = std::get_if<Pcm>(&options)) return m->composition;
  if (const auto* m = std::get_if<Densest>(&options)) return m->composition;
  return std::nullopt;
}

MergeMethod MergeMethod::make(std::string name, MergeMethodKind kind, double p, Composition composition) {
  MergeMethod m;
  m.name = std::move(name);
  switch (kind) {
    case MergeMethodKind::no_outliers:
      m.options = NoOutliers{};
      break;
    case MergeMethodKind::dcs:
      m.options = Dcs{};
      break;
    case MergeMethodKind::scgp:
      m.options = Scgp{composition, {}};
      break;
    case MergeMethodKind::ransac:
      m.options = Ransac{p, composition};
      break;
    case MergeMethodKind::pcm_exact:
      m.options = Pcm{p, composition, CliqueAlgorithm::exact};
      break;
    case MergeMethodKind::pcm_heuristic:
      m.options = Pcm{p, composition, CliqueAlgorithm::heuristic};
      break;
    case MergeMethodKind::densest:
      m.options = Densest{p, composition, {}};
      break;
  }
  return m;
}

void MergeMethod::validate() const {
  if (name.empty()) fail("MergeMethod: name must not be empty");
  if (const auto q = p(); q && !(*q > 0.0 && *q < 1.0))
    fail("MergeMethod '{}': p must be in (0, 1) (got {:g})", name, *q);
  if (const auto* m = std::get_if<Scgp>(&options)) m->options.validate();
  if (const auto* m = std::get_if<Densest>(&options)) m->options.validate();
  if (const auto* m = std::get_if<Pcm>(&options); m && m->algorithm == CliqueAlgorithm::brute_force)
    fail("MergeMethod '{}': the clique algorithm must be exact or heuristic", name);
  if (const auto* m = std::get_if<Dcs>(&options)) {
    if (!(std::isfinite(m->phi) && m->phi > 0.0))
      fail("MergeMethod '{}': dcs_phi must be finite and > 0 (got {:g})", name, m->phi);
    if (!(m->accept_scale > 0.0 && m->accept_scale <= 1.0))
      fail("MergeMethod '{}': dcs_accept_scale must be in (0, 1] (got {:g})", name, m->accept_scale);
  }
}

Selection select(const MergeMethod& method, const ConsistencyMatrix& Q) {
  method.validate();
  Selection s = std::visit(
      Overloaded{
          [&](const NoOutliers&) -> Selection {
            fail("select: method '{}' (no_outliers) selects the caller's inliers, not from Q", method.name);
          },
          [&](const Dcs&) -> Selection {
            fail("select: method '{}' (dcs) selects by merging (accepted_candidates), not from Q",
                 method.name);
          },
          [&](const Scgp& m) { return select_scgp(Q, m.options); },
          [&](const Ransac& m) { return select_ransac(Q, consistency_threshold(m.p, Q.dof)); },
          [&](const Pcm& m) { return select_pcm(Q, consistency_threshold(m.p, Q.dof), m.algorithm); },
          [&](const Densest& m) { return select_densest(Q, consistency_threshold(m.p, Q.dof), m.options); }},
      method.options);
  std::sort(s.selected.begin(), s.selected.end());
  return s;
}

}  // namespace keel::merge
