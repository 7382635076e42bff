#include "so3.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "concepts.hpp"
#include "lie_series.hpp"

namespace keel::lie {

static_assert(LieGroup<SO3>);

SO3 SO3::exp(const Tangent& phi, Jacobian* J_out_phi) {
  const double theta = phi.norm();
  const Mat3 W = hat(phi);
  const Mat3 W2 = W * W;
  Mat3 R = Mat3::Identity() + detail::sinc(theta) * W + detail::one_minus_cos_over_theta2(theta) * W2;
  if (J_out_phi) *J_out_phi = left_jacobian(phi);
  return SO3(R);
}

SO3::MatrixType SO3::hat(const Tangent& phi) {
  MatrixType m;
  m << 0.0, -phi.z(), phi.y(),  //
      phi.z(), 0.0, -phi.x(),   //
      -phi.y(), phi.x(), 0.0;
  return m;
}

SO3::Tangent SO3::vee(const MatrixType& omega) {
  return Tangent(0.5 * (omega(2, 1) - omega(1, 2)), 0.5 * (omega(0, 2) - omega(2, 0)),
                 0.5 * (omega(1, 0) - omega(0, 1)));
}

SO3::Jacobian SO3::left_jacobian(const Tangent& phi) {
  const double theta = phi.norm();
  const Mat3 W = hat(phi);
  return Mat3::Identity() + detail::one_minus_cos_over_theta2(theta) * W +
         detail::theta_minus_sin_over_theta3(theta) * (W * W);
}

SO3::Jacobian SO3::right_jacobian(const Tangent& phi) { return left_jacobian(-phi); }

SO3::Jacobian SO3::left_jacobian_inverse(const Tangent& phi) {
  const double theta = phi.norm();
  const Mat3 W = hat(phi);
  return Mat3::Identity() - 0.5 * W + detail::jl_inverse_coeff(theta) * (W * W);
}

SO3::Jacobian SO3::right_jacobian_inverse(const Tangent& phi) { return left_jacobian_inverse(-phi); }

SO3 SO3::from_matrix(const MatrixType& R, double tol) {
  if (!R.allFinite()) throw std::invalid_argument("SO3::from_matrix: matrix has non-finite entries");
  const double err = (R.transpose() * R - Mat3::Identity()).norm();
  if (!(err <= tol))
    throw std::invalid_argument(fmt::format(
        "SO3::from_matrix: matrix is not orthonormal (||R^T R - I||_F = {:f}, tolerance {:f})", err, tol));
  if (R.determinant() <= 0.0)
    throw std::invalid_argument("SO3::from_matrix: det(R) <= 0 (reflection, not a rotation)");
  // Project onto SO(3): nearest rotation in Frobenius norm, U diag(1,1,det(UV^T)) V^T.
  Eigen::JacobiSVD<Mat3> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return SO3(svd.matrixU() * D * svd.matrixV().transpose());
}

SO3 SO3::from_matrix_unchecked(const MatrixType& R) { return SO3(R); }

SO3::Tangent SO3::log(Jacobian* J_out_this) const {
  // R = cos(t) I + (1 - cos t) a a^T + sin(t) a^.
  const double c = std::clamp(0.5 * (R_.trace() - 1.0), -1.0, 1.0);
  const Vec3 w = vee(R_);  // = sin(t) a (from the skew part)
  const double s = w.norm();
  const double theta = std::atan2(s, c);  // accurate in [0, pi] unlike acos
  Tangent phi;
  if (theta < 2.0) {
    // phi = t / sin(t) * w; sinc is evaluated by series near 0.
    phi = w / detail::sinc(theta);
  } else {
    // Near pi, sin(t) -> 0 and the skew part carries no reliable axis information.
    // The symmetric part gives (1 - cos t) a a^T = (R + R^T)/2 - cos(t) I.
    const Mat3 S = 0.5 * (R_ + R_.transpose()) - c * Mat3::Identity();
    Eigen::Index k = 0;
    S.diagonal().maxCoeff(&k);
    Vec3 a = S.col(k) / std::sqrt(S(k, k));
    a.normalize();
    // The symmetric part fixes the axis only up to sign; sin(t) >= 0 so a . w >= 0.
    if (a.dot(w) < 0.0) a = -a;
    phi = theta * a;
  }
  if (J_out_this) *J_out_this = left_jacobian_inverse(phi);
  return phi;
}

SO3 SO3::inverse(Jacobian* J_out_this) const {
  if (J_out_this) *J_out_this = -R_.transpose();
  return SO3(R_.transpose());
}

SO3 SO3::compose(const SO3& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  if (J_out_this) J_out_this->setIdentity();
  if (J_out_other) *J_out_other = R_;
  return SO3(R_ * other.R_);
}

SO3::Point SO3::act(const Point& p, PointJacobian* J_out_this, Mat3* J_out_point) const {
  const Point q = R_ * p;
  // d/de [exp(e) q] = e^ q = -q^ e.
  if (J_out_this) *J_out_this = -hat(q);
  if (J_out_point) *J_out_point = R_;
  return q;
}

bool SO3::is_approx(const SO3& other, double tol) const { return (R_ - other.R_).norm() <= tol; }

}  // namespace keel::lie
