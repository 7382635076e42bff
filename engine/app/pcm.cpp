#include "app/pcm.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/timing.hpp"

namespace keel::app {

namespace {

// Poses of a graph: its initial estimate, or (for a graph built in memory without one) 1 + the largest id an
// edge names.
template <class Graph>
int pose_count(const Graph& g) {
  int n = static_cast<int>(g.poses.size());
  for (const auto& e : g.edges) n = std::max({n, e.i + 1, e.j + 1});
  return n;
}

template <class G, class Edge, class Graph>
std::vector<pcm::InterRobotMeasurement<G>> candidates_from_edges(const Graph& a, const Graph& b,
                                                                 const std::vector<Edge>& edges) {
  if (edges.empty()) throw std::invalid_argument("inter-robot candidates: the candidate list is empty");
  const int na = pose_count(a), nb = pose_count(b);
  std::vector<pcm::InterRobotMeasurement<G>> out;
  out.reserve(edges.size());
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const Edge& e = edges[k];
    const std::string where =
        e.line > 0 ? fmt::format("candidate {} (line {})", k, e.line) : fmt::format("candidate {}", k);
    if (e.i < 0 || e.i >= na) {
      throw std::invalid_argument(
          fmt::format("{}: robot a has no pose {} (it has {} poses: 0 … {})", where, e.i, na, na - 1));
    }
    if (e.j < 0 || e.j >= nb) {
      throw std::invalid_argument(
          fmt::format("{}: robot b has no pose {} (it has {} poses: 0 … {})", where, e.j, nb, nb - 1));
    }
    pcm::InterRobotMeasurement<G> m;
    m.pose_a = e.i;
    m.pose_b = e.j;
    m.z = e.measurement;
    try {
      m.covariance = pcm::left_covariance_from_information(e.measurement, e.information);
    } catch (const std::invalid_argument& ex) {
      throw std::invalid_argument(fmt::format("{}: {}", where, ex.what()));
    }
    out.push_back(m);
  }
  return out;
}

template <class G, class Graph, class Edge>
Consistency<G> consistency_impl(const Graph& ga, const Graph& gb, const std::vector<Edge>& edges,
                                const PcmOptions& o, const Progress& progress) {
  o.validate();
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  Consistency<G> run;
  run.candidates = candidates_from_edges<G>(ga, gb, edges);
  say(fmt::format("solving robot a ({} poses, {} edges)", pose_count(ga), ga.edges.size()));
  run.a = merge::solve_local(ga, o.local);
  say(fmt::format("solving robot b ({} poses, {} edges)", pose_count(gb), gb.edges.size()));
  run.b = merge::solve_local(gb, o.local);
  say(fmt::format("joint marginals of the poses {} candidates touch", run.candidates.size()));
  const auto maps = merge::local_maps(run.a, run.b, run.candidates);
  run.marginals_time_s = maps.time_s;
  const std::size_t n = run.candidates.size();
  say(fmt::format("consistency matrix ({} × {} loop errors, eq. 2.4)", n, n));
  const auto t0 = core::Clock::now();
  pcm::ConsistencyOptions co;
  co.composition = o.composition;
  co.threads = o.threads;
  run.q = pcm::consistency_matrix(maps.a, maps.b, run.candidates, co);
  run.consistency_time_s = core::seconds_since(t0);
  return run;
}

template <class G, class Graph, class Edge>
PcmRun<G> pcm_impl(const Graph& ga, const Graph& gb, const std::vector<Edge>& edges, const PcmOptions& o,
                   const Progress& progress) {
  PcmRun<G> run;
  static_cast<Consistency<G>&>(run) = consistency_impl<G>(ga, gb, edges, o, progress);
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  run.gamma = pcm::consistency_threshold(o.p, run.q.dof);
  say(fmt::format("maximum clique ({}, γ = {:.4g})", pcm::to_string(o.algorithm), run.gamma));
  pcm::CliqueOptions clique;
  clique.time_limit_s = o.time_limit_s;
  run.selection = pcm::select_pcm(run.q, run.gamma, o.algorithm, clique);
  if (o.merge) {
    say(fmt::format("merged solve with {} selected candidates", run.selection.selected.size()));
    run.merged = merge::merge_maps(run.a, run.b, run.candidates, run.selection.selected, o.merge_options);
  }
  return run;
}

template <class G, class Graph, class Edge>
Graph merged_graph_impl(const PcmRun<G>& run) {
  if (!run.merged)
    throw std::invalid_argument("merged_graph: the run has no merged solve (PcmOptions::merge)");
  const auto& m = *run.merged;
  const int na = static_cast<int>(m.poses_a.size());
  Graph g;
  g.poses = m.poses_a;
  g.poses.insert(g.poses.end(), m.poses_b.begin(), m.poses_b.end());
  g.has_initial_poses = true;
  for (const auto& e : run.a.graph.edges) g.edges.push_back(e);
  for (auto e : run.b.graph.edges) {
    e.i += na;
    e.j += na;
    g.edges.push_back(e);
  }
  for (int k : m.selected) {
    const auto& c = run.candidates[static_cast<std::size_t>(k)];
    Edge e;
    e.i = c.pose_a;
    e.j = na + c.pose_b;
    e.measurement = c.z;
    e.information = pcm::information_from_left_covariance(c.z, c.covariance);
    g.edges.push_back(e);
  }
  return g;
}

}  // namespace

void PcmOptions::validate() const {
  if (!(p > 0.0 && p < 1.0))
    throw std::invalid_argument(fmt::format("app::PcmOptions: p must be in (0, 1) (got {})", p));
  if (!(std::isfinite(time_limit_s) && time_limit_s >= 0.0)) {
    throw std::invalid_argument(fmt::format(
        "app::PcmOptions: time_limit_s must be finite and >= 0, 0 for none (got {})", time_limit_s));
  }
  local.validate();
  merge_options.validate();
}

std::vector<pcm::InterRobotMeasurement2> inter_robot_candidates(const graph::PoseGraph2D& a,
                                                                const graph::PoseGraph2D& b,
                                                                const std::vector<graph::Edge2>& edges) {
  return candidates_from_edges<lie::SE2>(a, b, edges);
}
std::vector<pcm::InterRobotMeasurement3> inter_robot_candidates(const graph::PoseGraph3D& a,
                                                                const graph::PoseGraph3D& b,
                                                                const std::vector<graph::Edge3>& edges) {
  return candidates_from_edges<lie::SE3>(a, b, edges);
}

Consistency<lie::SE2> consistency(const graph::PoseGraph2D& a, const graph::PoseGraph2D& b,
                                  const std::vector<graph::Edge2>& candidates, const PcmOptions& options,
                                  const Progress& progress) {
  return consistency_impl<lie::SE2>(a, b, candidates, options, progress);
}
Consistency<lie::SE3> consistency(const graph::PoseGraph3D& a, const graph::PoseGraph3D& b,
                                  const std::vector<graph::Edge3>& candidates, const PcmOptions& options,
                                  const Progress& progress) {
  return consistency_impl<lie::SE3>(a, b, candidates, options, progress);
}

PcmRun2 pcm(const graph::PoseGraph2D& a, const graph::PoseGraph2D& b,
            const std::vector<graph::Edge2>& candidates, const PcmOptions& options,
            const Progress& progress) {
  return pcm_impl<lie::SE2>(a, b, candidates, options, progress);
}
PcmRun3 pcm(const graph::PoseGraph3D& a, const graph::PoseGraph3D& b,
            const std::vector<graph::Edge3>& candidates, const PcmOptions& options,
            const Progress& progress) {
  return pcm_impl<lie::SE3>(a, b, candidates, options, progress);
}

graph::PoseGraph2D merged_graph(const PcmRun2& run) {
  return merged_graph_impl<lie::SE2, graph::PoseGraph2D, graph::Edge2>(run);
}
graph::PoseGraph3D merged_graph(const PcmRun3& run) {
  return merged_graph_impl<lie::SE3, graph::PoseGraph3D, graph::Edge3>(run);
}

SelectionScore score_selection(const std::vector<int>& selected, const std::vector<bool>& inlier) {
  SelectionScore s;
  const int n = static_cast<int>(inlier.size());
  int inliers = 0;
  for (bool b : inlier) inliers += b ? 1 : 0;
  for (int k : selected) {
    if (k < 0 || k >= n)
      throw std::invalid_argument(
          fmt::format("score_selection: candidate {} has no label ({} labels)", k, n));
    (inlier[static_cast<std::size_t>(k)] ? s.true_positives : s.false_positives) += 1;
  }
  s.tpr = inliers ? static_cast<double>(s.true_positives) / inliers : 1.0;
  s.fpr = n - inliers ? static_cast<double>(s.false_positives) / (n - inliers) : 0.0;
  return s;
}

}  // namespace keel::app
