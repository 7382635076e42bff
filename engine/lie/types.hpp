// keel::lie — basic linear-algebra aliases used by the Lie-group uncertainty engine.
//
// Everything in this engine is double precision.  Conventions (thesis ch. 5):
//   * LEFT perturbation: T = exp(xi^) T_bar, xi ~ N(0, Sigma)            (eq. 5.14)
//   * SE(3) tangent xi = [rho; phi] (translation first)                  (eq. 5.6)
//   * SE(2) tangent [rho_x, rho_y, theta]; SO(2) tangent theta; SO(3) phi.
#pragma once

#include <Eigen/Core>

namespace keel::lie {

using Vec1 = Eigen::Matrix<double, 1, 1>;
using Vec2 = Eigen::Matrix<double, 2, 1>;
using Vec3 = Eigen::Matrix<double, 3, 1>;
using Vec4 = Eigen::Matrix<double, 4, 1>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat1 = Eigen::Matrix<double, 1, 1>;
using Mat2 = Eigen::Matrix<double, 2, 2>;
using Mat3 = Eigen::Matrix<double, 3, 3>;
using Mat4 = Eigen::Matrix<double, 4, 4>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

inline constexpr double kPi = 3.14159265358979323846264338327950288;
inline constexpr double kTwoPi = 2.0 * kPi;

/// Default tolerance used by from_matrix() when checking that a rotation block is
/// orthonormal (Frobenius norm of R^T R - I).  It is deliberately loose enough to
/// accept matrices printed with 6 significant digits (e.g. thesis eqs. 5.52-5.53);
/// accepted matrices are projected exactly onto the group afterwards.
inline constexpr double kOrthonormalityTolerance = 1e-5;

}  // namespace keel::lie
