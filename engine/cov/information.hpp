// clang-format off
// keel::cov — the information (Fisher) matrix of a pose graph at a given solution, linearized in the Lie algebra.
//
// Thesis §5.8.2: to hand a MAP solution (iSAM, g2o, Ceres) to the Lie-algebra machinery of chapter 5, its
// uncertainty must be expressed in the left perturbation of eq. 5.14, T = exp(ξ^) T̄ — so the residuals are
// linearized with respect to ξ, not with respect to the coordinates (x, y, θ) of the poses.
//
// Residual conventions are those of keel::graph (engine/graph/pose_graph.hpp): an edge (i, j) with measurement z
// has E = z⁻¹ T_i⁻¹ T_j and r = ρ(E), 2D ρ(E) = (x_E, y_E, θ_E), 3D ρ(E) = (t_E, Log R_E); Ω is the inverse
// covariance of r.
//
// Derivation of the edge Jacobians (checked against central differences of the actual residual in
// information_test.cpp, at random poses and measurements, E far from the identity):
//   perturb T_i → exp(ξ_i^) T_i and T_j → exp(ξ_j^) T_j. Then, to first order (BCH),
//     E(ξ) = z⁻¹ T_i⁻¹ exp(−ξ_i^) exp(ξ_j^) T_j ≈ z⁻¹ T_i⁻¹ exp((ξ_j − ξ_i)^) T_j
//          = z⁻¹ T_i⁻¹ T_j exp((Ad(T_j⁻¹)(ξ_j − ξ_i))^) = E exp(η^),   η = Ad(T_j⁻¹)(ξ_j − ξ_i),
//   using X exp(a^) = exp((Ad_X a)^) X. With D(E) = ∂ρ(E exp(η^))/∂η at η = 0:
//     2D: E exp(η^) has translation t_E + R_E V(η_θ) η_ρ and angle θ_E + η_θ, so D(E) = diag(R_E, 1);
//     3D: translation t_E + R_E J_l(η_φ) η_ρ ≈ t_E + R_E η_ρ and
//         rotation Log(R_E exp(η_φ^)) ≈ Log R_E + J_r⁻¹(Log R_E) η_φ, so D(E) = blockdiag(R_E, J_r⁻¹(Log R_E));
//   hence A_j = ∂r/∂ξ_j = D(E) Ad(T_j⁻¹) and A_i = ∂r/∂ξ_i = −A_j.
// Landmarks (2D, world-frame position l, perturbed additively l → l + δ): r = R_iᵀ (l − t_i) − z = T_i⁻¹ l − z;
//   with T_i → exp(ξ^) T_i, T_i⁻¹ l → T_i⁻¹ exp(−ξ^) l ≈ T_i⁻¹ (l − ξ_ρ − ξ_θ J l), J = [0 −1; 1 0], so
//   ∂r/∂ξ_i = −R_iᵀ [I₂, J l] and ∂r/∂δ = R_iᵀ.
//
// H = Σ Aᵀ Ω A over all factors, stored as the upper triangle of a symmetric sparse matrix (compressed columns).
// The gauge freedom of relative measurements is removed by fixing one pose (its rows and columns are dropped
// and its covariance is zero) or by a prior on it.
// clang-format on
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "graph/pose_graph.hpp"
#include "graph/residuals.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"

namespace keel::cov {

using graph::PoseGraph2D;
using graph::PoseGraph3D;
using lie::Mat12;
using lie::Mat2;
using lie::Mat3;
using lie::Mat6;
using lie::MatX;
using lie::SE2;
using lie::SE3;
using lie::Vec2;
using lie::Vec3;
using lie::Vec6;
using lie::VecX;
using Mat23 = Eigen::Matrix<double, 2, 3>;

// ---------------------------------------------------------------------------------------------------------------------
// Residuals and their Lie-algebra Jacobians (left perturbation of eq. 5.14)
// ---------------------------------------------------------------------------------------------------------------------

/// The residuals themselves (graph/residuals.hpp): r = ρ(z⁻¹ T_i⁻¹ T_j), landmark r = Rᵀ (l − t) − z.
using graph::edge_residual;
using graph::landmark_residual;
/// Residual and Jacobians of one edge: A_j = D(E) Ad(T_j⁻¹), A_i = −A_j (graph/residuals.hpp).
using graph::EdgeLinearization2;
using graph::EdgeLinearization3;
using graph::LandmarkLinearization2;
using graph::linearize_edge;
using graph::linearize_landmark;

// ---------------------------------------------------------------------------------------------------------------------
// Gauge
// ---------------------------------------------------------------------------------------------------------------------

enum class Gauge {
  fix_pose,  // the pose `GaugeOptions::pose` is held fixed: its rows/columns are removed, its covariance is
             // zero
  prior,     // a prior with information `GaugeOptions::prior_information` on the Lie-algebra perturbation of
             // that pose
};
std::string_view to_string(Gauge g);  // "fix_pose", "prior"
// The exact names printed by to_string; anything else throws std::invalid_argument naming the valid names.
[[nodiscard]] Gauge gauge_from_string(std::string_view s);

struct GaugeOptions {
  Gauge kind = Gauge::fix_pose;  // how the gauge freedom of relative measurements is removed
  int pose = 0;                  // the pose that is fixed or receives the prior
  MatX
      prior_information;  // Gauge::prior only: DoF×DoF (3 for SE(2), 6 for SE(3)) symmetric positive definite
  /// Throws std::invalid_argument naming the violated constraint.
  void validate(int num_poses, int pose_dof) const;
};

// ---------------------------------------------------------------------------------------------------------------------
// Sparse symmetric information matrix
// ---------------------------------------------------------------------------------------------------------------------

/// The information matrix H (symmetric) of the variables that remain after the gauge: the upper triangle (row
/// ≤ col) in compressed-column form with sorted row indices. Variables are numbered poses first (0 …
/// num_poses−1), then landmarks (num_poses … num_poses+num_landmarks−1); `offset[v]` is the first row of
/// variable v in H, or −1 for the pose fixed by the gauge. Structural zeros inside the blocks that a factor
/// touches are stored explicitly.
struct SparseInformation {
  int num_poses = 0;
  int num_landmarks = 0;
  int pose_dof = 3;      // 3 (SE(2)) or 6 (SE(3))
  int landmark_dof = 2;  // 2D landmarks
  Gauge gauge = Gauge::fix_pose;
  int gauge_pose = 0;
  std::vector<int> offset;     // per variable, −1 when removed by the gauge
  int size = 0;                // rows (= columns) of H
  std::vector<int> col_start;  // size + 1 entries
  std::vector<int> row_index;  // row of each stored entry (≤ its column)
  std::vector<double> value;

  int num_variables() const { return num_poses + num_landmarks; }
  /// Variable id of landmark k.
  int landmark_variable(int k) const { return num_poses + k; }
  bool is_landmark(int v) const { return v >= num_poses; }
  /// DoF of variable v (pose_dof or landmark_dof).
  int variable_dim(int v) const { return v < num_poses ? pose_dof : landmark_dof; }
  std::size_t nonzeros() const { return value.size(); }
  /// Throws std::out_of_range unless 0 ≤ v < num_variables().
  void check_variable(int v) const;
  /// Variable whose block holds row r of H (r in [0, size)).
  int variable_of_row(int r) const;
  /// The full symmetric matrix as a dense matrix (for tests and small problems only).
  MatX dense() const;
  /// Throws std::invalid_argument if the compressed-column structure is inconsistent.
  void validate() const;
};

/// H = Σ Aᵀ Ω A of the edges (and landmark measurements) of `g`, linearized at `poses` (and `landmarks`,
/// world frame) in the left perturbation of eq. 5.14. `poses` must have one entry per pose of the graph (use
/// g.poses for the graph's own estimate); `landmarks` must cover every landmark id that is measured (it may
/// be empty when none is). Throws std::invalid_argument naming the offending edge (and its source line) on an
/// out-of-range index.
[[nodiscard]] SparseInformation information_matrix(const PoseGraph2D& g, const std::vector<SE2>& poses,
                                                   const std::vector<Vec2>& landmarks = {},
                                                   const GaugeOptions& gauge = {});
[[nodiscard]] SparseInformation information_matrix(const PoseGraph3D& g, const std::vector<SE3>& poses,
                                                   const GaugeOptions& gauge = {});

}  // namespace keel::cov
