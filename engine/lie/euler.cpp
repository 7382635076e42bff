#include "euler.hpp"

#include <cmath>

namespace keel::lie {

double wrap_angle(double a) {
  if (!std::isfinite(a)) return a;
  double r = std::remainder(a, kTwoPi);  // in [-pi, pi]
  if (r <= -kPi) r += kTwoPi;
  if (r > kPi) r -= kTwoPi;
  return r;
}

Mat3 rotation_from_rpy(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  Mat3 R;
  R << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return R;
}

Vec3 rpy_from_rotation(const Mat3& R) {
  const double cp = std::hypot(R(0, 0), R(1, 0));
  const double pitch = std::atan2(-R(2, 0), cp);
  double roll = 0.0;
  double yaw = 0.0;
  if (cp < kGimbalLockTolerance) {
    // pitch = +-pi/2: R(0,1) = -sin(yaw -/+ roll), R(1,1) = cos(yaw -/+ roll); choose roll = 0.
    yaw = std::atan2(-R(0, 1), R(1, 1));
  } else {
    roll = std::atan2(R(2, 1), R(2, 2));
    yaw = std::atan2(R(1, 0), R(0, 0));
  }
  return Vec3(wrap_angle(roll), pitch, wrap_angle(yaw));
}

SE3 se3_from_ssc(const Vec6& x) {
  return SE3(SO3::from_matrix_unchecked(rotation_from_rpy(x(3), x(4), x(5))), x.head<3>());
}

Vec6 ssc_from_se3(const SE3& T) {
  Vec6 x;
  x.head<3>() = T.translation();
  x.tail<3>() = rpy_from_rotation(T.rotation());
  return x;
}

SE2 se2_from_ssc(const Vec3& x) { return SE2(x(0), x(1), x(2)); }

Vec3 ssc_from_se2(const SE2& T) {
  return Vec3(T.translation().x(), T.translation().y(), wrap_angle(T.angle()));
}

Mat3 ssc_jacobian_of_left_perturbation(const SE2& T) {
  // exp(ξ^) T = (R_ξ R, R_ξ t + V ρ): to first order t + ρ + θ_ξ (−t_y, t_x) and θ + θ_ξ.
  Mat3 J = Mat3::Identity();
  J(0, 2) = -T.translation()(1);
  J(1, 2) = T.translation()(0);
  return J;
}

}  // namespace keel::lie
