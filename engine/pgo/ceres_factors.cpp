#include "pgo/ceres_factors.hpp"

#include <cmath>

#include "lie/euler.hpp"

namespace keel::pgo::detail {

Pose2Params to_params(const lie::SE2& T) { return {T.translation()(0), T.translation()(1), T.angle()}; }

lie::SE2 from_params(const Pose2Params& p) { return lie::SE2(p[0], p[1], p[2]); }

Pose3Params to_params(const lie::SE3& T) {
  Eigen::Quaterniond q(T.rotation());
  q.normalize();
  const lie::Vec3& t = T.translation();
  return {q.x(), q.y(), q.z(), q.w(), t(0), t(1), t(2)};
}

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
PoseEdge2Cost::PoseEdge2Cost(const lie::SE2& z, const lie::Mat3& sqrt_information)
    : cz_(z.so2().cos_angle()), sz_(z.so2().sin_angle()), theta_z_(z.angle()), U_(sqrt_information) {
  rzt_tz_ = z.rotation().transpose() * z.translation();
}

bool PoseEdge2Cost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double* pi = parameters[0];
  const double* pj = parameters[1];
  const double c = std::cos(pi[2]), s = std::sin(pi[2]);
  const double dx = pj[0] - pi[0], dy = pj[1] - pi[1];
  const double ux = c * dx + s * dy, uy = -s * dx + c * dy;          // R_iᵀ d
  const double ax = cz_ * ux + sz_ * uy, ay = -sz_ * ux + cz_ * uy;  // A d = R_zᵀ R_iᵀ d
  const lie::Vec3 r(ax - rzt_tz_(0), ay - rzt_tz_(1), lie::wrap_angle(pj[2] - pi[2] - theta_z_));
  Eigen::Map<lie::Vec3> res(residuals);
  res = U_ * r;
  if (!jacobians) return true;
  // A = R_zᵀ R_iᵀ = R(−(θ_i + θ_z)).
  const double ca = cz_ * c - sz_ * s, sa = cz_ * s + sz_ * c;  // cos, sin of θ_i + θ_z
  using RowMat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  if (jacobians[0]) {
    lie::Mat3 J;
    J << -ca, -sa, ay,  //
        sa, -ca, -ax,   //
        0.0, 0.0, -1.0;
    Eigen::Map<RowMat3> Ji(jacobians[0]);
    Ji = U_ * J;
  }
  if (jacobians[1]) {
    lie::Mat3 J;
    J << ca, sa, 0.0,  //
        -sa, ca, 0.0,  //
        0.0, 0.0, 1.0;
    Eigen::Map<RowMat3> Jj(jacobians[1]);
    Jj = U_ * J;
  }
  return true;
}

bool Landmark2Cost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double* p = parameters[0];
  const double* l = parameters[1];
  const double c = std::cos(p[2]), s = std::sin(p[2]);
  const double dx = l[0] - p[0], dy = l[1] - p[1];
  const double vx = c * dx + s * dy, vy = -s * dx + c * dy;  // R_iᵀ (l − t_i)
  Eigen::Map<lie::Vec2> res(residuals);
  res = U_ * lie::Vec2(vx - z_(0), vy - z_(1));
  if (!jacobians) return true;
  if (jacobians[0]) {
    Eigen::Matrix<double, 2, 3> J;
    J << -c, -s, vy,  //
        s, -c, -vx;
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jp(jacobians[0]);
    Jp = U_ * J;
  }
  if (jacobians[1]) {
    lie::Mat2 J;
    J << c, s,  //
        -s, c;
    Eigen::Map<Eigen::Matrix<double, 2, 2, Eigen::RowMajor>> Jl(jacobians[1]);
    Jl = U_ * J;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------------------------
namespace {

Eigen::Quaterniond quaternion_inverse_of(const lie::SE3& z) {
  Eigen::Quaterniond q(z.rotation());
  q.normalize();
  return q.conjugate();
}

}  // namespace

ceres::CostFunction* make_pose_edge3(const lie::SE3& z, const lie::Mat6& U) {
  return new ceres::AutoDiffCostFunction<PoseEdge3Functor, 6, 7, 7>(
      new PoseEdge3Functor{quaternion_inverse_of(z), z.translation(), U});
}

ceres::CostFunction* make_inter_robot2(const lie::SE2& z, const lie::Mat3& U) {
  auto* f = new InterRobot2Functor{{z.translation()(0), z.translation()(1), z.angle()}, U};
  return new ceres::AutoDiffCostFunction<InterRobot2Functor, 3, 3, 3, 3, 3>(f);
}

ceres::CostFunction* make_inter_robot3(const lie::SE3& z, const lie::Mat6& U) {
  return new ceres::AutoDiffCostFunction<InterRobot3Functor, 6, 7, 7, 7, 7>(
      new InterRobot3Functor{quaternion_inverse_of(z), z.translation(), U});
}

}  // namespace keel::pgo::detail
