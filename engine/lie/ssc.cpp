#include "ssc.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <stdexcept>

#include "euler.hpp"
#include "gaussian.hpp"
#include "so3.hpp"

namespace keel::lie::ssc {

namespace {

// Partial derivatives of R = Rz(yaw) Ry(pitch) Rx(roll) w.r.t. (roll, pitch, yaw):
// dRx/droll = Rx e1^, dRy/dpitch = e2^ Ry, dRz/dyaw = e3^ Rz.
struct RotationWithDerivatives {
  Mat3 R;
  std::array<Mat3, 3> dR;
};

RotationWithDerivatives rotation_and_derivatives(const Vec3& rpy) {
  const double cr = std::cos(rpy(0)), sr = std::sin(rpy(0));
  const double cp = std::cos(rpy(1)), sp = std::sin(rpy(1));
  const double cy = std::cos(rpy(2)), sy = std::sin(rpy(2));
  Mat3 Rx, Ry, Rz;
  Rx << 1, 0, 0, 0, cr, -sr, 0, sr, cr;
  Ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  Rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  RotationWithDerivatives out;
  out.R = Rz * Ry * Rx;
  out.dR[0] = out.R * SO3::hat(Vec3::UnitX());
  out.dR[1] = Rz * SO3::hat(Vec3::UnitY()) * Ry * Rx;
  out.dR[2] = SO3::hat(Vec3::UnitZ()) * out.R;
  return out;
}

// Differential of (roll, pitch, yaw) = g(R) at a rotation R along a tangent direction dR:
// roll = atan2(R32, R33), pitch = -asin(R31), yaw = atan2(R21, R11).
Vec3 rpy_differential(const Mat3& R, const Mat3& dR) {
  const double c2 = R(0, 0) * R(0, 0) + R(1, 0) * R(1, 0);  // cos^2(pitch)
  if (c2 < kGimbalLockTolerance * kGimbalLockTolerance || R(2, 1) * R(2, 1) + R(2, 2) * R(2, 2) <= 0.0)
    throw std::invalid_argument("ssc: Euler-angle Jacobian is undefined at gimbal lock (|pitch| = pi/2)");
  const double cp = std::sqrt(c2);
  const double d_roll = (R(2, 2) * dR(2, 1) - R(2, 1) * dR(2, 2)) / (R(2, 1) * R(2, 1) + R(2, 2) * R(2, 2));
  const double d_pitch = -dR(2, 0) / cp;
  const double d_yaw = (R(0, 0) * dR(1, 0) - R(1, 0) * dR(0, 0)) / c2;
  return Vec3(d_roll, d_pitch, d_yaw);
}

Vec6 pack(const Vec3& t, const Mat3& R) {
  Vec6 x;
  x.head<3>() = t;
  x.tail<3>() = rpy_from_rotation(R);
  return x;
}

Mat2 rot2(double th) {
  Mat2 R;
  R << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
  return R;
}

template <int N>
void check_joint(const Eigen::Matrix<double, 2 * N, 2 * N>& joint_cov, const char* fn) {
  validate_covariance(joint_cov, fn);
}

}  // namespace

// ------------------------------------------------------------------------------------------
// 3D
// ------------------------------------------------------------------------------------------

// t_ik = t_ij + R_ij t_jk, R_ik = R_ij R_jk.
Vec6 head_to_tail(const Vec6& x_ij, const Vec6& x_jk, Mat6* J_out_xij, Mat6* J_out_xjk) {
  const auto a = rotation_and_derivatives(x_ij.tail<3>());
  const auto b = rotation_and_derivatives(x_jk.tail<3>());
  const Vec3 t_jk = x_jk.head<3>();
  const Mat3 R = a.R * b.R;
  const Vec6 out = pack(x_ij.head<3>() + a.R * t_jk, R);
  if (J_out_xij) {
    Mat6& J = *J_out_xij;
    J.setZero();
    J.topLeftCorner<3, 3>().setIdentity();
    for (int m = 0; m < 3; ++m) {
      J.block<3, 1>(0, 3 + m) = a.dR[m] * t_jk;
      J.block<3, 1>(3, 3 + m) = rpy_differential(R, a.dR[m] * b.R);
    }
  }
  if (J_out_xjk) {
    Mat6& J = *J_out_xjk;
    J.setZero();
    J.topLeftCorner<3, 3>() = a.R;
    for (int m = 0; m < 3; ++m) J.block<3, 1>(3, 3 + m) = rpy_differential(R, a.R * b.dR[m]);
  }
  return out;
}

// t_ji = -R_ij^T t_ij, R_ji = R_ij^T.
Vec6 inverse(const Vec6& x_ij, Mat6* J_out_xij) {
  const auto a = rotation_and_derivatives(x_ij.tail<3>());
  const Vec3 t = x_ij.head<3>();
  const Mat3 Rt = a.R.transpose();
  const Vec6 out = pack(-Rt * t, Rt);
  if (J_out_xij) {
    Mat6& J = *J_out_xij;
    J.setZero();
    J.topLeftCorner<3, 3>() = -Rt;
    for (int m = 0; m < 3; ++m) {
      J.block<3, 1>(0, 3 + m) = -a.dR[m].transpose() * t;
      J.block<3, 1>(3, 3 + m) = rpy_differential(Rt, a.dR[m].transpose());
    }
  }
  return out;
}

// t_jk = R_ij^T (t_ik - t_ij), R_jk = R_ij^T R_ik.
Vec6 tail_to_tail(const Vec6& x_ij, const Vec6& x_ik, Mat6* J_out_xij, Mat6* J_out_xik) {
  const auto a = rotation_and_derivatives(x_ij.tail<3>());
  const auto b = rotation_and_derivatives(x_ik.tail<3>());
  const Vec3 d = x_ik.head<3>() - x_ij.head<3>();
  const Mat3 Rt = a.R.transpose();
  const Mat3 R = Rt * b.R;
  const Vec6 out = pack(Rt * d, R);
  if (J_out_xij) {
    Mat6& J = *J_out_xij;
    J.setZero();
    J.topLeftCorner<3, 3>() = -Rt;
    for (int m = 0; m < 3; ++m) {
      J.block<3, 1>(0, 3 + m) = a.dR[m].transpose() * d;
      J.block<3, 1>(3, 3 + m) = rpy_differential(R, a.dR[m].transpose() * b.R);
    }
  }
  if (J_out_xik) {
    Mat6& J = *J_out_xik;
    J.setZero();
    J.topLeftCorner<3, 3>() = Rt;
    for (int m = 0; m < 3; ++m) J.block<3, 1>(3, 3 + m) = rpy_differential(R, Rt * b.dR[m]);
  }
  return out;
}

Estimate3D head_to_tail(const Vec6& x_ij, const Vec6& x_jk, const Mat12& joint_cov) {
  check_joint<6>(joint_cov, "ssc::head_to_tail");
  Eigen::Matrix<double, 6, 12> J;
  Mat6 J1, J2;
  Estimate3D out;
  out.mean = head_to_tail(x_ij, x_jk, &J1, &J2);  // eq. 5.18
  J << J1, J2;
  out.cov = J * joint_cov * J.transpose();  // eq. 5.19
  out.cov = 0.5 * (out.cov + out.cov.transpose()).eval();
  return out;
}

Estimate3D inverse(const Estimate3D& x_ij) {
  validate_covariance(x_ij.cov, "ssc::inverse");
  Mat6 J;
  Estimate3D out;
  out.mean = inverse(x_ij.mean, &J);       // eq. 5.22
  out.cov = J * x_ij.cov * J.transpose();  // eq. 5.23
  out.cov = 0.5 * (out.cov + out.cov.transpose()).eval();
  return out;
}

Estimate3D tail_to_tail(const Vec6& x_ij, const Vec6& x_ik, const Mat12& joint_cov) {
  check_joint<6>(joint_cov, "ssc::tail_to_tail");
  Eigen::Matrix<double, 6, 12> J;
  Mat6 J1, J2;
  Estimate3D out;
  out.mean = tail_to_tail(x_ij, x_ik, &J1, &J2);  // eq. 5.25
  J << J1, J2;
  out.cov = J * joint_cov * J.transpose();  // eq. 5.26
  out.cov = 0.5 * (out.cov + out.cov.transpose()).eval();
  return out;
}

// ------------------------------------------------------------------------------------------
// 2D
// ------------------------------------------------------------------------------------------

// [t_ik; th_ik] = [t_ij + R(th_ij) t_jk; th_ij + th_jk].
Vec3 head_to_tail(const Vec3& x_ij, const Vec3& x_jk, Mat3* J_out_xij, Mat3* J_out_xjk) {
  const Mat2 R = rot2(x_ij(2));
  const Vec2 Rt = R * x_jk.head<2>();
  const Vec3 out(x_ij(0) + Rt(0), x_ij(1) + Rt(1), wrap_angle(x_ij(2) + x_jk(2)));
  if (J_out_xij) {
    // d(R t_jk)/d th_ij = hat(1) R t_jk = [-(R t_jk)_y; (R t_jk)_x].
    *J_out_xij << 1.0, 0.0, -Rt(1),  //
        0.0, 1.0, Rt(0),             //
        0.0, 0.0, 1.0;
  }
  if (J_out_xjk) {
    J_out_xjk->setZero();
    J_out_xjk->topLeftCorner<2, 2>() = R;
    (*J_out_xjk)(2, 2) = 1.0;
  }
  return out;
}

// [t_ji; th_ji] = [-R^T t_ij; -th_ij].
Vec3 inverse(const Vec3& x_ij, Mat3* J_out_xij) {
  const double c = std::cos(x_ij(2)), s = std::sin(x_ij(2));
  const double x = x_ij(0), y = x_ij(1);
  const Vec3 out(-c * x - s * y, s * x - c * y, wrap_angle(-x_ij(2)));
  if (J_out_xij) {
    *J_out_xij << -c, -s, out(1),  //
        s, -c, -out(0),            //
        0.0, 0.0, -1.0;
  }
  return out;
}

// [t_jk; th_jk] = [R(th_ij)^T (t_ik - t_ij); th_ik - th_ij].
Vec3 tail_to_tail(const Vec3& x_ij, const Vec3& x_ik, Mat3* J_out_xij, Mat3* J_out_xik) {
  const Mat2 Rt = rot2(x_ij(2)).transpose();
  const Vec2 d = x_ik.head<2>() - x_ij.head<2>();
  const Vec2 t = Rt * d;
  const Vec3 out(t(0), t(1), wrap_angle(x_ik(2) - x_ij(2)));
  if (J_out_xij) {
    // d(R^T d)/d th_ij = -hat(1) R^T d = [t_y; -t_x].
    J_out_xij->setZero();
    J_out_xij->topLeftCorner<2, 2>() = -Rt;
    (*J_out_xij)(0, 2) = t(1);
    (*J_out_xij)(1, 2) = -t(0);
    (*J_out_xij)(2, 2) = -1.0;
  }
  if (J_out_xik) {
    J_out_xik->setZero();
    J_out_xik->topLeftCorner<2, 2>() = Rt;
    (*J_out_xik)(2, 2) = 1.0;
  }
  return out;
}

Estimate2D head_to_tail(const Vec3& x_ij, const Vec3& x_jk, const Mat6& joint_cov) {
  check_joint<3>(joint_cov, "ssc::head_to_tail");
  Eigen::Matrix<double, 3, 6> J;
  Mat3 J1, J2;
  Estimate2D out;
  out.mean = head_to_tail(x_ij, x_jk, &J1, &J2);
  J << J1, J2;
  out.cov = J * joint_cov * J.transpose();
  out.cov = 0.5 * (out.cov + out.cov.transpose()).eval();
  return out;
}

Estimate2D inverse(const Estimate2D& x_ij) {
  validate_covariance(x_ij.cov, "ssc::inverse");
  Mat3 J;
  Estimate2D out;
  out.mean = inverse(x_ij.mean, &J);
  out.cov = J * x_ij.cov * J.transpose();
  out.cov = 0.5 * (out.cov + out.cov.transpose()).eval();
  return out;
}

Estimate2D tail_to_tail(const Vec3& x_ij, const Vec3& x_ik, const Mat6& joint_cov) {
  check_joint<3>(joint_cov, "ssc::tail_to_tail");
  Eigen::Matrix<double, 3, 6> J;
  Mat3 J1, J2;
  Estimate2D out;
  out.mean = tail_to_tail(x_ij, x_ik, &J1, &J2);
  J << J1, J2;
  out.cov = J * joint_cov * J.transpose();
  out.cov = 0.5 * (out.cov + out.cov.transpose()).eval();
  return out;
}

// ------------------------------------------------------------------------------------------
// Chains: x_acc <- x_acc (+) x_k; d x_acc / d x = J1 (d x_acc_prev / d x) + J2 E_k, where E_k
// selects x_k.  The full joint covariance of all inputs is then mapped once.
// ------------------------------------------------------------------------------------------

namespace {

template <int D, class Vec, class Mat, class Est>
Est chain_impl(const VecX& x, const MatX& joint_cov, const char* fn) {
  if (x.size() == 0 || x.size() % D != 0) {
    throw std::invalid_argument(fmt::format(
        "{}: stacked parameter vector has length {}, expected a positive multiple of {}", fn, x.size(), D));
  }
  if (joint_cov.rows() != x.size() || joint_cov.cols() != x.size()) {
    throw std::invalid_argument(fmt::format("{}: joint covariance is {}x{}, expected {}x{}", fn,
                                            joint_cov.rows(), joint_cov.cols(), x.size(), x.size()));
  }
  validate_covariance(joint_cov, fn);
  const Eigen::Index n = x.size() / D;
  MatX J = MatX::Zero(D, x.size());
  J.leftCols(D).setIdentity();
  Vec acc = x.head<D>();
  for (Eigen::Index k = 1; k < n; ++k) {
    Mat J1, J2;
    acc = head_to_tail(acc, Vec(x.segment<D>(D * k)), &J1, &J2);
    J.leftCols(D * k) = (J1 * J.leftCols(D * k)).eval();
    J.middleCols(D * k, D) = J2;
  }
  Est out;
  out.mean = acc;
  out.cov = J * joint_cov * J.transpose();
  out.cov = 0.5 * (out.cov + out.cov.transpose()).eval();
  return out;
}

}  // namespace

Estimate3D head_to_tail_chain_3d(const VecX& x, const MatX& joint_cov) {
  return chain_impl<6, Vec6, Mat6, Estimate3D>(x, joint_cov, "ssc::head_to_tail_chain_3d");
}

Estimate2D head_to_tail_chain_2d(const VecX& x, const MatX& joint_cov) {
  return chain_impl<3, Vec3, Mat3, Estimate2D>(x, joint_cov, "ssc::head_to_tail_chain_2d");
}

}  // namespace keel::lie::ssc
