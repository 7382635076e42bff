// keel::lie — fourth-order covariance propagation through the composition of CORRELATED SE(3)
// poses (thesis ch. 5, §5.5.1, eqs. 5.34-5.39 and the footnote to eq. 5.37: "If increased
// accuracy is needed, then Isserlis Theorem can be applied to evaluate the fourth order terms in
// (5.36) and (5.37)").  Extends Barfoot & Furgale's Sigma_4th (T. D. Barfoot and P. T. Furgale,
// "Associating Uncertainty With Three-Dimensional Poses for Use in Estimation Problems",
// IEEE Trans. Robotics 30(3), 2014; see compose_fourth_order in uncertain.hpp) to jointly
// Gaussian perturbations.
//
// Setting (eqs. 5.14, 5.30-5.34): T_ik = T_ij T_jk, T = exp(xi^) T_bar, T_bar_ik = T_bar_ij T_bar_jk,
//   z = [xi_ij; xi_jk] ~ N(0, [Sigma_ij, Sigma_c; Sigma_c^T, Sigma_jk]),   Sigma_c = E[xi_ij xi_jk^T],
//   x = xi_ij, y = xi'_jk = Ad(T_bar_ij) xi_jk, and (BCH, eq. 5.34, ^c = curly hat of eq. 5.12)
//   xi_ik = L + Q + C + O(4),  L = x + y,  Q = 1/2 x^c y,  C = 1/12 (x^c x^c y + y^c y^c x).
//
// Second moment to fourth order in the perturbations (odd moments of a zero-mean Gaussian vanish,
// so E[L Q^T], E[Q C^T] and E[L D^T] with the 4th-order BCH term D are zero or of order 6):
//   E[xi_ik xi_ik^T] = E[L L^T] + E[Q Q^T] + E[L C^T] + E[C L^T] + O(6).
//   E[L L^T] is eq. 5.39.  E[Q Q^T] (4th-order diagonal and cross terms of eqs. 5.36-5.37, the
//   square of 1/2 x^c y) and E[L C^T] (products of the first-order term with the 1/12 terms) are
//   fourth moments of z, evaluated exactly with Isserlis' theorem (L. Isserlis, "On a formula for
//   the product-moment coefficient of any order of a normal frequency distribution in any number
//   of variables", Biometrika 12, 1918):  E[z_a z_b z_c z_d] = S_ab S_cd + S_ac S_bd + S_ad S_bc.
// With Sigma_c = 0 this reduces exactly to Barfoot & Furgale's Sigma_4th.
//
// Mean.  E[xi_ik] = E[Q] + O(4) = 1/2 sum_ab E[x_a y_b] G_a e_b, E[x y^T] = Sigma_c Ad(T_bar_ij)^T
// (G_a = curly_hat(e_a)), which is
// NON-zero at second order once the poses are correlated (it vanishes for independent poses).
// Convention used here: the mean pose stays T_bar_ik = T_bar_ij T_bar_jk (eq. 5.32) and the
// returned covariance is the SECOND MOMENT ABOUT ZERO of xi_ik = log(T_ik T_bar_ik^-1), the quantity
// eq. 5.57 estimates from Monte-Carlo samples (Sigma_mc).  The second-order mean m = E[xi_ik] is
// available through the optional out-parameter; the covariance about the mean is, to fourth order,
// cov - m m^T (m m^T is itself a fourth-order term).
#pragma once

#include <cstddef>
#include <string_view>

#include "se3.hpp"
#include "types.hpp"
#include "uncertain.hpp"

namespace keel::lie {

/// xi = BCH(x, y) truncated after the third-order terms (eq. 5.34), log(exp(x^) exp(y^)) =
/// x + y + 1/2 x^c y + 1/12 (x^c x^c y + y^c y^c x) + O(4).
inline Vec6 bch_third_order(const Vec6& x, const Vec6& y) {
  const Mat6 X = SE3::curly_hat(x);
  const Mat6 Y = SE3::curly_hat(y);
  const Vec6 xy = X * y;
  return x + y + 0.5 * xy + (X * xy + Y * (Y * x)) / 12.0;
}

/// E[xi xi^T] to fourth order for xi = bch_third_order(x, y) with [x; y] ~ N(0, S) (12x12,
/// S = [E[x x^T], E[x y^T]; E[y x^T], E[y y^T]]).  Brute-force Isserlis sums over all 12^4 index
/// quadruples.  `mean` (optional) receives E[xi] to third order (= E[1/2 x^c y]).
Mat6 bch_second_moment_fourth_order(const Mat12& S, Vec6* mean = nullptr);

/// T_ij T_jk of correlated poses, cross_ij_jk = E[xi_ij xi_jk^T] (untransformed, as in eq. 5.39).
/// Mean: T_bar_ij T_bar_jk (eq. 5.32).  Covariance: the fourth-order second moment about zero of
/// xi_ik (see the header comment).  With cross_ij_jk = 0 it equals compose_fourth_order(ij, jk).
/// perturbation_mean (optional) receives E[xi_ik] to second order.  Throws std::invalid_argument
/// (from UncertainPose) if the truncated expansion is not positive semi-definite (possible only
/// for nearly singular joint covariances; bch_second_moment_fourth_order gives the raw moment).
UncertainPose<SE3> compose_fourth_order_joint(const UncertainPose<SE3>& ij, const UncertainPose<SE3>& jk,
                                              const Mat6& cross_ij_jk, Vec6* perturbation_mean = nullptr);

/// T_i T_j for poses i, j of a joint distribution (uses cross(i, j)).
UncertainPose<SE3> compose_fourth_order_joint(const JointPoses<SE3>& poses, std::size_t i, std::size_t j,
                                              Vec6* perturbation_mean = nullptr);

/// How compose_chain_fourth_order_joint carries E[xi_{1:k} xi_m^T] (m > k) from step to step.
enum class ChainCrossOrder {
  /// E[xi_{1:k+1} xi_m^T] = E[xi_{1:k} xi_m^T] + Ad(T_bar_{1:k}) E[xi_{k+1} xi_m^T] (first order).
  first,
  /// first + E[C(x, y) xi_m^T], the fourth moment (Isserlis) of the 1/12 BCH terms with xi_m,
  /// treating (xi_{1:k}, xi'_{k+1}, xi_m) as jointly Gaussian.  Measured: no gain over `first`
  /// (slightly worse on the Fig. 5.4-like chain), because fourth-order terms of the same size
  /// that the sequential scheme cannot represent remain; use the _exact chain instead.
  fourth,
};

/// "first" / "fourth"; chain_cross_order_from_string throws std::invalid_argument naming the valid names.
[[nodiscard]] std::string_view to_string(ChainCrossOrder v);
[[nodiscard]] ChainCrossOrder chain_cross_order_from_string(std::string_view s);

/// T_1 T_2 ... T_N of jointly distributed poses, composed left to right one step at a time with
/// compose_fourth_order_joint.  Approximation (as in Barfoot & Furgale's sequential chain): the
/// running composite xi_{1:k} is treated as a zero-mean Gaussian with covariance equal to its
/// carried (fourth-order) second moment, and its cross-covariances with the remaining steps are
/// carried per `cross` (first order by default).  What this neglects when poses are correlated:
/// the second-order mean of xi_{1:k} and the non-Gaussian (quadratic) part of xi_{1:k} in the
/// fourth moments of the next step.  compose_chain_fourth_order_joint_exact keeps those terms.
/// For independent poses the result equals compose_chain_fourth_order.  Measured on the
/// Fig. 5.4-like chain (N = 10, AR(1) rho = 0.4, 2e5 Monte-Carlo samples): it halves the
/// normalized covariance error of eq. 5.39 chains (0.013 -> 0.0075 at sigma = 3, 0.023 -> 0.0115
/// at sigma = 5) while compose_chain_fourth_order_joint_exact reaches 0.0009 / 0.0020.
UncertainPose<SE3> compose_chain_fourth_order_joint(const JointPoses<SE3>& poses,
                                                    ChainCrossOrder cross = ChainCrossOrder::first);

/// The raw moment behind compose_chain_fourth_order_joint (symmetrized, not validated; poses.cov
/// may be singular).
Mat6 chain_second_moment_fourth_order_sequential(const JointPoses<SE3>& poses,
                                                 ChainCrossOrder cross = ChainCrossOrder::first);

/// T_1 T_2 ... T_N with E[xi xi^T] exact to fourth order for the whole chain: xi_{1:N} is built
/// as a cubic polynomial in the stacked 6N-vector u = [xi_1; ...; xi_N] ~ N(0, poses.cov) by
/// applying the truncated BCH step xi_{1:k+1} = BCH_3(xi_{1:k}, Ad(T_bar_{1:k}) xi_{k+1}) to
/// polynomials (terms of degree > 3 dropped), and
///   E[xi xi^T] = A S A^T + E[Q Q^T] + E[L C^T] + E[C L^T]
/// is evaluated in closed form with Isserlis' theorem (Q quadratic, C cubic part).
/// Cost: O(N^3) memory (6 (6N)^3 doubles for the cubic part: 10 MB at N = 10) and
/// O(N^4) time (~0.05 s at N = 10, -O2); meant for moderate N and as the reference for the
/// sequential method.  For N = 2 it equals compose_fourth_order_joint (to round-off); for
/// independent poses it agrees with compose_chain_fourth_order up to sixth-order terms (the
/// sequential chain keeps some sixth-order products that the truncated polynomial drops).
/// With correlated steps the sequential chain errs at fourth order and this one at sixth order
/// (checked against Gauss-Hermite quadrature in fourth_order_joint_test.cpp).
/// perturbation_mean (optional) receives E[xi_{1:N}] to second order.
/// Throws std::invalid_argument (from UncertainPose) if the truncated expansion is not positive
/// semi-definite, which can happen for (nearly) singular joint covariances.
UncertainPose<SE3> compose_chain_fourth_order_joint_exact(const JointPoses<SE3>& poses,
                                                          Vec6* perturbation_mean = nullptr);

/// The raw moment behind compose_chain_fourth_order_joint_exact: E[xi_{1:N} xi_{1:N}^T] to fourth
/// order (symmetrized, not validated; poses.cov may be singular).
Mat6 chain_second_moment_fourth_order(const JointPoses<SE3>& poses, Vec6* perturbation_mean = nullptr);

}  // namespace keel::lie
