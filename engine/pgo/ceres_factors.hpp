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
// Residuals are graph/residuals.hpp's, whitened by U with Ω = UᵀU (internal.hpp: sqrt_information).
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

#include "graph/residuals.hpp"
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
// 2D pose–pose edge with the analytic Jacobians of graph::edge_residual (graph/residuals.hpp), multiplied by
// U.
class PoseEdge2Cost final : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  PoseEdge2Cost(const lie::SE2& z, const lie::Mat3& sqrt_information) : z_(z), U_(sqrt_information) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  graph::EdgeMeasurement2 z_;
  lie::Mat3 U_;
};

// 2D landmark measurement with the analytic Jacobians of graph::landmark_residual, multiplied by U.
class Landmark2Cost final : public ceres::SizedCostFunction<2, 3, 2> {
 public:
  Landmark2Cost(const lie::Vec2& z, const lie::Mat2& sqrt_information) : z_(z), U_(sqrt_information) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  lie::Vec2 z_;
  lie::Mat2 U_;
};

// ---------------------------------------------------------------------------------------------------------------
// Automatic differentiation of graph::edge_residual (graph/residuals.hpp).

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
  graph::EdgeMeasurement2 z;
  lie::Mat3 U;
  template <class T>
  bool operator()(const T* da, const T* ti, const T* db, const T* tj, T* out) const {
    T gi[3], gj[3], r[3];
    compose2(da, ti, gi);
    compose2(db, tj, gj);
    graph::edge_residual(z, gi, gj, r);
    for (int k = 0; k < 3; ++k) out[k] = T(U(k, 0)) * r[0] + T(U(k, 1)) * r[1] + T(U(k, 2)) * r[2];
    return true;
  }
};

struct PoseEdge3Functor {
  graph::EdgeMeasurement3 z;
  lie::Mat6 U;
  template <class T>
  bool operator()(const T* pi, const T* pj, T* out) const {
    T r[6];
    graph::edge_residual(z, pi, pj, r);
    for (int k = 0; k < 6; ++k) {
      out[k] = T(0.0);
      for (int l = 0; l < 6; ++l) out[k] += T(U(k, l)) * r[l];
    }
    return true;
  }
};

// Inter-robot 3D edge: parameters Δ_a, T^a_i, Δ_b, T^b_j.
struct InterRobot3Functor {
  graph::EdgeMeasurement3 z;
  lie::Mat6 U;
  template <class T>
  bool operator()(const T* da, const T* pi, const T* db, const T* pj, T* out) const {
    const Eigen::Map<const Eigen::Quaternion<T>> qa(da), qi(pi), qb(db), qj(pj);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> ta(da + 4), ti(pi + 4), tb(db + 4), tj(pj + 4);
    const Eigen::Quaternion<T> gqi = qa * qi, gqj = qb * qj;
    const Eigen::Matrix<T, 3, 1> gti = ta + qa * ti, gtj = tb + qb * tj;
    T r[6];
    graph::edge_residual<T>(z, gqi, gti, gqj, gtj, r);
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
