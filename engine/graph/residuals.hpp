// The residuals that define the measurement convention of pose_graph.hpp, written once for every consumer
// (the solver in keel::pgo, the linearization in keel::cov, tests and experiments).
#pragma once

#include "graph/pose_graph.hpp"

namespace keel::graph {

/// 2D edge: r = ρ(z⁻¹ T_i⁻¹ T_j) = (x_E, y_E, θ_E), θ_E in (−π, π].
lie::Vec3 edge_residual(const SE2& z, const SE2& T_i, const SE2& T_j);
/// 3D edge: r = ρ(z⁻¹ T_i⁻¹ T_j) = (t_E, Log R_E).
lie::Vec6 edge_residual(const SE3& z, const SE3& T_i, const SE3& T_j);
/// 2D landmark: r = T⁻¹ l − z = Rᵀ (l − t) − z.
Vec2 landmark_residual(const Vec2& z, const SE2& T, const Vec2& l);

}  // namespace keel::graph
