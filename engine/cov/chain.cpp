#include "cov/chain.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "graph/residuals.hpp"

namespace keel::cov {

namespace {

template <class G, class Graph>
lie::MatX chain_joint_impl(const Graph& graph, const std::vector<G>& poses, const std::vector<int>& ids) {
  using J = typename G::Jacobian;
  constexpr int d = G::DoF;
  const int n = static_cast<int>(poses.size());
  if (n == 0) throw std::invalid_argument("chain_joint: no poses");
  // Λ_k, the information of Δ_k = ξ_{k+1} − ξ_k, from every edge of step k.
  std::vector<J> info(static_cast<std::size_t>(n > 1 ? n - 1 : 0), J::Zero());
  std::vector<char> seen(info.size(), 0);
  for (std::size_t e = 0; e < graph.edges.size(); ++e) {
    const auto& edge = graph.edges[e];
    const std::string where =
        edge.line > 0 ? fmt::format("edge {} (line {})", e, edge.line) : fmt::format("edge {}", e);
    if (edge.i < 0 || edge.j < 0 || edge.i >= n || edge.j >= n)
      throw std::invalid_argument(fmt::format("chain_joint: {} joins {} and {}; the chain has poses 0 … {}",
                                              where, edge.i, edge.j, n - 1));
    if (std::abs(edge.j - edge.i) != 1)
      throw std::invalid_argument(
          fmt::format("chain_joint: {} joins {} and {}, not consecutive poses: the graph is not a chain",
                      where, edge.i, edge.j));
    const auto lin = graph::linearize_edge(edge.measurement, poses[static_cast<std::size_t>(edge.i)],
                                           poses[static_cast<std::size_t>(edge.j)]);
    // r ≈ A_j (ξ_j − ξ_i) = ±A_j Δ_k: the sign squares away in A_jᵀ Ω A_j.
    const std::size_t k = static_cast<std::size_t>(std::min(edge.i, edge.j));
    info[k] += lin.J_r_xi_j.transpose() * edge.information * lin.J_r_xi_j;
    seen[k] = 1;
  }
  // P_k, the marginal of ξ_k: P_0 = 0, P_{k+1} = P_k + Λ_k⁻¹.
  std::vector<J> P(static_cast<std::size_t>(n), J::Zero());
  for (std::size_t k = 0; k + 1 < static_cast<std::size_t>(n); ++k) {
    if (!seen[k])
      throw std::invalid_argument(
          fmt::format("chain_joint: pose {} has no edge to pose {}: the graph is not a chain", k + 1, k));
    const J S = 0.5 * (info[k] + info[k].transpose());
    const Eigen::LLT<J> llt(S);
    if (llt.info() != Eigen::Success)
      throw std::invalid_argument(
          fmt::format("chain_joint: the information of the step {} → {} is not positive definite", k, k + 1));
    const J C = llt.solve(J::Identity());
    P[k + 1] = P[k] + 0.5 * (C + C.transpose());
  }
  const auto m = static_cast<Eigen::Index>(ids.size());
  for (const int id : ids)
    if (id < 0 || id >= n)
      throw std::invalid_argument(fmt::format("chain_joint: pose id {} is not in 0 … {}", id, n - 1));
  lie::MatX out(d * m, d * m);
  for (Eigen::Index a = 0; a < m; ++a)
    for (Eigen::Index b = a; b < m; ++b) {
      const J& block = P[static_cast<std::size_t>(
          std::min(ids[static_cast<std::size_t>(a)], ids[static_cast<std::size_t>(b)]))];
      out.template block<d, d>(d * a, d * b) = block;
      if (b != a) out.template block<d, d>(d * b, d * a) = block.transpose();
    }
  return out;
}

}  // namespace

lie::MatX chain_joint(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& poses,
                      const std::vector<int>& ids) {
  return chain_joint_impl(graph, poses, ids);
}
lie::MatX chain_joint(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& poses,
                      const std::vector<int>& ids) {
  return chain_joint_impl(graph, poses, ids);
}

}  // namespace keel::cov
