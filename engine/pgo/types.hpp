// keel::pgo — the types of one dimension, by group: what the solver, its evaluation and the map merge need of
// a 2D or a 3D problem, named once. The graph type is graph::PoseGraphOf<G> (graph/pose_graph.hpp), the one
// mapping below pgo.
#pragma once

#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"
#include "pgo/multi_robot.hpp"
#include "pgo/optimize.hpp"

namespace keel::pgo {

template <class G>
struct Types;

template <>
struct Types<lie::SE2> {
  static constexpr int kPoseDof = lie::SE2::DoF;
  static constexpr bool kLandmarks = true;  // 2D graphs may hold landmarks
  using Pose = lie::SE2;
  using Graph = graph::PoseGraphOf<lie::SE2>;
  using Edge = graph::Edge2;
  using Inter = InterRobotEdge2;
  using Residual = lie::Vec3;
  using Information = lie::Mat3;
  using Estimate = Estimate2D;
  using MultiEstimate = MultiRobotEstimate2D;
  using MultiGraph = MultiRobotGraph2D;
  using Evaluation = Evaluation2D;
  using MultiEvaluation = MultiRobotEvaluation2D;
};

template <>
struct Types<lie::SE3> {
  static constexpr int kPoseDof = lie::SE3::DoF;
  static constexpr bool kLandmarks = false;
  using Pose = lie::SE3;
  using Graph = graph::PoseGraphOf<lie::SE3>;
  using Edge = graph::Edge3;
  using Inter = InterRobotEdge3;
  using Residual = lie::Vec6;
  using Information = lie::Mat6;
  using Estimate = Estimate3D;
  using MultiEstimate = MultiRobotEstimate3D;
  using MultiGraph = MultiRobotGraph3D;
  using Evaluation = Evaluation3D;
  using MultiEvaluation = MultiRobotEvaluation3D;
};

}  // namespace keel::pgo
