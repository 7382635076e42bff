#include "graph/residuals.hpp"

#include "lie/so3.hpp"

namespace keel::graph {

std::array<double, 3> pose_parameters(const SE2& T) {
  return {T.translation()(0), T.translation()(1), T.angle()};
}

std::array<double, 7> pose_parameters(const SE3& T) {
  const Eigen::Quaterniond q = Eigen::Quaterniond(T.rotation()).normalized();
  const lie::Vec3& t = T.translation();
  return {q.x(), q.y(), q.z(), q.w(), t(0), t(1), t(2)};
}

lie::Vec3 edge_residual(const SE2& z, const SE2& T_i, const SE2& T_j) {
  const auto p_i = pose_parameters(T_i), p_j = pose_parameters(T_j);
  lie::Vec3 r;
  edge_residual(EdgeMeasurement2(z), p_i.data(), p_j.data(), r.data());
  return r;
}

lie::Vec6 edge_residual(const SE3& z, const SE3& T_i, const SE3& T_j) {
  const auto p_i = pose_parameters(T_i), p_j = pose_parameters(T_j);
  lie::Vec6 r;
  edge_residual(EdgeMeasurement3(z), p_i.data(), p_j.data(), r.data());
  return r;
}

EdgeLinearization2 linearize_edge(const SE2& z, const SE2& T_i, const SE2& T_j) {
  const auto p_i = pose_parameters(T_i), p_j = pose_parameters(T_j);
  EdgeLinearization2 out;
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> J_p;  // ∂r/∂p_j
  edge_residual(EdgeMeasurement2(z), p_i.data(), p_j.data(), out.residual.data(), nullptr, J_p.data());
  lie::Mat3 P = lie::Mat3::Identity();  // ∂p_j/∂ξ_j = [I, S t_j; 0, 1], S t = (−t_y, t_x)
  P(0, 2) = -T_j.translation()(1);
  P(1, 2) = T_j.translation()(0);
  out.J_r_xi_j = J_p * P;
  out.J_r_xi_i = -out.J_r_xi_j;
  return out;
}

EdgeLinearization3 linearize_edge(const SE3& z, const SE3& T_i, const SE3& T_j) {
  EdgeLinearization3 out;
  out.residual = edge_residual(z, T_i, T_j);
  const lie::Vec3 phi = out.residual.tail<3>();
  lie::Mat6 D = lie::Mat6::Zero();
  D.topLeftCorner<3, 3>() = lie::SO3::exp(phi).matrix();
  D.bottomRightCorner<3, 3>() = lie::SO3::right_jacobian_inverse(phi);
  out.J_r_xi_j = D * T_j.inverse().adjoint();
  out.J_r_xi_i = -out.J_r_xi_j;
  return out;
}

Vec2 landmark_residual(const Vec2& z, const SE2& T, const Vec2& l) {
  const auto p = pose_parameters(T);
  Vec2 r;
  landmark_residual(z, p.data(), l.data(), r.data());
  return r;
}

LandmarkLinearization2 linearize_landmark(const Vec2& z, const SE2& T, const Vec2& l) {
  const auto p = pose_parameters(T);
  LandmarkLinearization2 out;
  Eigen::Matrix<double, 2, 2, Eigen::RowMajor> J_l;
  landmark_residual(z, p.data(), l.data(), out.residual.data(), nullptr, J_l.data());
  Eigen::Matrix<double, 2, 3> B;  // [I₂, S l]
  B << 1.0, 0.0, -l.y(),          //
      0.0, 1.0, l.x();
  out.J_r_xi = -J_l * B;
  out.J_r_l = J_l;
  return out;
}

}  // namespace keel::graph
