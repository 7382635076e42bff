#include "app/robust.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/timing.hpp"

namespace keel::app {

namespace {

template <class G, class Graph>
RobustRun<G> robust_impl(const Graph& input, const RobustOptions& o, const Progress& progress) {
  o.validate();
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  constexpr int dof = G::DoF;
  RobustRun<G> run;
  run.options = o;
  const int n = static_cast<int>(input.poses.size());
  // The odometry: every edge between consecutive poses (either direction). Every pose k > 0 must be reached
  // from k − 1, or the odometry map is not one connected chain.
  run.odometry.poses = input.poses;
  run.odometry.has_initial_poses = input.has_initial_poses;
  std::vector<char> chained(static_cast<std::size_t>(std::max(n, 1)), 0);
  for (std::size_t k = 0; k < input.edges.size(); ++k) {
    const auto& e = input.edges[k];
    if (std::abs(e.j - e.i) == 1) {
      run.odometry.edges.push_back(e);
      chained[static_cast<std::size_t>(std::max(e.i, e.j))] = 1;
    } else {
      run.candidate_edges.push_back(static_cast<int>(k));
    }
  }
  for (int k = 1; k < n; ++k)
    if (!chained[static_cast<std::size_t>(k)])
      throw std::invalid_argument(fmt::format(
          "robust: pose {} has no odometry edge from pose {} (the odometry, edges between consecutive poses, "
          "must chain every pose; the loop closures are the other edges)",
          k, k - 1));
  for (const int k : run.candidate_edges) {
    const auto& e = input.edges[static_cast<std::size_t>(k)];
    pcm::InterRobotMeasurement<G> m;
    m.pose_a = e.i;
    m.pose_b = e.j;
    m.z = e.measurement;
    try {
      m.covariance = pcm::left_covariance_from_information(e.measurement, e.information);
    } catch (const std::invalid_argument& ex) {
      throw std::invalid_argument(fmt::format("robust: loop closure {} → {}{}: {}", e.i, e.j,
                                              e.line > 0 ? fmt::format(" (line {})", e.line) : std::string(),
                                              ex.what()));
    }
    run.candidates.push_back(m);
  }

  say(fmt::format("odometry map ({} poses, {} odometry edges, {} candidate loop closures)", n,
                  run.odometry.edges.size(), run.candidates.size()));
  const auto t_odo = core::Clock::now();
  const auto local = merge::solve_local(run.odometry, o.local);
  run.odometry_time_s = core::seconds_since(t_odo);

  if (!run.candidates.empty()) {
    pcm::LocalMap<G> map;
    map.poses = local.poses;
    for (const auto& c : run.candidates) map.ids.insert(map.ids.end(), {c.pose_a, c.pose_b});
    std::sort(map.ids.begin(), map.ids.end());
    map.ids.erase(std::unique(map.ids.begin(), map.ids.end()), map.ids.end());
    const double bytes = 8.0 * std::pow(static_cast<double>(dof) * static_cast<double>(map.ids.size()), 2);
    if (bytes > 2.0 * 1024 * 1024 * 1024)
      throw std::invalid_argument(
          fmt::format("robust: the {} candidates touch {} poses, whose dense joint marginal would take "
                      "{:.1f} GiB (limit 2)",
                      run.candidates.size(), map.ids.size(), bytes / (1024.0 * 1024 * 1024)));
    say(fmt::format("joint marginals of the {} poses the candidates touch", map.ids.size()));
    const auto t_m = core::Clock::now();
    map.joint = local.covariance->joint(map.ids);
    run.marginals_time_s = core::seconds_since(t_m);
    const std::size_t m = run.candidates.size();
    say(fmt::format("consistency matrix ({} × {} loop errors, eq. 2.4, one map)", m, m));
    const auto t_q = core::Clock::now();
    pcm::ConsistencyOptions co;
    co.composition = o.composition;
    co.threads = o.threads;
    run.q = pcm::consistency_matrix(map, run.candidates, co);
    run.consistency_time_s = core::seconds_since(t_q);
    run.gamma = pcm::consistency_threshold(o.p, run.q.dof);
    say(fmt::format("maximum clique ({}, γ = {:.4g})", pcm::to_string(o.algorithm), run.gamma));
    pcm::CliqueOptions clique;
    clique.time_limit_s = o.time_limit_s;
    run.selection = pcm::select_pcm(run.q, run.gamma, o.algorithm, clique);
  } else {
    run.q.dof = dof;
    run.gamma = pcm::consistency_threshold(o.p, dof);
  }

  run.selected = run.odometry;
  for (const int k : run.selection.selected)
    run.selected.edges.push_back(
        input.edges[static_cast<std::size_t>(run.candidate_edges[static_cast<std::size_t>(k)])]);
  say(fmt::format("certified solve of the odometry and {} selected loop closures",
                  run.selection.selected.size()));
  run.solved = solve_certified(run.selected, Certified{o.solve});
  return run;
}

}  // namespace

void RobustOptions::validate() const {
  if (!(p > 0.0 && p < 1.0))
    throw std::invalid_argument(fmt::format("app::RobustOptions: p must be in (0, 1) (got {})", p));
  if (!(std::isfinite(time_limit_s) && time_limit_s >= 0.0))
    throw std::invalid_argument(fmt::format(
        "app::RobustOptions: time_limit_s must be finite and >= 0, 0 for none (got {})", time_limit_s));
  local.validate();
  solve.validate();
}

RobustRun2 robust(const graph::PoseGraph2D& graph, const RobustOptions& options, const Progress& progress) {
  return robust_impl<lie::SE2>(graph, options, progress);
}
RobustRun3 robust(const graph::PoseGraph3D& graph, const RobustOptions& options, const Progress& progress) {
  return robust_impl<lie::SE3>(graph, options, progress);
}

}  // namespace keel::app
