#include "so2.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

#include "concepts.hpp"

namespace keel::lie {

static_assert(LieGroup<SO2>);

SO2::SO2(double theta) : c_(std::cos(theta)), s_(std::sin(theta)) {}

SO2 SO2::exp(const Tangent& theta, Jacobian* J_out_theta) {
  if (J_out_theta) J_out_theta->setIdentity();
  return SO2(theta(0));
}

SO2::MatrixType SO2::hat(const Tangent& theta) {
  MatrixType m;
  m << 0.0, -theta(0), theta(0), 0.0;
  return m;
}

SO2::Tangent SO2::vee(const MatrixType& omega) {
  Tangent t;
  t(0) = 0.5 * (omega(1, 0) - omega(0, 1));
  return t;
}

SO2 SO2::from_matrix(const MatrixType& R, double tol) {
  if (!R.allFinite()) throw std::invalid_argument("SO2::from_matrix: matrix has non-finite entries");
  const double err = (R.transpose() * R - Mat2::Identity()).norm();
  if (!(err <= tol))
    throw std::invalid_argument(
        fmt::format("SO2::from_matrix: matrix is not orthonormal (||R^T R - I||_F = {:f})", err));
  if (R.determinant() <= 0.0)
    throw std::invalid_argument("SO2::from_matrix: det(R) <= 0 (reflection, not a rotation)");
  return SO2(std::atan2(R(1, 0) - R(0, 1), R(0, 0) + R(1, 1)));
}

double SO2::angle() const {
  double a = std::atan2(s_, c_);
  if (a <= -kPi) a += kTwoPi;  // map -pi to +pi so the range is (-pi, pi]
  return a;
}

SO2::Tangent SO2::log(Jacobian* J_out_this) const {
  if (J_out_this) J_out_this->setIdentity();
  Tangent t;
  t(0) = angle();
  return t;
}

SO2 SO2::inverse(Jacobian* J_out_this) const {
  // (exp(e) R)^-1 = R^-1 exp(-e) = exp(-Ad_{R^-1} e) R^-1, Ad = 1.
  if (J_out_this) *J_out_this = -Jacobian::Identity();
  SO2 r;
  r.c_ = c_;
  r.s_ = -s_;
  return r;
}

SO2 SO2::compose(const SO2& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  if (J_out_this) J_out_this->setIdentity();
  if (J_out_other) J_out_other->setIdentity();  // Ad_this = 1
  SO2 r;
  r.c_ = c_ * other.c_ - s_ * other.s_;
  r.s_ = s_ * other.c_ + c_ * other.s_;
  // Keep (c, s) on the unit circle despite round-off accumulation.
  const double n = std::hypot(r.c_, r.s_);
  r.c_ /= n;
  r.s_ /= n;
  return r;
}

SO2::Point SO2::act(const Point& p, PointJacobian* J_out_this, Mat2* J_out_point) const {
  const Point q(c_ * p.x() - s_ * p.y(), s_ * p.x() + c_ * p.y());
  // d/de [exp(e) q] at e = 0 is hat(1) q = [-q_y, q_x]^T.
  if (J_out_this) *J_out_this << -q.y(), q.x();
  if (J_out_point) *J_out_point = matrix();
  return q;
}

SO2::MatrixType SO2::matrix() const {
  MatrixType m;
  m << c_, -s_, s_, c_;
  return m;
}

bool SO2::is_approx(const SO2& other, double tol) const { return (matrix() - other.matrix()).norm() <= tol; }

}  // namespace keel::lie
