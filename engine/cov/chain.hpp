// keel::cov — the joint marginal covariance of an odometry chain in closed form.
//
// A graph whose every edge joins consecutive poses (i, i + 1 in either direction; parallel edges allowed) and
// in which every pose k > 0 is joined to k − 1 is a chain. With pose 0 fixed (the gauge of
// information_matrix) and Δ_k = ξ_{k+1} − ξ_k, each edge's linearized residual depends on one Δ_k only (r ≈
// A_j (ξ_j − ξ_i), A_j = ∂r/∂ξ_j, information.hpp), so the information of Δ is block-diagonal: Λ_k = Σ_e A_eᵀ
// Ω_e A_e over the edges of step k, and the Δ_k are independent with covariance Λ_k⁻¹. Since ξ_a = Σ_{m<a}
// Δ_m,
//
//     Cov(ξ_a, ξ_b) = P_min(a,b),   P_0 = 0,   P_{k+1} = P_k + Λ_k⁻¹                 (thesis eqs. 5.28, 5.48)
//
// which is H⁻¹ of information_matrix exactly (up to rounding): the change of variables ξ → Δ is linear and
// invertible. It costs O(n d³) for the P_k and O(m² d²) to write the joint of m poses, where a factorization
// of H and its selected inverse (MarginalCovariance::joint) cost far more for a dense joint of many poses.
#pragma once

#include <vector>

#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"

namespace keel::cov {

/// The joint covariance of the poses `ids` (ascending or not, repeats allowed; blocks in the order of `ids`)
/// of the chain `graph` linearized at `poses` (left perturbation, pose 0 fixed): the (d · ids.size())² matrix
/// MarginalCovariance::joint would give. Throws std::invalid_argument naming the edge or pose when an edge
/// does not join consecutive poses, a pose k > 0 has no edge to k − 1, an id is out of range, or a step's
/// information is not positive definite.
[[nodiscard]] lie::MatX chain_joint(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& poses,
                                    const std::vector<int>& ids);
[[nodiscard]] lie::MatX chain_joint(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& poses,
                                    const std::vector<int>& ids);

}  // namespace keel::cov
