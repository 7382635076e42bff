// keel_python_reference — the engine calls behind keel.solve, keel.marginals and keel.consistency_matrix,
// from C++, with every double printed as {:.17g} (which round-trips), so tests/python/test_keel.py can check
// that the bindings agree bit for bit. Not installed.
//
//   keel_python_reference solve <graph> [i j]...
//       read the graph (2D or 3D by its first record, as keel.read_graph), solve it with app::solve's
//       defaults (keel.solve's defaults), then app::marginals of the pairs (i, j) at the solution (gauge pose
//       0, default CovarianceOptions, one thread).
//       -> {"dim", "poses": [[...]], "cost", "normalized_chi2", "iterations", "termination",
//           "marginals": [[row-major 6x6 or 12x12]...]}
//   keel_python_reference certify <graph>
//       app::solve_certified with keel.solve(certify=True)'s defaults
//       -> {"dim", "poses": [[...]], "cost", "lower_bound", "rank", "iterations", "termination"}
//   keel_python_reference consistency <graph_a> <graph_b> <candidates.g2o>
//       -> {"q": [[...]]}: app::consistency with composition joint, one thread (keel.consistency_matrix's
//       defaults)
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "app/files.hpp"
#include "app/marginals.hpp"
#include "app/pcm.hpp"
#include "app/solve.hpp"
#include "graph/build.hpp"
#include "graph/g2o.hpp"
#include "graph/io.hpp"
#include "graph/text_records.hpp"
#include "pcm/consistency.hpp"
#include "pgo/optimize.hpp"

namespace {

using namespace keel;

std::string num(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
  return fmt::format("{:.17g}", v);
}

template <class M>
std::string flat(const M& m) {
  std::string s = "[";
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) s += (i + j ? ", " : "") + num(m(i, j));
  return s + "]";
}

std::string row(const lie::SE2& T) {
  return fmt::format("[{}, {}, {}]", num(T.translation().x()), num(T.translation().y()), num(T.angle()));
}

std::string row(const lie::SE3& T) {
  double q[4];
  graph::quaternion_from_rotation(T.rotation(), q);
  const lie::Vec3& t = T.translation();
  return fmt::format("[{}, {}, {}, {}, {}, {}, {}]", num(t.x()), num(t.y()), num(t.z()), num(q[0]), num(q[1]),
                     num(q[2]), num(q[3]));
}

template <class Graph>
void solve(const Graph& g, int dim, const std::vector<std::pair<int, int>>& pairs) {
  const auto r = app::solve(g);
  std::string poses;
  for (const auto& T : r.graph.poses) poses += (poses.empty() ? "" : ",\n  ") + row(T);
  std::string marginals;
  if (!pairs.empty()) {
    app::MarginalsRequest request;
    request.pairs = pairs;
    const auto m = [&] {
      if constexpr (std::is_same_v<Graph, graph::PoseGraph2D>) {
        return app::marginals(g, pgo::Estimate2D{r.graph.poses, r.graph.landmarks}, request);
      } else {
        return app::marginals(g, pgo::Estimate3D{r.graph.poses}, request);
      }
    }();
    for (const auto& block : m.pairs) marginals += (marginals.empty() ? "" : ",\n  ") + flat(block);
  }
  fmt::print(
      "{{\"dim\": {}, \"cost\": {}, \"normalized_chi2\": {}, \"iterations\": {}, \"termination\": \"{}\",\n"
      "\"poses\": [\n  {}],\n\"marginals\": [\n  {}]}}\n",
      dim, num(r.summary.final_cost), num(r.summary.normalized_chi2), r.summary.iterations,
      pgo::to_string(r.summary.termination), poses, marginals);
}

template <class Graph>
void certify(const Graph& g, int dim) {
  const auto r = app::solve_certified(g);
  std::string poses;
  for (const auto& T : r.graph.poses) poses += (poses.empty() ? "" : ",\n  ") + row(T);
  const double lower = r.summary.certificate.bound.lower;
  fmt::print(
      "{{\"dim\": {}, \"cost\": {}, \"lower_bound\": {}, \"rank\": {}, \"iterations\": {}, "
      "\"termination\": \"{}\",\n\"poses\": [\n  {}]}}\n",
      dim, num(r.summary.final_cost), std::isfinite(lower) ? num(lower) : std::string("null"),
      r.summary.final_rank, r.summary.iterations, pgo::to_string(r.summary.termination), poses);
}

template <class Graph, class Edge>
void consistency(const Graph& a, const Graph& b, const std::vector<Edge>& edges) {
  const pcm::ConsistencyMatrix Q = app::consistency(a, b, edges).q;
  std::string rows;
  for (int u = 0; u < Q.n; ++u) {
    std::string r;
    for (int v = 0; v < Q.n; ++v) r += (v ? ", " : "") + num(Q.at(u, v));
    rows += (u ? ",\n  [" : "[") + r + "]";
  }
  fmt::print("{{\"q\": [\n  {}]}}\n", rows);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() >= 2 && args[0] == "solve" && args.size() % 2 == 0) {
      std::vector<std::pair<int, int>> pairs;
      for (std::size_t k = 2; k + 1 < args.size(); k += 2)
        pairs.emplace_back(std::stoi(args[k]), std::stoi(args[k + 1]));
      if (app::graph_dimension(args[1]) == 3) {
        solve(graph::read_pose_graph_3d(args[1]), 3, pairs);
      } else {
        solve(graph::read_pose_graph_2d(args[1]), 2, pairs);
      }
      return 0;
    }
    if (args.size() == 2 && args[0] == "certify") {
      if (app::graph_dimension(args[1]) == 3) {
        certify(graph::read_pose_graph_3d(args[1]), 3);
      } else {
        certify(graph::read_pose_graph_2d(args[1]), 2);
      }
      return 0;
    }
    if (args.size() == 4 && args[0] == "consistency") {
      if (app::graph_dimension(args[1]) == 3) {
        consistency(graph::read_pose_graph_3d(args[1]), graph::read_pose_graph_3d(args[2]),
                    graph::read_g2o_edges_3d(args[3]));
      } else {
        consistency(graph::read_pose_graph_2d(args[1]), graph::read_pose_graph_2d(args[2]),
                    graph::read_g2o_edges_2d(args[3]));
      }
      return 0;
    }
    fmt::print(stderr,
               "usage: keel_python_reference solve <graph> [i j]...\n"
               "       keel_python_reference certify <graph>\n"
               "       keel_python_reference consistency <graph_a> <graph_b> <candidates.g2o>\n");
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "keel_python_reference: {}\n", e.what());
    return 1;
  }
}
