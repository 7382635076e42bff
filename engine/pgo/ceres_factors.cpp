#include "pgo/ceres_factors.hpp"

#include <cmath>

#include "lie/euler.hpp"

namespace keel::pgo::detail {

Pose2Params to_params(const lie::SE2& T) { return graph::pose_parameters(T); }

lie::SE2 from_params(const Pose2Params& p) { return lie::SE2(p[0], p[1], p[2]); }

Pose3Params to_params(const lie::SE3& T) { return graph::pose_parameters(T); }

lie::SE3 from_params(const Pose3Params& p) {
  const Eigen::Quaterniond q = Eigen::Quaterniond(p[3], p[0], p[1], p[2]).normalized();
  return lie::SE3(lie::SO3::from_matrix_unchecked(q.toRotationMatrix()), lie::Vec3(p[4], p[5], p[6]));
}

// ---------------------------------------------------------------------------------------------------------------
bool Se2Manifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  x_plus_delta[0] = x[0] + delta[0];
  x_plus_delta[1] = x[1] + delta[1];
  x_plus_delta[2] = lie::wrap_angle(x[2] + delta[2]);
  return true;
}

bool Se2Manifold::PlusJacobian(const double*, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(jacobian);
  J.setIdentity();
  return true;
}

bool Se2Manifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  y_minus_x[0] = y[0] - x[0];
  y_minus_x[1] = y[1] - x[1];
  y_minus_x[2] = lie::wrap_angle(y[2] - x[2]);
  return true;
}

bool Se2Manifold::MinusJacobian(const double*, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(jacobian);
  J.setIdentity();
  return true;
}

// ---------------------------------------------------------------------------------------------------------------
bool PoseEdge2Cost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  using RowMat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  lie::Vec3 r;
  RowMat3 J_i, J_j;
  const bool want_i = jacobians && jacobians[0], want_j = jacobians && jacobians[1];
  graph::edge_residual(z_, parameters[0], parameters[1], r.data(), want_i ? J_i.data() : nullptr,
                       want_j ? J_j.data() : nullptr);
  Eigen::Map<lie::Vec3> res(residuals);
  res = U_ * r;
  if (want_i) {
    Eigen::Map<RowMat3> Ji(jacobians[0]);
    Ji = U_ * J_i;
  }
  if (want_j) {
    Eigen::Map<RowMat3> Jj(jacobians[1]);
    Jj = U_ * J_j;
  }
  return true;
}

bool Landmark2Cost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  lie::Vec2 r;
  Eigen::Matrix<double, 2, 3, Eigen::RowMajor> J_p;
  Eigen::Matrix<double, 2, 2, Eigen::RowMajor> J_l;
  const bool want_p = jacobians && jacobians[0], want_l = jacobians && jacobians[1];
  graph::landmark_residual(z_, parameters[0], parameters[1], r.data(), want_p ? J_p.data() : nullptr,
                           want_l ? J_l.data() : nullptr);
  Eigen::Map<lie::Vec2> res(residuals);
  res = U_ * r;
  if (want_p) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jp(jacobians[0]);
    Jp = U_ * J_p;
  }
  if (want_l) {
    Eigen::Map<Eigen::Matrix<double, 2, 2, Eigen::RowMajor>> Jl(jacobians[1]);
    Jl = U_ * J_l;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------------------------
ceres::CostFunction* make_pose_edge3(const lie::SE3& z, const lie::Mat6& U) {
  return new ceres::AutoDiffCostFunction<PoseEdge3Functor, 6, 7, 7>(
      new PoseEdge3Functor{graph::EdgeMeasurement3(z), U});
}

ceres::CostFunction* make_inter_robot2(const lie::SE2& z, const lie::Mat3& U) {
  auto* f = new InterRobot2Functor{graph::EdgeMeasurement2(z), U};
  return new ceres::AutoDiffCostFunction<InterRobot2Functor, 3, 3, 3, 3, 3>(f);
}

ceres::CostFunction* make_inter_robot3(const lie::SE3& z, const lie::Mat6& U) {
  return new ceres::AutoDiffCostFunction<InterRobot3Functor, 6, 7, 7, 7, 7>(
      new InterRobot3Functor{graph::EdgeMeasurement3(z), U});
}

}  // namespace keel::pgo::detail
