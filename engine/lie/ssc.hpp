// keel::lie::ssc — the Smith, Self & Cheeseman (1990) coordinate-based baseline (thesis §5.3).
//
// 3D poses are x = [x y z roll pitch yaw] with R = Rz(yaw) Ry(pitch) Rx(roll) (eq. 5.15);
// 2D poses are x = [x y theta].  All Jacobians are analytic (3D: chain rule through the
// rotation matrix; 2D: the classic closed forms).  Output angles are wrapped to (-pi, pi]
// (pitch to [-pi/2, pi/2]).  3D Jacobians are undefined at gimbal lock (|pitch| = pi/2) and
// throw std::invalid_argument there.
#pragma once

#include "types.hpp"

namespace keel::lie::ssc {

/// Mean and covariance of an SSC parameter vector.
struct Estimate2D {
  Vec3 mean = Vec3::Zero();
  Mat3 cov = Mat3::Zero();
};
struct Estimate3D {
  Vec6 mean = Vec6::Zero();
  Mat6 cov = Mat6::Zero();
};

// ---- 3D (eq. 5.15) -----------------------------------------------------------------------

/// x_ik = x_ij (+) x_jk (eq. 5.17); J_out_xij = d x_ik / d x_ij, J_out_xjk = d x_ik / d x_jk.
Vec6 head_to_tail(const Vec6& x_ij, const Vec6& x_jk, Mat6* J_out_xij = nullptr, Mat6* J_out_xjk = nullptr);
/// x_ji = (-) x_ij (eq. 5.21).
Vec6 inverse(const Vec6& x_ij, Mat6* J_out_xij = nullptr);
/// x_jk = (-x_ij) (+) x_ik (eq. 5.24).
Vec6 tail_to_tail(const Vec6& x_ij, const Vec6& x_ik, Mat6* J_out_xij = nullptr, Mat6* J_out_xik = nullptr);

/// eqs. 5.18-5.20: joint_cov is the 12x12 covariance of [x_ij; x_jk].
Estimate3D head_to_tail(const Vec6& x_ij, const Vec6& x_jk, const Mat12& joint_cov);
/// eqs. 5.22-5.23.
Estimate3D inverse(const Estimate3D& x_ij);
/// eqs. 5.25-5.27: joint_cov is the 12x12 covariance of [x_ij; x_ik].
Estimate3D tail_to_tail(const Vec6& x_ij, const Vec6& x_ik, const Mat12& joint_cov);

// ---- 2D ----------------------------------------------------------------------------------

Vec3 head_to_tail(const Vec3& x_ij, const Vec3& x_jk, Mat3* J_out_xij = nullptr, Mat3* J_out_xjk = nullptr);
Vec3 inverse(const Vec3& x_ij, Mat3* J_out_xij = nullptr);
Vec3 tail_to_tail(const Vec3& x_ij, const Vec3& x_ik, Mat3* J_out_xij = nullptr, Mat3* J_out_xik = nullptr);
/// joint_cov is the 6x6 covariance of [x_ij; x_jk].
Estimate2D head_to_tail(const Vec3& x_ij, const Vec3& x_jk, const Mat6& joint_cov);
Estimate2D inverse(const Estimate2D& x_ij);
/// joint_cov is the 6x6 covariance of [x_ij; x_ik].
Estimate2D tail_to_tail(const Vec3& x_ij, const Vec3& x_ik, const Mat6& joint_cov);

// ---- chains ------------------------------------------------------------------------------

/// x_1 (+) x_2 (+) ... (+) x_N for stacked x = [x_1; ...; x_N] (6N) with joint covariance
/// (6N x 6N, all cross-covariances used): Sigma = J Sigma_x J^T where J = d(result)/dx is
/// accumulated by the chain rule of the analytic head-to-tail Jacobians.
Estimate3D head_to_tail_chain_3d(const VecX& x, const MatX& joint_cov);
/// Same for stacked 2D vectors (3N).
Estimate2D head_to_tail_chain_2d(const VecX& x, const MatX& joint_cov);

}  // namespace keel::lie::ssc
