// The residuals that define the measurement convention of pose_graph.hpp, written once per dimension for
// every consumer: the graph's own cost, the Lie-algebra linearization of keel::cov and the Ceres factors of
// keel::pgo (its analytic 2D cost and its automatic-differentiation 3D and inter-robot costs) all evaluate
// the templates below, on poses given as parameter blocks:
//   2D pose: (x, y, θ);
//   3D pose: (q_x, q_y, q_z, q_w, t_x, t_y, t_z), Eigen's quaternion storage order, then the translation.
// The scalar type T is double or a Ceres Jet; this header includes Eigen only, and a Jet's cos, sin, sqrt and
// atan2 are found by argument-dependent lookup where the template is instantiated.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <type_traits>

#include "graph/pose_graph.hpp"
#include "lie/euler.hpp"

namespace keel::graph {

// ---------------------------------------------------------------------------------------------------------------------
// Scalar helpers for the templates.

/// The value of a double or of a Jet's scalar part.
template <class T>
double scalar_part(const T& v) {
  if constexpr (std::is_arithmetic_v<T>)
    return static_cast<double>(v);
  else
    return v.a;
}

/// a − 2πk with k chosen on the scalar part so that the value lies in (−π, π]; a Jet's derivative is
/// untouched.
template <class T>
T wrap_angle(const T& a) {
  if constexpr (std::is_arithmetic_v<T>) {
    return lie::wrap_angle(a);
  } else {
    const double v = scalar_part(a);
    return a + T(lie::wrap_angle(v) - v);
  }
}

// ---------------------------------------------------------------------------------------------------------------------
// 2D edge: r = ρ(z⁻¹ T_i⁻¹ T_j) = (R_zᵀ R_iᵀ (t_j − t_i) − R_zᵀ t_z,  wrap(θ_j − θ_i − θ_z)), θ in (−π, π].

/// What the 2D residual reads of a measurement z, computed once per edge.
struct EdgeMeasurement2 {
  double c = 1.0, s = 0.0, theta = 0.0;  // cos, sin and angle of R_z
  Vec2 rzt_tz = Vec2::Zero();            // R_zᵀ t_z
  EdgeMeasurement2() = default;
  explicit EdgeMeasurement2(const SE2& z)
      : c(z.so2().cos_angle()),
        s(z.so2().sin_angle()),
        theta(z.angle()),
        rzt_tz(z.rotation().transpose() * z.translation()) {}
};

/// The 2D edge residual at pose parameters p_i, p_j (x, y, θ), written to r[0..2]. For T = double, J_i and
/// J_j (row-major 3×3, may be null) receive ∂r/∂p_i and ∂r/∂p_j. With d = t_j − t_i, a = A d, A = R_zᵀ R_iᵀ =
/// R(−(θ_i + θ_z)) and S = [0 −1; 1 0]:
///   ∂r/∂t_i = [−A; 0], ∂r/∂θ_i = [−S a; −1], ∂r/∂t_j = [A; 0], ∂r/∂θ_j = [0; 1].
template <class T>
void edge_residual(const EdgeMeasurement2& z, const T* p_i, const T* p_j, T* r, double* J_i = nullptr,
                   double* J_j = nullptr) {
  using std::cos;
  using std::sin;
  const T c = cos(p_i[2]), s = sin(p_i[2]);
  const T dx = p_j[0] - p_i[0], dy = p_j[1] - p_i[1];
  const T ux = c * dx + s * dy, uy = -s * dx + c * dy;          // R_iᵀ d
  const T ax = z.c * ux + z.s * uy, ay = -z.s * ux + z.c * uy;  // a = R_zᵀ R_iᵀ d
  r[0] = ax - z.rzt_tz(0);
  r[1] = ay - z.rzt_tz(1);
  r[2] = graph::wrap_angle(T(p_j[2] - p_i[2] - z.theta));
  if constexpr (std::is_arithmetic_v<T>) {
    const double ca = z.c * c - z.s * s, sa = z.c * s + z.s * c;  // cos, sin of θ_i + θ_z
    if (J_i) {
      const std::array<double, 9> J{-ca, -sa, ay,   //
                                    sa,  -ca, -ax,  //
                                    0.0, 0.0, -1.0};
      for (int k = 0; k < 9; ++k) J_i[k] = J[static_cast<std::size_t>(k)];
    }
    if (J_j) {
      const std::array<double, 9> J{ca,  sa,  0.0,  //
                                    -sa, ca,  0.0,  //
                                    0.0, 0.0, 1.0};
      for (int k = 0; k < 9; ++k) J_j[k] = J[static_cast<std::size_t>(k)];
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------------
// 3D edge: r = ρ(z⁻¹ T_i⁻¹ T_j) = (t_E, Log R_E), the rotation vector of norm ≤ π.

/// What the 3D residual reads of a measurement z, computed once per edge.
struct EdgeMeasurement3 {
  Eigen::Quaterniond q_inv = Eigen::Quaterniond::Identity();  // R_zᵀ as a unit quaternion
  lie::Vec3 t = lie::Vec3::Zero();                            // t_z
  EdgeMeasurement3() = default;
  explicit EdgeMeasurement3(const SE3& z)
      : q_inv(Eigen::Quaterniond(z.rotation()).normalized().conjugate()), t(z.translation()) {}
};

/// The rotation vector of a unit quaternion q = (w, v), principal: |φ| ≤ π whatever the sign of q. With
/// sin(θ/2) = |v|, cos(θ/2) = w: φ = θ v / |v|, θ = 2 atan2(|v|, w) taken for the sign of w that makes θ ≤ π;
/// at v = 0 the limit φ = 2 v.
template <class T>
void quaternion_to_rotation_vector(const Eigen::Quaternion<T>& q, T* phi) {
  using std::atan2;
  using std::sqrt;
  const T& x = q.x();
  const T& y = q.y();
  const T& zc = q.z();
  const T sin_sq = x * x + y * y + zc * zc;
  T k(2.0);
  if (scalar_part(sin_sq) > 0.0) {
    const T sin_half = sqrt(sin_sq);
    const T& cos_half = q.w();
    const T theta = scalar_part(cos_half) < 0.0 ? T(2.0) * atan2(-sin_half, -cos_half)
                                                : T(2.0) * atan2(sin_half, cos_half);
    k = theta / sin_half;
  }
  phi[0] = x * k;
  phi[1] = y * k;
  phi[2] = zc * k;
}

/// The 3D edge residual at poses (q_i, t_i), (q_j, t_j), written to r[0..5]: t_E = R_zᵀ (R_iᵀ (t_j − t_i) −
/// t_z), q_E = q_z⁻¹ q_i⁻¹ q_j.
template <class T>
void edge_residual(const EdgeMeasurement3& z, const Eigen::Quaternion<T>& q_i,
                   const Eigen::Matrix<T, 3, 1>& t_i, const Eigen::Quaternion<T>& q_j,
                   const Eigen::Matrix<T, 3, 1>& t_j, T* r) {
  const Eigen::Quaternion<T> qi_inv = q_i.conjugate();
  const Eigen::Quaternion<T> qz_inv = z.q_inv.template cast<T>();
  const Eigen::Matrix<T, 3, 1> t_ij = qi_inv * (t_j - t_i);
  const Eigen::Quaternion<T> q_e = qz_inv * (qi_inv * q_j);
  const Eigen::Matrix<T, 3, 1> t_e = qz_inv * (t_ij - z.t.template cast<T>());
  r[0] = t_e(0);
  r[1] = t_e(1);
  r[2] = t_e(2);
  quaternion_to_rotation_vector(q_e, r + 3);
}

/// The same on parameter blocks (q_x, q_y, q_z, q_w, t_x, t_y, t_z).
template <class T>
void edge_residual(const EdgeMeasurement3& z, const T* p_i, const T* p_j, T* r) {
  const Eigen::Map<const Eigen::Quaternion<T>> q_i(p_i), q_j(p_j);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_i(p_i + 4), t_j(p_j + 4);
  edge_residual<T>(z, Eigen::Quaternion<T>(q_i), Eigen::Matrix<T, 3, 1>(t_i), Eigen::Quaternion<T>(q_j),
                   Eigen::Matrix<T, 3, 1>(t_j), r);
}

// ---------------------------------------------------------------------------------------------------------------------
// 2D landmark: r = T⁻¹ l − z = R_iᵀ (l − t_i) − z.

/// The 2D landmark residual at pose parameters p (x, y, θ) and landmark l (x, y), written to r[0..1]. For
/// T = double, J_p (row-major 2×3) and J_l (row-major 2×2), either may be null, receive ∂r/∂p and ∂r/∂l: with
/// v = R_iᵀ (l − t_i), ∂r/∂t_i = −R_iᵀ, ∂r/∂θ_i = −S v = (v_y, −v_x), ∂r/∂l = R_iᵀ.
template <class T>
void landmark_residual(const Vec2& z, const T* p, const T* l, T* r, double* J_p = nullptr,
                       double* J_l = nullptr) {
  using std::cos;
  using std::sin;
  const T c = cos(p[2]), s = sin(p[2]);
  const T dx = l[0] - p[0], dy = l[1] - p[1];
  const T vx = c * dx + s * dy, vy = -s * dx + c * dy;  // R_iᵀ (l − t_i)
  r[0] = vx - z(0);
  r[1] = vy - z(1);
  if constexpr (std::is_arithmetic_v<T>) {
    if (J_p) {
      const std::array<double, 6> J{-c, -s, vy,  //
                                    s,  -c, -vx};
      for (int k = 0; k < 6; ++k) J_p[k] = J[static_cast<std::size_t>(k)];
    }
    if (J_l) {
      const std::array<double, 4> J{c, s,  //
                                    -s, c};
      for (int k = 0; k < 4; ++k) J_l[k] = J[static_cast<std::size_t>(k)];
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------------
// The same residuals on keel's pose types, and their Lie-algebra Jacobians.

/// Pose parameters of the templates above.
std::array<double, 3> pose_parameters(const SE2& T);
std::array<double, 7> pose_parameters(const SE3& T);

/// 2D edge: r = ρ(z⁻¹ T_i⁻¹ T_j) = (x_E, y_E, θ_E), θ_E in (−π, π].
lie::Vec3 edge_residual(const SE2& z, const SE2& T_i, const SE2& T_j);
/// 3D edge: r = ρ(z⁻¹ T_i⁻¹ T_j) = (t_E, Log R_E).
lie::Vec6 edge_residual(const SE3& z, const SE3& T_i, const SE3& T_j);

/// An edge's residual and its Jacobians for left perturbations T_i = exp(ξ_i^) T̄_i, T_j = exp(ξ_j^) T̄_j
/// (thesis eq. 5.14): with E = z⁻¹ T_i⁻¹ T_j, ∂r/∂ξ_j = D(E) Ad(T_j⁻¹) and ∂r/∂ξ_i = −∂r/∂ξ_j, D(E) = ∂ρ(E
/// exp(η^))/∂η at 0.
template <class Vec, class Mat>
struct EdgeLinearization {
  Vec residual = Vec::Zero();
  Mat J_r_xi_i = Mat::Zero();  // ∂r/∂ξ_i
  Mat J_r_xi_j = Mat::Zero();  // ∂r/∂ξ_j
};
using EdgeLinearization2 = EdgeLinearization<lie::Vec3, lie::Mat3>;
using EdgeLinearization3 = EdgeLinearization<lie::Vec6, lie::Mat6>;

/// 2D: ∂r/∂ξ_j = (∂r/∂p_j)(∂p_j/∂ξ_j) with ∂p_j/∂ξ_j = [I, S t_j; 0, 1], which is [A, A S t_j; 0, 1] = D(E)
/// Ad(T_j⁻¹), D(E) = diag(R_E, 1).
EdgeLinearization2 linearize_edge(const SE2& z, const SE2& T_i, const SE2& T_j);
/// 3D: D(E) = blockdiag(R_E, J_r⁻¹(φ)), R_E = Exp(φ), φ the residual's rotation part.
EdgeLinearization3 linearize_edge(const SE3& z, const SE3& T_i, const SE3& T_j);

/// 2D landmark: r = T⁻¹ l − z = Rᵀ (l − t) − z.
Vec2 landmark_residual(const Vec2& z, const SE2& T, const Vec2& l);

/// A landmark measurement's residual and Jacobians: ∂r/∂ξ for T = exp(ξ^) T̄ is −Rᵀ [I₂, S l] (S = [0 −1; 1
/// 0]), ∂r/∂l = Rᵀ (world-frame landmark, additive perturbation).
struct LandmarkLinearization2 {
  Vec2 residual = Vec2::Zero();
  Eigen::Matrix<double, 2, 3> J_r_xi = Eigen::Matrix<double, 2, 3>::Zero();  // ∂r/∂ξ of the observing pose
  lie::Mat2 J_r_l = lie::Mat2::Zero();                                       // ∂r/∂l
};
LandmarkLinearization2 linearize_landmark(const Vec2& z, const SE2& T, const Vec2& l);

}  // namespace keel::graph
