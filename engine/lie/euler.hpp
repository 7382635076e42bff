// keel::lie — the Euler-angle (SSC) parameter vectors of eq. 5.15 and their
// conversion to/from the groups.
//
// SE(3): x = [x y z roll pitch yaw], R = Rz(yaw) Ry(pitch) Rx(roll) (eq. 5.15).
// SE(2): x = [x y theta].
#pragma once

#include "se2.hpp"
#include "se3.hpp"
#include "types.hpp"

namespace keel::lie {

/// Wraps an angle to (-pi, pi].
double wrap_angle(double a);

/// R = Rz(yaw) Ry(pitch) Rx(roll).
Mat3 rotation_from_rpy(double roll, double pitch, double yaw);
inline Mat3 rotation_from_rpy(const Vec3& rpy) { return rotation_from_rpy(rpy(0), rpy(1), rpy(2)); }

/// [roll, pitch, yaw] of R = Rz(yaw) Ry(pitch) Rx(roll), with roll, yaw in (-pi, pi] and
/// pitch in [-pi/2, pi/2].  At gimbal lock (cos(pitch) < kGimbalLockTolerance) only
/// yaw -/+ roll is observable; the result is made deterministic by setting roll = 0 and
/// yaw = atan2(-R(0,1), R(1,1)) (valid for both pitch = +pi/2 and -pi/2).
Vec3 rpy_from_rotation(const Mat3& R);

/// cos(pitch) below which rpy_from_rotation treats the rotation as gimbal-locked.
inline constexpr double kGimbalLockTolerance = 1e-12;

SE3 se3_from_ssc(const Vec6& x);
Vec6 ssc_from_se3(const SE3& T);
SE2 se2_from_ssc(const Vec3& x);
/// theta wrapped to (-pi, pi].
Vec3 ssc_from_se2(const SE2& T);

// The SSC (x, y, θ) covariance of poses perturbed on the left, to first order: Σ_x = J Σ_ξ Jᵀ with
// J = ∂ssc(exp(ξ^) T̄)/∂ξ at 0 = [[1, 0, −y], [0, 1, x], [0, 0, 1]] per pose. This is the covariance a solver
// that linearizes in (x, y, θ) coordinates (iSAM's Pose2d) reports at the same solution.
Mat3 ssc_jacobian_of_left_perturbation(const SE2& T);

}  // namespace keel::lie
