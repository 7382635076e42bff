// keel::lie — SE(3), rigid motions (eq. 5.1).  Tangent: xi = [rho; phi] (eq. 5.6).
#pragma once

#include <tuple>

#include "so3.hpp"
#include "types.hpp"
#include "core/fields.hpp"

namespace keel::lie {

class SE3 {
 public:
  static constexpr int DoF = 6;
  static constexpr int Dim = 4;
  using Tangent = Vec6;
  using Jacobian = Mat6;
  using MatrixType = Mat4;
  using Point = Vec3;
  using PointJacobian = Eigen::Matrix<double, 3, DoF>;

  SE3() = default;
  SE3(const SO3& rotation, const Vec3& translation) : rot_(rotation), t_(translation) {}

  static SE3 identity() { return SE3(); }
  /// exp([rho; phi]^) = [exp(phi^), J_l(phi) rho; 0, 1] (closed form of eq. 5.7).
  /// J_out_xi = J_l(xi) (left perturbation of the result).
  static SE3 exp(const Tangent& xi, Jacobian* J_out_xi = nullptr);
  /// eq. 5.6
  static MatrixType hat(const Tangent& xi);
  static Tangent vee(const MatrixType& m);
  /// The 6x6 operator of eq. 5.12 (Barfoot & Furgale's "curly hat"): [phi^, rho^; 0, phi^].
  /// It is the matrix of ad_xi, i.e. Ad_{exp(xi)} = exp(curly_hat(xi)).
  static Jacobian curly_hat(const Tangent& xi);
  /// J_l(xi) = [J(phi), Q(rho, phi); 0, J(phi)], J = SO(3) left Jacobian, Q = Barfoot's Q block.
  static Jacobian left_jacobian(const Tangent& xi);
  /// J_r(xi) = J_l(-xi).
  static Jacobian right_jacobian(const Tangent& xi);
  /// [J^-1, -J^-1 Q J^-1; 0, J^-1].
  static Jacobian left_jacobian_inverse(const Tangent& xi);
  static Jacobian right_jacobian_inverse(const Tangent& xi);
  /// Barfoot's Q(rho, phi) block of the SE(3) left Jacobian (series near phi = 0).
  static Mat3 q_block(const Vec3& rho, const Vec3& phi);
  /// Validates the rotation block (see SO3::from_matrix) and the bottom row [0 0 0 1].
  static SE3 from_matrix(const MatrixType& T, double tol = kOrthonormalityTolerance);

  /// xi = [J_l(phi)^-1 t; log(R)].  J_out_this = J_l^-1(xi).
  Tangent log(Jacobian* J_out_this = nullptr) const;
  /// J_out_this = -Ad_{T^-1} (eq. 5.43).
  SE3 inverse(Jacobian* J_out_this = nullptr) const;
  /// J_out_this = I, J_out_other = Ad_this (eq. 5.31).
  SE3 compose(const SE3& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  SE3 operator*(const SE3& other) const { return compose(other); }
  /// R p + t.  J_out_this = [I, -q^] with q = T p; J_out_point = R.
  Point act(const Point& p, PointJacobian* J_out_this = nullptr, Mat3* J_out_point = nullptr) const;
  Point operator*(const Point& p) const { return act(p); }
  /// Ad_T = [R, t^ R; 0, R] for tangent order [rho; phi] (eqs. 5.9-5.10).
  Jacobian adjoint() const;
  MatrixType matrix() const;
  const Mat3& rotation() const { return rot_.matrix(); }
  const SO3& so3() const { return rot_; }
  const Vec3& translation() const { return t_; }
  bool is_approx(const SE3& other, double tol = 1e-9) const;

  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(rot_, t_)

 private:
  SO3 rot_;
  Vec3 t_ = Vec3::Zero();
};

}  // namespace keel::lie
