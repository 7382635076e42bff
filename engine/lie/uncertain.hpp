// keel::lie — uncertain poses with Lie-algebra (left) perturbations, and first-order
// propagation through composition, inversion and relative pose (thesis ch. 5,
// sections 5.4-5.7), plus Barfoot & Furgale (2014) fourth-order compounding for SE(3).
//
// Model (eq. 5.14):  T = exp(xi^) T_bar,  xi ~ N(0, Sigma).
// Jointly distributed poses (eqs. 5.28-5.29): xi_{1:n} ~ N(0, Sigma_{1:n}).
// Cross-covariance convention: cross(i, j) = E[xi_i xi_j^T] (block (i, j) of Sigma_{1:n}).
//
// All function templates below are explicitly instantiated (in uncertain.cpp) for
// SO2, SO3, SE2 and SE3.
#pragma once

#include <cstddef>
#include <vector>

#include "concepts.hpp"
#include "se2.hpp"
#include "se3.hpp"
#include "so2.hpp"
#include "so3.hpp"
#include "types.hpp"

namespace keel::lie {

/// An uncertain pose T = exp(xi^) mean, xi ~ N(0, cov) (eq. 5.14).
template <LieGroup G>
struct UncertainPose {
  using Group = G;
  using Jacobian = typename G::Jacobian;

  G mean{};
  Jacobian cov = Jacobian::Zero();

  UncertainPose() = default;
  /// Throws std::invalid_argument if cov is not symmetric positive semi-definite.
  UncertainPose(const G& mean_, const Jacobian& cov_) : mean(mean_), cov(cov_) { validate(); }
  /// A known (certain) pose: zero covariance.
  static UncertainPose known(const G& mean_) { return UncertainPose(mean_, Jacobian::Zero()); }
  /// Throws std::invalid_argument if cov is not symmetric positive semi-definite.
  void validate() const;
};

/// n jointly distributed poses: means (eq. 5.29) and the joint Lie-algebra covariance (eq. 5.28).
template <LieGroup G>
struct JointPoses {
  using Group = G;
  using Jacobian = typename G::Jacobian;

  std::vector<G> means;
  MatX cov;

  std::size_t size() const { return means.size(); }
  /// Pose i with its marginal covariance (block (i, i)).
  UncertainPose<G> marginal(std::size_t i) const;
  /// E[xi_i xi_j^T], block (i, j) of cov.
  Jacobian cross(std::size_t i, std::size_t j) const;
  /// Cheap check: cov is (DoF n) x (DoF n).  Throws std::invalid_argument.
  void check_dimensions() const;
  /// check_dimensions() plus symmetry / positive semi-definiteness of cov.
  void validate() const;
  /// Block-diagonal joint distribution of independent poses.
  static JointPoses independent(const std::vector<UncertainPose<G>>& poses);
};

/// exp(xi^) mean — a sample of the distribution of eq. 5.14 for a given perturbation.
template <LieGroup G>
inline G perturb(const G& mean, const typename G::Tangent& xi) {
  return G::exp(xi) * mean;
}

/// log(T mean^-1)^v — the perturbation of a sample about a mean (eq. 5.59).
template <LieGroup G>
inline typename G::Tangent perturbation_of(const G& sample, const G& mean) {
  return (sample * mean.inverse()).log();
}

// ---------------------------------------------------------------------------------------
// Composition T_ik = T_ij T_jk.  Mean: eq. 5.32.
// ---------------------------------------------------------------------------------------

/// Independent poses (Barfoot & Furgale 2014, first order): Sigma_ij + Ad Sigma_jk Ad^T.
template <LieGroup G>
UncertainPose<G> compose(const UncertainPose<G>& ij, const UncertainPose<G>& jk);

/// Correlated poses, eq. 5.39; cross_ij_jk = E[xi_ij xi_jk^T].
template <LieGroup G>
UncertainPose<G> compose(const UncertainPose<G>& ij, const UncertainPose<G>& jk,
                         const typename G::Jacobian& cross_ij_jk);

/// Known pose on the left (exact): K exp(xi) T_bar = exp(Ad_K xi) K T_bar => Ad_K Sigma Ad_K^T.
template <LieGroup G>
UncertainPose<G> compose(const G& known_ij, const UncertainPose<G>& jk);

/// Known pose on the right (exact): exp(xi) T_bar K => covariance unchanged.
template <LieGroup G>
UncertainPose<G> compose(const UncertainPose<G>& ij, const G& known_jk);

/// T_i T_j for poses i, j of a joint distribution (eq. 5.39 with cross(i, j) when
/// use_cross, otherwise the independent formula).
template <LieGroup G>
UncertainPose<G> compose(const JointPoses<G>& poses, std::size_t i, std::size_t j, bool use_cross = true);

// ---------------------------------------------------------------------------------------
// Inverse T_ji = T_ij^-1 (eqs. 5.43-5.45, exact).
// ---------------------------------------------------------------------------------------
template <LieGroup G>
UncertainPose<G> inverse(const UncertainPose<G>& ij);

// ---------------------------------------------------------------------------------------
// Relative pose T_jk = T_ij^-1 T_ik.  Mean: eq. 5.48.  Covariance: eq. 5.51 (signs
// re-derived, see uncertain.cpp):  A = Ad_{T_ij^-1},
//   Sigma_jk = A (Sigma_ij + Sigma_ik - Sigma_{ij,ik} - Sigma_{ij,ik}^T) A^T.
// ---------------------------------------------------------------------------------------

/// Independent poses (eq. 5.51 without the cross terms).
template <LieGroup G>
UncertainPose<G> relative(const UncertainPose<G>& ij, const UncertainPose<G>& ik);

/// Correlated poses (eq. 5.51); cross_ij_ik = E[xi_ij xi_ik^T].
template <LieGroup G>
UncertainPose<G> relative(const UncertainPose<G>& ij, const UncertainPose<G>& ik,
                          const typename G::Jacobian& cross_ij_ik);

/// Known T_ij (exact): Ad_{K^-1} Sigma_ik Ad_{K^-1}^T.
template <LieGroup G>
UncertainPose<G> relative(const G& known_ij, const UncertainPose<G>& ik);

/// Known T_ik (exact): Ad_{T_ij^-1} Sigma_ij Ad_{T_ij^-1}^T.
template <LieGroup G>
UncertainPose<G> relative(const UncertainPose<G>& ij, const G& known_ik);

/// T_i^-1 T_k for poses i, k of a joint distribution.
template <LieGroup G>
UncertainPose<G> relative(const JointPoses<G>& poses, std::size_t i, std::size_t k, bool use_cross = true);

// ---------------------------------------------------------------------------------------
// Growing a joint distribution: each function appends a new pose whose perturbation is the
// first-order linear function of the existing ones, keeping all cross-covariances.
// They return the index of the new pose.
// ---------------------------------------------------------------------------------------

/// Appends T_i T_j: xi_new = xi_i + Ad_{T_i} xi_j (repeated eq. 5.39).
template <LieGroup G>
std::size_t append_composition(JointPoses<G>& poses, std::size_t i, std::size_t j);

/// Appends T_i^-1: xi_new = -Ad_{T_i^-1} xi_i (eq. 5.43).
template <LieGroup G>
std::size_t append_inverse(JointPoses<G>& poses, std::size_t i);

/// Appends T_i^-1 T_k: xi_new = Ad_{T_i^-1} (xi_k - xi_i) (eq. 5.47).
template <LieGroup G>
std::size_t append_relative(JointPoses<G>& poses, std::size_t i, std::size_t k);

/// The DoF x (DoF n) first-order Jacobian of T_1 T_2 ... T_n w.r.t. xi_{1:n}:
/// J = [I, Ad(T_1), Ad(T_1 T_2), ..., Ad(T_1 ... T_{n-1})].
template <LieGroup G>
MatX chain_jacobian(const JointPoses<G>& poses);

/// T_1 T_2 ... T_n with Sigma = J Sigma_{1:n} J^T (use_cross) or
/// sum_k J_k Sigma_k J_k^T (cross-covariances ignored).
template <LieGroup G>
UncertainPose<G> compose_chain(const JointPoses<G>& poses, bool use_cross = true);

/// Chain of independent poses (first order).
template <LieGroup G>
UncertainPose<G> compose_chain(const std::vector<UncertainPose<G>>& poses);

// ---------------------------------------------------------------------------------------
// Fourth-order compounding of INDEPENDENT SE(3) poses:
// T. D. Barfoot and P. T. Furgale, "Associating Uncertainty With Three-Dimensional Poses
// for Use in Estimation Problems", IEEE Trans. Robotics 30(3), 2014 (Sigma_4th, Sec. III).
// ---------------------------------------------------------------------------------------

/// <<A>> = -tr(A) I + A (3x3).
Mat3 double_bracket(const Mat3& A);
/// <<A, B>> = <<A>> <<B>> + <<B A>> (3x3).
Mat3 double_bracket(const Mat3& A, const Mat3& B);
/// <<Sigma>> = [<<S_pp>>, <<S_rp + S_rp^T>>; 0, <<S_pp>>] for Sigma = [S_rr, S_rp; S_rp^T, S_pp]
/// (equals E[xi^curly xi^curly] for xi ~ N(0, Sigma), curly = eq. 5.12).
Mat6 double_bracket(const Mat6& Sigma);
/// Barfoot & Furgale's B = E[xi_1^curly Sigma_2 xi_1^curly^T] assembled from 3x3 blocks.
Mat6 fourth_order_b_matrix(const Mat6& Sigma1, const Mat6& Sigma2);

/// T_ij T_jk of independent poses with Barfoot & Furgale's Sigma_4th:
/// Sigma_1 + Sigma_2' + B/4 + (A_1 Sigma_2' + Sigma_2' A_1^T + A_2' Sigma_1 + Sigma_1 A_2'^T)/12,
/// Sigma_2' = Ad(T_ij) Sigma_jk Ad(T_ij)^T, A = <<.>>.
UncertainPose<SE3> compose_fourth_order(const UncertainPose<SE3>& ij, const UncertainPose<SE3>& jk);

/// Chain of independent poses, compounded left to right one at a time with compose_fourth_order.
UncertainPose<SE3> compose_chain_fourth_order(const std::vector<UncertainPose<SE3>>& poses);

}  // namespace keel::lie
