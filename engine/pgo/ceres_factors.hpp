// keel::pgo — the Ceres side of the optimizer: manifolds, cost functions and the kernel adapter.
//
// INTERNAL: this header includes Ceres. It is used by solve.cpp and by the unit tests only; the facade
// pgo.cppm and every public header stay free of Ceres (shared design card: a facade that pulls in Ceres
// breaks importers).
//
// Parameter blocks:
//   2D pose:     double[3] = (x, y, θ), manifold Se2Manifold (additive, θ wrapped to (−π, π]);
//   2D landmark: double[2] = (x, y), Euclidean;
//   3D pose:     double[7] = (q_x, q_y, q_z, q_w, t_x, t_y, t_z): Eigen's quaternion storage order, then the
//                translation; manifold ProductManifold<EigenQuaternionManifold, EuclideanManifold<3>>.
// Residuals are those of pose_graph.hpp, whitened by U with Ω = UᵀU (internal.hpp: sqrt_information).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/jet.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/product_manifold.h>
#include <ceres/rotation.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "lie/euler.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"
#include "pgo/options.hpp"
#include "pgo/robust.hpp"

namespace keel::pgo::detail {

// ---------------------------------------------------------------------------------------------------------------
// Parameter conversions.
using Pose2Params = std::array<double, 3>;
using Pose3Params = std::array<double, 7>;

Pose2Params to_params(const lie::SE2& T);
lie::SE2 from_params(const Pose2Params& p);
Pose3Params to_params(const lie::SE3& T);
lie::SE3 from_params(const Pose3Params& p);

// ---------------------------------------------------------------------------------------------------------------
// SE(2) as R² × S¹ with (x, y, θ): x ⊞ δ = x + δ with θ wrapped, y ⊟ x = y − x with the angle difference
// wrapped. Both Jacobians are the identity.
class Se2Manifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 3; }
  int TangentSize() const override { return 3; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

using Se3Manifold = ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>;

// ---------------------------------------------------------------------------------------------------------------
// 2D pose–pose edge with analytic Jacobians. With d = t_j − t_i and A = R_zᵀ R_iᵀ:
//   r = (A d − R_zᵀ t_z,  wrap(θ_j − θ_i − θ_z)),
//   ∂r/∂t_i = [−A; 0], ∂r/∂θ_i = [−S A d; −1], ∂r/∂t_j = [A; 0], ∂r/∂θ_j = [0; 1],  S = [0 −1; 1 0];
// everything is multiplied by U.
class PoseEdge2Cost final : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  PoseEdge2Cost(const lie::SE2& z, const lie::Mat3& sqrt_information);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  double cz_, sz_, theta_z_;  // cos, sin, angle of z
  lie::Vec2 rzt_tz_;          // R_zᵀ t_z
  lie::Mat3 U_;
};

// 2D landmark measurement with analytic Jacobians: r = R_iᵀ (l − t_i) − z,
//   ∂r/∂t_i = −R_iᵀ, ∂r/∂θ_i = −S R_iᵀ (l − t_i), ∂r/∂l = R_iᵀ; multiplied by U.
class Landmark2Cost final : public ceres::SizedCostFunction<2, 3, 2> {
 public:
  Landmark2Cost(const lie::Vec2& z, const lie::Mat2& sqrt_information) : z_(z), U_(sqrt_information) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  lie::Vec2 z_;
  lie::Mat2 U_;
};

// ---------------------------------------------------------------------------------------------------------------
// Templated residuals for automatic differentiation.
template <class T>
double scalar_part(const T& v) {
  if constexpr (std::is_arithmetic_v<T>)
    return static_cast<double>(v);
  else
    return v.a;
}

// a − 2πk with k chosen on the scalar part so the value lies in (−π, π]; the derivative is untouched.
template <class T>
T wrap_angle_t(const T& a) {
  const double v = scalar_part(a);
  const double w = lie::wrap_angle(v);
  return a + T(w - v);
}

// 2D: residual of z at global poses G_i, G_j given as (x, y, θ).
template <class T>
void pose_edge2_residual(const double z[3], const T* gi, const T* gj, T* r) {
  using std::cos;
  using std::sin;
  const T c = cos(gi[2]), s = sin(gi[2]);
  const T dx = gj[0] - gi[0], dy = gj[1] - gi[1];
  const T ux = c * dx + s * dy, uy = -s * dx + c * dy;  // R_iᵀ (t_j − t_i)
  const double cz = std::cos(z[2]), sz = std::sin(z[2]);
  const T ex = ux - T(z[0]), ey = uy - T(z[1]);
  r[0] = cz * ex + sz * ey;
  r[1] = -sz * ex + cz * ey;
  r[2] = wrap_angle_t(T(gj[2] - gi[2] - T(z[2])));
}

// 2D composition Δ T of (x, y, θ) triples.
template <class T>
void compose2(const T* a, const T* b, T* out) {
  using std::cos;
  using std::sin;
  const T c = cos(a[2]), s = sin(a[2]);
  out[0] = a[0] + c * b[0] - s * b[1];
  out[1] = a[1] + s * b[0] + c * b[1];
  out[2] = a[2] + b[2];
}

// Inter-robot 2D edge: parameters Δ_a, T^a_i, Δ_b, T^b_j.
struct InterRobot2Functor {
  double z[3];
  lie::Mat3 U;
  template <class T>
  bool operator()(const T* da, const T* ti, const T* db, const T* tj, T* out) const {
    T gi[3], gj[3], r[3];
    compose2(da, ti, gi);
    compose2(db, tj, gj);
    pose_edge2_residual(z, gi, gj, r);
    for (int k = 0; k < 3; ++k) out[k] = T(U(k, 0)) * r[0] + T(U(k, 1)) * r[1] + T(U(k, 2)) * r[2];
    return true;
  }
};

// 3D: residual of z at global poses given as quaternion + translation.
template <class T>
void pose_edge3_residual(const Eigen::Quaterniond& qz_inv, const lie::Vec3& tz,
                         const Eigen::Quaternion<T>& qi, const Eigen::Matrix<T, 3, 1>& ti,
                         const Eigen::Quaternion<T>& qj, const Eigen::Matrix<T, 3, 1>& tj, T* r) {
  const Eigen::Quaternion<T> qi_inv = qi.conjugate();
  const Eigen::Quaternion<T> qz_inv_t = qz_inv.template cast<T>();
  const Eigen::Matrix<T, 3, 1> t_ij = qi_inv * (tj - ti);
  const Eigen::Quaternion<T> q_e = qz_inv_t * (qi_inv * qj);
  const Eigen::Matrix<T, 3, 1> t_e = qz_inv_t * (t_ij - tz.template cast<T>());
  const T q[4] = {q_e.w(), q_e.x(), q_e.y(), q_e.z()};
  T phi[3];
  ceres::QuaternionToAngleAxis(q, phi);  // principal: |φ| ≤ π whatever the sign of q
  r[0] = t_e(0);
  r[1] = t_e(1);
  r[2] = t_e(2);
  r[3] = phi[0];
  r[4] = phi[1];
  r[5] = phi[2];
}

struct PoseEdge3Functor {
  Eigen::Quaterniond qz_inv;
  lie::Vec3 tz;
  lie::Mat6 U;
  template <class T>
  bool operator()(const T* pi, const T* pj, T* out) const {
    const Eigen::Map<const Eigen::Quaternion<T>> qi(pi), qj(pj);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> ti(pi + 4), tj(pj + 4);
    T r[6];
    pose_edge3_residual<T>(qz_inv, tz, qi, ti, qj, tj, r);
    for (int k = 0; k < 6; ++k) {
      out[k] = T(0.0);
      for (int l = 0; l < 6; ++l) out[k] += T(U(k, l)) * r[l];
    }
    return true;
  }
};

// Inter-robot 3D edge: parameters Δ_a, T^a_i, Δ_b, T^b_j.
struct InterRobot3Functor {
  Eigen::Quaterniond qz_inv;
  lie::Vec3 tz;
  lie::Mat6 U;
  template <class T>
  bool operator()(const T* da, const T* pi, const T* db, const T* pj, T* out) const {
    const Eigen::Map<const Eigen::Quaternion<T>> qa(da), qi(pi), qb(db), qj(pj);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> ta(da + 4), ti(pi + 4), tb(db + 4), tj(pj + 4);
    const Eigen::Quaternion<T> gqi = qa * qi, gqj = qb * qj;
    const Eigen::Matrix<T, 3, 1> gti = ta + qa * ti, gtj = tb + qb * tj;
    T r[6];
    pose_edge3_residual<T>(qz_inv, tz, gqi, gti, gqj, gtj, r);
    for (int k = 0; k < 6; ++k) {
      out[k] = T(0.0);
      for (int l = 0; l < 6; ++l) out[k] += T(U(k, l)) * r[l];
    }
    return true;
  }
};

ceres::CostFunction* make_pose_edge3(const lie::SE3& z, const lie::Mat6& U);
ceres::CostFunction* make_inter_robot2(const lie::SE2& z, const lie::Mat3& U);
ceres::CostFunction* make_inter_robot3(const lie::SE3& z, const lie::Mat6& U);

// ---------------------------------------------------------------------------------------------------------------
// The robust kernels of robust.hpp as a Ceres loss (ρ of the squared whitened residual).
class KernelLoss final : public ceres::LossFunction {
 public:
  KernelLoss(RobustKernel kernel, double parameter) : kernel_(kernel), parameter_(parameter) {}
  void Evaluate(double sq_norm, double out[3]) const override {
    const Rho r = robust_rho(kernel_, parameter_, sq_norm);
    out[0] = r.rho;
    // Ceres requires ρ' > 0 (its corrector aborts otherwise); a weight that underflows for a huge χ² (a
    // residual far out on the kernel's tail) is held at the smallest normal double instead of 0.
    constexpr double tiny = std::numeric_limits<double>::min();
    out[1] = r.d1 > tiny ? r.d1 : tiny;
    out[2] = std::isfinite(r.d2) ? r.d2 : 0.0;
  }

 private:
  RobustKernel kernel_;
  double parameter_;
};

}  // namespace keel::pgo::detail
