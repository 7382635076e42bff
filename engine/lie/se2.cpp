#include "se2.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "concepts.hpp"
#include "lie_series.hpp"

namespace keel::lie {

static_assert(LieGroup<SE2>);

namespace {

// V(theta) such that the translation of exp([rho; theta]) is V rho.
Mat2 se2_v(double theta) {
  const double at = std::abs(theta);
  const double a = detail::sinc(at);                               // even in theta
  const double b = theta * detail::one_minus_cos_over_theta2(at);  // (1 - cos t)/t, odd
  Mat2 V;
  V << a, -b, b, a;
  return V;
}

// V(theta)^-1 = [(t/2) cot(t/2), t/2; -t/2, (t/2) cot(t/2)].
Mat2 se2_v_inverse(double theta) {
  const double a = detail::half_theta_cot_half_theta(std::abs(theta));
  const double b = 0.5 * theta;
  Mat2 Vi;
  Vi << a, b, -b, a;
  return Vi;
}

// Upper-right column of the left Jacobian.
Vec2 se2_jl_column(const Vec3& xi) {
  const double t = xi(2);
  const double at = std::abs(t);
  const double p = t * detail::theta_minus_sin_over_theta3(at);  // (t - sin t)/t^2 (odd in t)
  const double q = detail::one_minus_cos_over_theta2(at);        // (1 - cos t)/t^2 (even in t)
  return Vec2(xi(0) * p + xi(1) * q, -xi(0) * q + xi(1) * p);
}

}  // namespace

SE2 SE2::exp(const Tangent& xi, Jacobian* J_out_xi) {
  if (J_out_xi) *J_out_xi = left_jacobian(xi);
  return SE2(SO2(xi(2)), se2_v(xi(2)) * xi.head<2>());
}

SE2::MatrixType SE2::hat(const Tangent& xi) {
  MatrixType m;
  m << 0.0, -xi(2), xi(0),  //
      xi(2), 0.0, xi(1),    //
      0.0, 0.0, 0.0;
  return m;
}

SE2::Tangent SE2::vee(const MatrixType& m) { return Tangent(m(0, 2), m(1, 2), 0.5 * (m(1, 0) - m(0, 1))); }

SE2::Jacobian SE2::left_jacobian(const Tangent& xi) {
  Jacobian J = Jacobian::Zero();
  J.topLeftCorner<2, 2>() = se2_v(xi(2));
  J.topRightCorner<2, 1>() = se2_jl_column(xi);
  J(2, 2) = 1.0;
  return J;
}

SE2::Jacobian SE2::right_jacobian(const Tangent& xi) { return left_jacobian(-xi); }

SE2::Jacobian SE2::left_jacobian_inverse(const Tangent& xi) {
  const Mat2 Vi = se2_v_inverse(xi(2));
  Jacobian J = Jacobian::Zero();
  J.topLeftCorner<2, 2>() = Vi;
  J.topRightCorner<2, 1>() = -Vi * se2_jl_column(xi);
  J(2, 2) = 1.0;
  return J;
}

SE2::Jacobian SE2::right_jacobian_inverse(const Tangent& xi) { return left_jacobian_inverse(-xi); }

SE2 SE2::from_matrix(const MatrixType& T, double tol) {
  if (!T.allFinite()) throw std::invalid_argument("SE2::from_matrix: matrix has non-finite entries");
  const double bottom = std::abs(T(2, 0)) + std::abs(T(2, 1)) + std::abs(T(2, 2) - 1.0);
  if (!(bottom <= tol))
    throw std::invalid_argument(
        fmt::format("SE2::from_matrix: bottom row is not [0 0 1] (deviation {:f})", bottom));
  return SE2(SO2::from_matrix(T.topLeftCorner<2, 2>(), tol), T.topRightCorner<2, 1>());
}

SE2::Tangent SE2::log(Jacobian* J_out_this) const {
  const double theta = rot_.angle();
  Tangent xi;
  xi.head<2>() = se2_v_inverse(theta) * t_;
  xi(2) = theta;
  if (J_out_this) *J_out_this = left_jacobian_inverse(xi);
  return xi;
}

SE2 SE2::inverse(Jacobian* J_out_this) const {
  const SO2 ri = rot_.inverse();
  SE2 inv(ri, -(ri * t_));
  if (J_out_this) *J_out_this = -inv.adjoint();
  return inv;
}

SE2 SE2::compose(const SE2& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  if (J_out_this) J_out_this->setIdentity();
  if (J_out_other) *J_out_other = adjoint();
  return SE2(rot_ * other.rot_, t_ + rot_ * other.t_);
}

SE2::Point SE2::act(const Point& p, PointJacobian* J_out_this, Mat2* J_out_point) const {
  const Point q = rot_ * p + t_;
  if (J_out_this) {
    // d/de [exp(e) q] = [I, hat(1) q] with hat(1) q = [-q_y; q_x].
    *J_out_this << 1.0, 0.0, -q.y(),  //
        0.0, 1.0, q.x();
  }
  if (J_out_point) *J_out_point = rot_.matrix();
  return q;
}

SE2::Jacobian SE2::adjoint() const {
  // T [rho; theta]^ T^-1 = [theta J, R rho - theta J t]^, J = hat(1); -J t = [t_y; -t_x].
  Jacobian A = Jacobian::Zero();
  A.topLeftCorner<2, 2>() = rot_.matrix();
  A(0, 2) = t_.y();
  A(1, 2) = -t_.x();
  A(2, 2) = 1.0;
  return A;
}

SE2::MatrixType SE2::matrix() const {
  MatrixType m = MatrixType::Identity();
  m.topLeftCorner<2, 2>() = rot_.matrix();
  m.topRightCorner<2, 1>() = t_;
  return m;
}

bool SE2::is_approx(const SE2& other, double tol) const { return (matrix() - other.matrix()).norm() <= tol; }

}  // namespace keel::lie
