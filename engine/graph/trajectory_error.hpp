// keel::graph — how far an estimated trajectory is from a reference one (the robust back end's accuracy,
// ext_robust_backend):
//   ATE  the root mean square of the position errors ‖p_k − (R p̂_k + t)‖ after the rigid motion (R, t) that
//        minimizes it (the closed form of Umeyama 1991 without scale: R from the SVD of the positions'
//        cross-covariance with det R = +1, t from the centroids), so a trajectory that differs from the
//        reference by a rigid motion has ATE 0 whatever the gauge either was solved in;
//   RPE  the root mean square of the translation of (T_i⁻¹ T_j)⁻¹ (T̂_i⁻¹ T̂_j) over the pairs given
//        (consecutive poses: the local drift), which no rigid motion of either trajectory changes.
#pragma once

#include <utility>
#include <vector>

#include "graph/pose_graph.hpp"

namespace keel::graph {

/// Throws std::invalid_argument when the sizes differ or the trajectories are empty.
[[nodiscard]] double absolute_trajectory_error(const std::vector<SE2>& reference,
                                               const std::vector<SE2>& estimate);
[[nodiscard]] double absolute_trajectory_error(const std::vector<SE3>& reference,
                                               const std::vector<SE3>& estimate);

/// Throws std::invalid_argument when the sizes differ, a pair names a pose out of range, or no pair is given.
[[nodiscard]] double relative_pose_error(const std::vector<SE2>& reference, const std::vector<SE2>& estimate,
                                         const std::vector<std::pair<int, int>>& pairs);
[[nodiscard]] double relative_pose_error(const std::vector<SE3>& reference, const std::vector<SE3>& estimate,
                                         const std::vector<std::pair<int, int>>& pairs);

}  // namespace keel::graph
