#include "graph/residuals.hpp"

namespace keel::graph {

lie::Vec3 edge_residual(const SE2& z, const SE2& T_i, const SE2& T_j) {
  const SE2 E = z.inverse() * (T_i.inverse() * T_j);
  return lie::Vec3(E.translation()(0), E.translation()(1), E.angle());  // angle() is in (−π, π]
}

lie::Vec6 edge_residual(const SE3& z, const SE3& T_i, const SE3& T_j) {
  const SE3 E = z.inverse() * (T_i.inverse() * T_j);
  lie::Vec6 r;
  r.head<3>() = E.translation();
  r.tail<3>() = E.so3().log();
  return r;
}

Vec2 landmark_residual(const Vec2& z, const SE2& T, const Vec2& l) {
  return T.rotation().transpose() * (l - T.translation()) - z;
}

}  // namespace keel::graph
