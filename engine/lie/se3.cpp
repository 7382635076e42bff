#include "se3.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "concepts.hpp"
#include "lie_series.hpp"

namespace keel::lie {

static_assert(LieGroup<SE3>);

SE3 SE3::exp(const Tangent& xi, Jacobian* J_out_xi) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  if (J_out_xi) *J_out_xi = left_jacobian(xi);
  return SE3(SO3::exp(phi), SO3::left_jacobian(phi) * rho);
}

SE3::MatrixType SE3::hat(const Tangent& xi) {
  MatrixType m = MatrixType::Zero();
  m.topLeftCorner<3, 3>() = SO3::hat(xi.tail<3>());
  m.topRightCorner<3, 1>() = xi.head<3>();
  return m;
}

SE3::Tangent SE3::vee(const MatrixType& m) {
  Tangent xi;
  xi.head<3>() = m.topRightCorner<3, 1>();
  xi.tail<3>() = SO3::vee(m.topLeftCorner<3, 3>());
  return xi;
}

SE3::Jacobian SE3::curly_hat(const Tangent& xi) {
  Jacobian A = Jacobian::Zero();
  const Mat3 P = SO3::hat(xi.tail<3>());
  A.topLeftCorner<3, 3>() = P;
  A.bottomRightCorner<3, 3>() = P;
  A.topRightCorner<3, 3>() = SO3::hat(xi.head<3>());
  return A;
}

Mat3 SE3::q_block(const Vec3& rho, const Vec3& phi) {
  // Barfoot & Furgale (2014), Barfoot (2017) eq. 7.86:
  // Q = 1/2 P + c1 (F P + P F + F P F) + c2 (F F P + P F F - 3 F P F) + c3 (F P F F + F F P F),
  // F = phi^, P = rho^, c1 = (t - sin t)/t^3, c2 = (t^2 + 2 cos t - 2)/(2 t^4),
  // c3 = (2 t - 3 sin t + t cos t)/(2 t^5).
  const double theta = phi.norm();
  const Mat3 F = SO3::hat(phi);
  const Mat3 P = SO3::hat(rho);
  const Mat3 FP = F * P;
  const Mat3 PF = P * F;
  const Mat3 FPF = FP * F;
  const Mat3 FFP = F * FP;
  const Mat3 PFF = PF * F;
  const double c1 = detail::theta_minus_sin_over_theta3(theta);
  const double c2 = detail::q_coeff2(theta);
  const double c3 = detail::q_coeff3(theta);
  return 0.5 * P + c1 * (FP + PF + FPF) + c2 * (FFP + PFF - 3.0 * FPF) + c3 * (FPF * F + F * FPF);
}

SE3::Jacobian SE3::left_jacobian(const Tangent& xi) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  const Mat3 J = SO3::left_jacobian(phi);
  Jacobian out = Jacobian::Zero();
  out.topLeftCorner<3, 3>() = J;
  out.bottomRightCorner<3, 3>() = J;
  out.topRightCorner<3, 3>() = q_block(rho, phi);
  return out;
}

SE3::Jacobian SE3::right_jacobian(const Tangent& xi) { return left_jacobian(-xi); }

SE3::Jacobian SE3::left_jacobian_inverse(const Tangent& xi) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  const Mat3 Ji = SO3::left_jacobian_inverse(phi);
  Jacobian out = Jacobian::Zero();
  out.topLeftCorner<3, 3>() = Ji;
  out.bottomRightCorner<3, 3>() = Ji;
  out.topRightCorner<3, 3>() = -Ji * q_block(rho, phi) * Ji;
  return out;
}

SE3::Jacobian SE3::right_jacobian_inverse(const Tangent& xi) { return left_jacobian_inverse(-xi); }

SE3 SE3::from_matrix(const MatrixType& T, double tol) {
  if (!T.allFinite()) throw std::invalid_argument("SE3::from_matrix: matrix has non-finite entries");
  const double bottom = T.bottomLeftCorner<1, 3>().cwiseAbs().sum() + std::abs(T(3, 3) - 1.0);
  if (!(bottom <= tol))
    throw std::invalid_argument(
        fmt::format("SE3::from_matrix: bottom row is not [0 0 0 1] (deviation {:f})", bottom));
  return SE3(SO3::from_matrix(T.topLeftCorner<3, 3>(), tol), T.topRightCorner<3, 1>());
}

SE3::Tangent SE3::log(Jacobian* J_out_this) const {
  const Vec3 phi = rot_.log();
  Tangent xi;
  xi.head<3>() = SO3::left_jacobian_inverse(phi) * t_;
  xi.tail<3>() = phi;
  if (J_out_this) *J_out_this = left_jacobian_inverse(xi);
  return xi;
}

SE3 SE3::inverse(Jacobian* J_out_this) const {
  const SO3 ri = rot_.inverse();
  SE3 inv(ri, -(ri * t_));
  if (J_out_this) *J_out_this = -inv.adjoint();
  return inv;
}

SE3 SE3::compose(const SE3& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  if (J_out_this) J_out_this->setIdentity();
  if (J_out_other) *J_out_other = adjoint();
  return SE3(rot_ * other.rot_, t_ + rot_ * other.t_);
}

SE3::Point SE3::act(const Point& p, PointJacobian* J_out_this, Mat3* J_out_point) const {
  const Point q = rot_ * p + t_;
  if (J_out_this) {
    // d/de [exp(e) q] = e^ q = rho + phi x q = [I, -q^] e.
    J_out_this->leftCols<3>().setIdentity();
    J_out_this->rightCols<3>() = -SO3::hat(q);
  }
  if (J_out_point) *J_out_point = rot_.matrix();
  return q;
}

SE3::Jacobian SE3::adjoint() const {
  const Mat3& R = rot_.matrix();
  Jacobian A = Jacobian::Zero();
  A.topLeftCorner<3, 3>() = R;
  A.bottomRightCorner<3, 3>() = R;
  A.topRightCorner<3, 3>() = SO3::hat(t_) * R;
  return A;
}

SE3::MatrixType SE3::matrix() const {
  MatrixType m = MatrixType::Identity();
  m.topLeftCorner<3, 3>() = rot_.matrix();
  m.topRightCorner<3, 1>() = t_;
  return m;
}

bool SE3::is_approx(const SE3& other, double tol) const { return (matrix() - other.matrix()).norm() <= tol; }

}  // namespace keel::lie
