// keel::lie — SE(2), planar rigid motions.  Tangent: [rho_x, rho_y, theta].
#pragma once

#include <tuple>

#include "so2.hpp"
#include "types.hpp"
#include "core/fields.hpp"

namespace keel::lie {

class SE2 {
 public:
  static constexpr int DoF = 3;
  static constexpr int Dim = 3;
  using Tangent = Vec3;
  using Jacobian = Mat3;
  using MatrixType = Mat3;
  using Point = Vec2;
  using PointJacobian = Eigen::Matrix<double, 2, DoF>;

  SE2() = default;
  SE2(const SO2& rotation, const Vec2& translation) : rot_(rotation), t_(translation) {}
  SE2(double x, double y, double theta) : rot_(theta), t_(x, y) {}

  static SE2 identity() { return SE2(); }
  /// exp([rho; theta]) = [R(theta), V(theta) rho; 0, 1],
  /// V = [sin t / t, -(1 - cos t)/t; (1 - cos t)/t, sin t / t].  J_out_xi = J_l(xi).
  static SE2 exp(const Tangent& xi, Jacobian* J_out_xi = nullptr);
  static MatrixType hat(const Tangent& xi);
  static Tangent vee(const MatrixType& m);
  /// J_l = [V(theta), w; 0, 1] with
  /// w = [rho_x (t - sin t)/t^2 + rho_y (1 - cos t)/t^2; -rho_x (1 - cos t)/t^2 + rho_y (t - sin t)/t^2].
  static Jacobian left_jacobian(const Tangent& xi);
  /// J_r(xi) = J_l(-xi).
  static Jacobian right_jacobian(const Tangent& xi);
  /// [V^-1, -V^-1 w; 0, 1].
  static Jacobian left_jacobian_inverse(const Tangent& xi);
  static Jacobian right_jacobian_inverse(const Tangent& xi);
  /// Validates the rotation block (see SO2::from_matrix) and the bottom row [0 0 1].
  static SE2 from_matrix(const MatrixType& T, double tol = kOrthonormalityTolerance);

  /// theta in (-pi, pi], rho = V(theta)^-1 t.  J_out_this = J_l^-1(log T).
  Tangent log(Jacobian* J_out_this = nullptr) const;
  /// J_out_this = -Ad_{T^-1}.
  SE2 inverse(Jacobian* J_out_this = nullptr) const;
  /// J_out_this = I, J_out_other = Ad_this.
  SE2 compose(const SE2& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  SE2 operator*(const SE2& other) const { return compose(other); }
  /// R p + t.  J_out_this = [I, hat(1) q] with q = T p; J_out_point = R.
  Point act(const Point& p, PointJacobian* J_out_this = nullptr, Mat2* J_out_point = nullptr) const;
  Point operator*(const Point& p) const { return act(p); }
  /// Ad_T = [R, [t_y; -t_x]; 0, 1] for tangent order [rho; theta].
  Jacobian adjoint() const;
  MatrixType matrix() const;
  Mat2 rotation() const { return rot_.matrix(); }
  const SO2& so2() const { return rot_; }
  const Vec2& translation() const { return t_; }
  double angle() const { return rot_.angle(); }
  bool is_approx(const SE2& other, double tol = 1e-9) const;

  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(rot_, t_)

 private:
  SO2 rot_;
  Vec2 t_ = Vec2::Zero();
};

}  // namespace keel::lie
