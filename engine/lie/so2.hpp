// keel::lie — SO(2), planar rotations.  Tangent: theta (1-vector).
#pragma once

#include <tuple>

#include "types.hpp"
#include "core/fields.hpp"

namespace keel::lie {

class SO2 {
 public:
  static constexpr int DoF = 1;
  static constexpr int Dim = 2;
  using Tangent = Vec1;
  using Jacobian = Mat1;
  using MatrixType = Mat2;
  using Point = Vec2;
  using PointJacobian = Eigen::Matrix<double, 2, DoF>;

  SO2() = default;
  /// Rotation by `theta` radians.
  explicit SO2(double theta);

  static SO2 identity() { return SO2(); }
  static SO2 exp(const Tangent& theta, Jacobian* J_out_theta = nullptr);
  static MatrixType hat(const Tangent& theta);
  static Tangent vee(const MatrixType& omega);
  /// SO(2) is abelian: every Jacobian is the 1x1 identity.
  static Jacobian left_jacobian(const Tangent&) { return Jacobian::Identity(); }
  static Jacobian right_jacobian(const Tangent&) { return Jacobian::Identity(); }
  static Jacobian left_jacobian_inverse(const Tangent&) { return Jacobian::Identity(); }
  static Jacobian right_jacobian_inverse(const Tangent&) { return Jacobian::Identity(); }
  /// Validates R^T R = I (within `tol`, Frobenius) and det R > 0, then projects exactly
  /// onto SO(2).  Throws std::invalid_argument otherwise.
  static SO2 from_matrix(const MatrixType& R, double tol = kOrthonormalityTolerance);

  /// Angle in (-pi, pi].  J_out_this (left perturbation) is 1.
  Tangent log(Jacobian* J_out_this = nullptr) const;
  double angle() const;
  SO2 inverse(Jacobian* J_out_this = nullptr) const;
  SO2 compose(const SO2& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  SO2 operator*(const SO2& other) const { return compose(other); }
  Point act(const Point& p, PointJacobian* J_out_this = nullptr, Mat2* J_out_point = nullptr) const;
  Point operator*(const Point& p) const { return act(p); }
  Jacobian adjoint() const { return Jacobian::Identity(); }
  MatrixType matrix() const;
  MatrixType rotation() const { return matrix(); }
  double cos_angle() const { return c_; }
  double sin_angle() const { return s_; }
  bool is_approx(const SO2& other, double tol = 1e-9) const;

  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(c_, s_)

 private:
  double c_ = 1.0;
  double s_ = 0.0;
};

}  // namespace keel::lie
