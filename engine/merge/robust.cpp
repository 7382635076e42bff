#include "merge/robust.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "core/names.hpp"
#include "core/timing.hpp"
#include "cov/chain.hpp"
#include "graph/residuals.hpp"
#include "pgo/optimize.hpp"

namespace keel::merge {

namespace {

std::string at_line(int line) { return line > 0 ? fmt::format(" (line {})", line) : std::string(); }

// pgo's estimate type of a graph.
template <class Graph>
using EstimateOf =
    std::conditional_t<std::is_same_v<Graph, graph::PoseGraph2D>, pgo::Estimate2D, pgo::Estimate3D>;

template <class G, class Graph, class Edge>
RobustRun<G> robust_impl(const std::vector<Graph>& robots, const std::vector<Edge>& inter,
                         const RobustOptions& o, const RobustProgress& progress) {
  o.validate();
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  using J = typename G::Jacobian;
  constexpr int dof = G::DoF;
  if (robots.empty()) throw std::invalid_argument("robust: no robot's graph given");
  const int R = static_cast<int>(robots.size());
  RobustRun<G> run;
  run.options = o;
  auto robot_name = [&](int r) {
    const std::string& src = robots[static_cast<std::size_t>(r)].source;
    return R == 1 ? std::string("the robot")
                  : fmt::format("robot {}{}", r, src.empty() ? "" : " (" + src + ")");
  };

  // A candidate from an input edge: its robots and local poses, where it came from, and the left covariance
  // of its measurement (an information that is not positive definite is refused, named by `where`).
  auto candidate = [](int robot_a, int pose_a, int robot_b, int pose_b, int source, std::size_t edge,
                      const Edge& e, const std::string& where) {
    RobustCandidate<G> c;
    c.robot_a = robot_a;
    c.pose_a = pose_a;
    c.robot_b = robot_b;
    c.pose_b = pose_b;
    c.source = source;
    c.edge = static_cast<int>(edge);
    c.line = e.line;
    c.z = e.measurement;
    try {
      c.covariance = pcm::left_covariance_from_information(e.measurement, e.information);
    } catch (const std::invalid_argument& ex) {
      throw std::invalid_argument(fmt::format("{}: {}", where, ex.what()));
    }
    return c;
  };

  // Each robot's odometry (edges between consecutive poses, either direction, chaining every pose) and its
  // own candidate closures (every other edge).
  int total = 0;
  for (int r = 0; r < R; ++r) {
    const Graph& g = robots[static_cast<std::size_t>(r)];
    const int n = static_cast<int>(g.poses.size());
    if (n == 0) throw std::invalid_argument(fmt::format("robust: {} has no poses", robot_name(r)));
    run.offsets.push_back(total);
    total += n;
    Graph odo;
    odo.poses = g.poses;
    odo.has_initial_poses = g.has_initial_poses;
    odo.source = g.source;
    std::vector<char> chained(static_cast<std::size_t>(n), 0);
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      const auto& e = g.edges[k];
      if (e.i < 0 || e.i >= n || e.j < 0 || e.j >= n)
        throw std::invalid_argument(
            fmt::format("robust: {}: edge {} → {}{} names a pose it does not have (0 … {})", robot_name(r),
                        e.i, e.j, at_line(e.line), n - 1));
      if (std::abs(e.j - e.i) == 1) {
        odo.edges.push_back(e);
        chained[static_cast<std::size_t>(std::max(e.i, e.j))] = 1;
        continue;
      }
      run.candidates.push_back(candidate(
          r, e.i, r, e.j, r, k, e,
          fmt::format("robust: {}: loop closure {} → {}{}", robot_name(r), e.i, e.j, at_line(e.line))));
    }
    for (int k = 1; k < n; ++k)
      if (!chained[static_cast<std::size_t>(k)])
        throw std::invalid_argument(fmt::format(
            "robust: {}: pose {} has no odometry edge from pose {} (the odometry, edges between consecutive "
            "poses, must chain every pose; the loop closures are the other edges)",
            robot_name(r), k, k - 1));
    run.odometry.push_back(std::move(odo));
  }

  // The inter-robot candidates, ids global; each oriented from the lower robot to the higher (z⁻¹ =
  // exp(−Ad(z⁻¹) n) z̄⁻¹ to first order, so Σ' = Ad(z⁻¹) Σ Ad(z⁻¹)ᵀ).
  auto robot_of = [&](int id) {
    const auto it = std::upper_bound(run.offsets.begin(), run.offsets.end(), id);
    return static_cast<int>(it - run.offsets.begin()) - 1;
  };
  for (std::size_t k = 0; k < inter.size(); ++k) {
    const auto& e = inter[k];
    const std::string where = fmt::format("robust: inter-robot candidate {}{}", k, at_line(e.line));
    for (const int id : {e.i, e.j})
      if (id < 0 || id >= total)
        throw std::invalid_argument(
            fmt::format("{}: id {} is not a pose of the robots ({} poses together: ids 0 … {}, robot r's "
                        "pose k is id k plus "
                        "the poses of the robots before it)",
                        where, id, total, total - 1));
    const int ra = robot_of(e.i), rb = robot_of(e.j);
    RobustCandidate<G> c = candidate(ra, e.i - run.offsets[static_cast<std::size_t>(ra)], rb,
                                     e.j - run.offsets[static_cast<std::size_t>(rb)], -1, k, e, where);
    if (c.robot_a > c.robot_b) {
      std::swap(c.robot_a, c.robot_b);
      std::swap(c.pose_a, c.pose_b);
      c.z = c.z.inverse();
      const J A = c.z.adjoint();
      const J S = A * c.covariance * A.transpose();
      c.covariance = 0.5 * (S + S.transpose());
    }
    run.candidates.push_back(c);
  }

  // Groups: each robot's own closures, then each pair of robots, in that order.
  std::map<std::pair<int, int>, int> group_of;
  {
    std::vector<std::pair<int, int>> keys;
    for (const auto& c : run.candidates) keys.emplace_back(c.robot_a, c.robot_b);
    std::sort(keys.begin(), keys.end(), [](const auto& x, const auto& y) {
      return std::tuple(x.first != x.second, x) < std::tuple(y.first != y.second, y);
    });
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (const auto& k : keys) {
      group_of[k] = static_cast<int>(run.groups.size());
      RobustGroup grp;
      grp.robot_a = k.first;
      grp.robot_b = k.second;
      run.groups.push_back(grp);
    }
    for (std::size_t k = 0; k < run.candidates.size(); ++k) {
      auto& c = run.candidates[k];
      c.group = group_of.at({c.robot_a, c.robot_b});
      run.groups[static_cast<std::size_t>(c.group)].members.push_back(static_cast<int>(k));
    }
  }

  // Each robot's odometry map and the joint marginal of the poses its candidates touch.
  say(fmt::format("odometry maps ({} robot{}, {} poses, {} candidate loop closures)", R, R == 1 ? "" : "s",
                  total, run.candidates.size()));
  std::vector<pcm::LocalMap<G>> maps(static_cast<std::size_t>(R));
  for (const auto& c : run.candidates) {
    maps[static_cast<std::size_t>(c.robot_a)].ids.push_back(c.pose_a);
    maps[static_cast<std::size_t>(c.robot_b)].ids.push_back(c.pose_b);
  }
  for (int r = 0; r < R; ++r) {
    auto& map = maps[static_cast<std::size_t>(r)];
    if (map.ids.empty()) continue;  // no candidate touches it: its odometry is solved with the rest
    std::sort(map.ids.begin(), map.ids.end());
    map.ids.erase(std::unique(map.ids.begin(), map.ids.end()), map.ids.end());
    const double gib = 8.0 * std::pow(static_cast<double>(dof) * static_cast<double>(map.ids.size()), 2) /
                       (1024.0 * 1024 * 1024);
    if (gib > 2.0)
      throw std::invalid_argument(
          fmt::format("robust: {}: its candidates touch {} poses, whose dense joint marginal would take "
                      "{:.1f} GiB (limit 2)",
                      robot_name(r), map.ids.size(), gib));
    const auto t0 = core::Clock::now();
    const auto local = solve_local(run.odometry[static_cast<std::size_t>(r)], o.local);
    run.odometry_time_s += core::seconds_since(t0);
    say(fmt::format("joint marginals of the {} poses of {} that candidates touch", map.ids.size(),
                    robot_name(r)));
    const auto t1 = core::Clock::now();
    map.poses = local.poses;
    // The odometry map is a chain: its joint marginal in closed form (cov/chain.hpp), H⁻¹ exactly.
    map.joint = cov::chain_joint(run.odometry[static_cast<std::size_t>(r)], local.poses, map.ids);
    run.marginals_time_s += core::seconds_since(t1);
  }

  // Each group's Q (eq. 2.4), its threshold and its largest consistent set (eq. 2.5).
  run.gamma = pcm::consistency_threshold(o.p, dof);
  pcm::ConsistencyOptions co;
  co.composition = o.composition;
  co.threads = o.threads;
  pcm::CliqueOptions clique;
  clique.time_limit_s = o.time_limit_s;
  for (auto& grp : run.groups) {
    std::vector<pcm::InterRobotMeasurement<G>> cand;
    for (const int k : grp.members) {
      const auto& c = run.candidates[static_cast<std::size_t>(k)];
      cand.push_back({c.pose_a, c.pose_b, c.z, c.covariance});
    }
    const auto& ma = maps[static_cast<std::size_t>(grp.robot_a)];
    say(fmt::format("{}: consistency of {} candidates, then the largest consistent set",
                    grp.robot_a == grp.robot_b ? robot_name(grp.robot_a)
                                               : robot_name(grp.robot_a) + " and " + robot_name(grp.robot_b),
                    cand.size()));
    const auto t0 = core::Clock::now();
    grp.q = grp.robot_a == grp.robot_b
                ? pcm::consistency_matrix(ma, cand, co)
                : pcm::consistency_matrix(ma, maps[static_cast<std::size_t>(grp.robot_b)], cand, co);
    grp.consistency_time_s = core::seconds_since(t0);
    run.consistency_time_s += grp.consistency_time_s;
    grp.selector = o.selector != RobustSelector::automatic          ? o.selector
                   : static_cast<int>(cand.size()) <= o.exact_up_to ? RobustSelector::exact
                                                                    : RobustSelector::densest;
    if (grp.selector == RobustSelector::densest) {
      grp.selection = pcm::select_densest(grp.q, run.gamma);
      // No search proves its size; the degeneracy bound of the consistency graph (max core + 1) bounds it.
      const auto t1 = core::Clock::now();
      const auto bound =
          pcm::maximum_clique_heuristic(pcm::ConsistencyGraph::from_threshold(grp.q.n, grp.q.q, run.gamma));
      pcm::CliqueResult r;
      r.clique = grp.selection.selected;
      r.upper_bound = bound.upper_bound;
      r.status = static_cast<int>(r.clique.size()) == r.upper_bound ? core::SearchStatus::optimal
                                                                    : core::SearchStatus::unproven;
      grp.selection.search = r;
      grp.selection.time_s += core::seconds_since(t1);
    } else {
      grp.selection = pcm::select_pcm(grp.q, run.gamma,
                                      grp.selector == RobustSelector::exact ? pcm::CliqueAlgorithm::exact
                                                                            : pcm::CliqueAlgorithm::heuristic,
                                      clique);
    }
    run.selection_time_s += grp.selection.time_s;
    for (const int s : grp.selection.selected)
      run.candidates[static_cast<std::size_t>(grp.members[static_cast<std::size_t>(s)])].kept = true;
    for (std::size_t u = 0; u < grp.members.size(); ++u) {
      int against = 0;
      for (const int s : grp.selection.selected)
        if (grp.q.at(static_cast<int>(u), s) > run.gamma || grp.q.at(s, static_cast<int>(u)) > run.gamma)
          ++against;
      run.candidates[static_cast<std::size_t>(grp.members[u])].inconsistent_with_kept = against;
    }
    run.kept += static_cast<int>(grp.selection.selected.size());
  }

  // The first robot that kept closures (all but candidate `skip`) leave unjoined to robot 0, or −1 when every
  // robot is joined: without a join the robots have no common frame.
  auto unjoined_robot = [&](std::size_t skip) {
    std::vector<int> up(static_cast<std::size_t>(R));
    std::iota(up.begin(), up.end(), 0);
    auto top = [&](int r) {
      while (up[static_cast<std::size_t>(r)] != r) r = up[static_cast<std::size_t>(r)];
      return r;
    };
    for (std::size_t k = 0; k < run.candidates.size(); ++k)
      if (k != skip && run.candidates[k].kept)
        up[static_cast<std::size_t>(top(run.candidates[k].robot_b))] = top(run.candidates[k].robot_a);
    for (int r = 1; r < R; ++r)
      if (top(r) != top(0)) return r;
    return -1;
  };
  if (const int r = unjoined_robot(run.candidates.size()); r >= 0)
    throw std::invalid_argument(fmt::format(
        "robust: no kept inter-robot closure joins {} to robot 0, so the robots have no common frame "
        "({} of {} candidates kept)",
        robot_name(r), run.kept, run.candidates.size()));

  // All odometry, then the kept closures, as the inputs gave them (ids moved by the robots' offsets).
  Graph base;
  for (int r = 0; r < R; ++r) {
    const auto off = run.offsets[static_cast<std::size_t>(r)];
    const Graph& odo = run.odometry[static_cast<std::size_t>(r)];
    base.poses.insert(base.poses.end(), odo.poses.begin(), odo.poses.end());
    for (auto e : odo.edges) {
      e.i += off;
      e.j += off;
      base.edges.push_back(e);
    }
  }
  base.has_initial_poses =
      std::all_of(robots.begin(), robots.end(), [](const Graph& g) { return g.has_initial_poses; });
  base.source = R == 1 ? robots[0].source : std::string();
  auto edge_of = [&](const RobustCandidate<G>& c) {
    if (c.source < 0) return inter[static_cast<std::size_t>(c.edge)];
    auto e = robots[static_cast<std::size_t>(c.source)].edges[static_cast<std::size_t>(c.edge)];
    e.i += run.offsets[static_cast<std::size_t>(c.source)];
    e.j += run.offsets[static_cast<std::size_t>(c.source)];
    return e;
  };
  auto assemble = [&] {
    run.selected = base;
    for (const auto& c : run.candidates)
      if (c.kept) run.selected.edges.push_back(edge_of(c));
  };
  auto chi2_at = [&](const RobustCandidate<G>& c, const std::vector<G>& poses) {
    const auto e = edge_of(c);
    const auto res = graph::edge_residual(e.measurement, poses[static_cast<std::size_t>(e.i)],
                                          poses[static_cast<std::size_t>(e.j)]);
    return static_cast<double>(res.dot(e.information * res));
  };
  assemble();
  say(fmt::format("certified solve of the odometry and {} kept loop closures", run.kept));
  run.solved = pgo::certified_solution(run.selected, o.solve);
  // The residual check: the kept closure whose χ² = rᵀΩr at the solution is largest, above γ_r =
  // F⁻¹_χ²(dof)(1 − residual_p), is removed and the rest re-solved by Levenberg–Marquardt from the current
  // estimate, one closure per round (never one whose removal would leave a robot without a common frame);
  // once none is above γ_r, the certified solve of what is left gives the answer and its certificate.
  if (o.residual_p > 0.0) {
    run.residual_threshold = pcm::consistency_threshold(o.residual_p, dof);
    // Time of the check: the certified solves whose answers a later round replaced (the first among them) and
    // the re-solves; the last certified solve is the answer's own (solved.summary).
    const auto t_check = core::Clock::now();
    const double first_solve_s = run.solved.summary.total_time_s;
    // The worst kept closure above γ_r at `estimate`, if any (candidates.size() if none).
    auto worst_at = [&](const std::vector<G>& estimate, double* chi2) {
      double worst = run.residual_threshold;
      std::size_t worst_k = run.candidates.size();
      for (std::size_t k = 0; k < run.candidates.size(); ++k) {
        if (!run.candidates[k].kept) continue;
        const double x = chi2_at(run.candidates[k], estimate);
        if (x > worst && unjoined_robot(k) < 0) worst = x, worst_k = k;
      }
      *chi2 = worst;
      return worst_k;
    };
    std::vector<G> estimate = run.solved.graph.poses;
    bool certified_estimate = true;  // `estimate` is the certified solve's answer
    while (run.residual_rounds < o.max_residual_rounds) {
      double worst = 0.0;
      const std::size_t k = worst_at(estimate, &worst);
      if (k == run.candidates.size()) {
        if (certified_estimate) break;
        // None is above γ_r at LM's estimate: solve what is left with the certificate, and check its answer.
        say(fmt::format("certified solve of the odometry and {} kept loop closures", run.kept));
        run.solved = pgo::certified_solution(run.selected, o.solve);
        estimate = run.solved.graph.poses;
        certified_estimate = true;
        continue;
      }
      auto& c = run.candidates[k];
      c.kept = false;
      c.removed_in_round = ++run.residual_rounds;
      c.residual_chi2 = worst;
      --run.kept;
      assemble();
      say(fmt::format("residual check, round {}: closure {} → {} removed (χ² {:.4g} > {:.4g})",
                      run.residual_rounds, c.pose_a, c.pose_b, worst, run.residual_threshold));
      pgo::Options lm;
      lm.initial_guess = pgo::InitialGuess::supplied;
      lm.constant_poses = {run.selected.gauge_pose};
      EstimateOf<Graph> from;
      from.poses = estimate;
      estimate = pgo::optimize(run.selected, lm, &from).estimate.poses;
      certified_estimate = false;
    }
    if (!certified_estimate)  // the round limit was reached after a removal
      run.solved = pgo::certified_solution(run.selected, o.solve);
    if (run.residual_rounds > 0)
      run.residual_time_s = first_solve_s + core::seconds_since(t_check) - run.solved.summary.total_time_s;
  }
  for (auto& c : run.candidates)
    if (c.kept) c.residual_chi2 = chi2_at(c, run.solved.graph.poses);
  return run;
}

}  // namespace

namespace {
constexpr core::NameTable<RobustSelector, 4> kSelectorNames{"merge::RobustSelector",
                                                            {{{RobustSelector::automatic, "auto"},
                                                              {RobustSelector::exact, "exact"},
                                                              {RobustSelector::heuristic, "heuristic"},
                                                              {RobustSelector::densest, "densest"}}}};
}  // namespace

std::string_view to_string(RobustSelector s) { return kSelectorNames.name(s); }
RobustSelector robust_selector_from_string(std::string_view text) { return kSelectorNames.parse(text); }

void RobustOptions::validate() const {
  if (!(residual_p >= 0.0 && residual_p < 1.0))
    throw std::invalid_argument(fmt::format(
        "merge::RobustOptions: residual_p must be in [0, 1), 0 for no residual check (got {})", residual_p));
  if (max_residual_rounds < 0)
    throw std::invalid_argument(
        fmt::format("merge::RobustOptions: max_residual_rounds must be >= 0 (got {})", max_residual_rounds));
  if (exact_up_to < 1)
    throw std::invalid_argument(
        fmt::format("merge::RobustOptions: exact_up_to must be >= 1 (got {})", exact_up_to));
  if (!(p > 0.0 && p < 1.0))
    throw std::invalid_argument(fmt::format("merge::RobustOptions: p must be in (0, 1) (got {})", p));
  if (!(std::isfinite(time_limit_s) && time_limit_s >= 0.0))
    throw std::invalid_argument(fmt::format(
        "merge::RobustOptions: time_limit_s must be finite and >= 0, 0 for none (got {})", time_limit_s));
  local.validate();
  solve.validate();
}

RobustRun2 robust(const std::vector<graph::PoseGraph2D>& robots, const std::vector<graph::Edge2>& inter_robot,
                  const RobustOptions& options, const RobustProgress& progress) {
  return robust_impl<lie::SE2>(robots, inter_robot, options, progress);
}
RobustRun3 robust(const std::vector<graph::PoseGraph3D>& robots, const std::vector<graph::Edge3>& inter_robot,
                  const RobustOptions& options, const RobustProgress& progress) {
  return robust_impl<lie::SE3>(robots, inter_robot, options, progress);
}

}  // namespace keel::merge
