// keel::lie — SO(3), 3D rotations.  Tangent: phi (rotation vector).
#pragma once

#include <tuple>

#include "types.hpp"
#include "core/fields.hpp"

namespace keel::lie {

class SO3 {
 public:
  static constexpr int DoF = 3;
  static constexpr int Dim = 3;
  using Tangent = Vec3;
  using Jacobian = Mat3;
  using MatrixType = Mat3;
  using Point = Vec3;
  using PointJacobian = Mat3;

  SO3() = default;

  static SO3 identity() { return SO3(); }
  /// Rodrigues' formula, R = I + sin(t)/t phi^ + (1-cos t)/t^2 phi^ phi^ (series near 0).
  /// J_out_phi = J_l(phi) (left perturbation of the result).
  static SO3 exp(const Tangent& phi, Jacobian* J_out_phi = nullptr);
  /// eq. 5.4
  static MatrixType hat(const Tangent& phi);
  /// Inverse of hat (uses the skew-symmetric part of the argument).
  static Tangent vee(const MatrixType& omega);
  /// J_l(phi) = I + (1-cos t)/t^2 phi^ + (t - sin t)/t^3 phi^ phi^.
  static Jacobian left_jacobian(const Tangent& phi);
  /// J_r(phi) = J_l(-phi).
  static Jacobian right_jacobian(const Tangent& phi);
  /// J_l^-1(phi) = I - phi^/2 + (1/t^2 - (1 + cos t)/(2 t sin t)) phi^ phi^ (singular at |phi| = 2 pi).
  static Jacobian left_jacobian_inverse(const Tangent& phi);
  static Jacobian right_jacobian_inverse(const Tangent& phi);
  /// Validates orthonormality within `tol` (Frobenius norm of R^T R - I) and det > 0;
  /// then projects onto SO(3) (SVD).  Throws std::invalid_argument otherwise.
  static SO3 from_matrix(const MatrixType& R, double tol = kOrthonormalityTolerance);
  /// No validation: the caller guarantees that R is a rotation matrix to machine precision.
  static SO3 from_matrix_unchecked(const MatrixType& R);

  /// Principal logarithm, |phi| in [0, pi].  Stable near 0 (series) and near pi (the axis is
  /// taken from the symmetric part of R).  J_out_this = J_l^-1(phi) (left perturbation).
  Tangent log(Jacobian* J_out_this = nullptr) const;
  /// J_out_this = -Ad_{R^-1} = -R^T.
  SO3 inverse(Jacobian* J_out_this = nullptr) const;
  /// J_out_this = I, J_out_other = Ad_this = R.
  SO3 compose(const SO3& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  SO3 operator*(const SO3& other) const { return compose(other); }
  /// R p.  J_out_this = -(R p)^, J_out_point = R.
  Point act(const Point& p, PointJacobian* J_out_this = nullptr, Mat3* J_out_point = nullptr) const;
  Point operator*(const Point& p) const { return act(p); }
  /// Ad_R = R (eqs. 5.9-5.10).
  Jacobian adjoint() const { return R_; }
  const MatrixType& matrix() const { return R_; }
  const Mat3& rotation() const { return R_; }
  bool is_approx(const SO3& other, double tol = 1e-9) const;

  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(R_)

 private:
  explicit SO3(const Mat3& R) : R_(R) {}
  Mat3 R_ = Mat3::Identity();
};

}  // namespace keel::lie
