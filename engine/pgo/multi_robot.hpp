// keel::pgo — several robots' pose graphs joined by inter-robot measurements through anchor nodes
// (Kim et al., ICRA 2010; thesis §2.3, eq. 2.2).
//
// Robot r keeps its own local graph (poses T^r_i in its local frame). Its anchor Δ_r (the thesis's T_r^g) is
// the pose of that local frame in the global frame, so pose i of robot r is Δ_r T^r_i globally. An
// inter-robot edge measures z ≈ (Δ_a T^a_i)⁻¹ (Δ_b T^b_j), the pose of robot b's pose j in the frame of robot
// a's pose i, and its residual is that of pose_graph.hpp with the global poses Δ_a T^a_i and Δ_b T^b_j:
//     E = z⁻¹ (Δ_a T^a_i)⁻¹ (Δ_b T^b_j),   2D: r = (x_E, y_E, wrap(θ_E)),   3D: r = (t_E, Log R_E).
// Gauge: robot 0's anchor is held constant, and so are the Options::constant_poses of every robot (pose 0 by
// default), as Kim et al. fix the first pose of each trajectory in its local frame.
#pragma once

#include <vector>

#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"

namespace keel::pgo {

struct InterRobotEdge2 {
  int robot_a = 0, pose_a = 0;                    // robot a, its pose i
  int robot_b = 1, pose_b = 0;                    // robot b (≠ a), its pose j
  lie::SE2 measurement;                           // z ≈ (Δ_a T^a_i)⁻¹ Δ_b T^b_j
  lie::Mat3 information = lie::Mat3::Identity();  // Ω of r = (x_E, y_E, θ_E)
  int line = 0;                                   // 1-based source line (0 if generated)
};

struct InterRobotEdge3 {
  int robot_a = 0, pose_a = 0;
  int robot_b = 1, pose_b = 0;
  lie::SE3 measurement;
  lie::Mat6 information = lie::Mat6::Identity();  // Ω of r = (t_E, Log R_E)
  int line = 0;
};

struct MultiRobotGraph2D {
  std::vector<graph::PoseGraph2D> robots;  // local graphs; local poses in each robot's own frame
  std::vector<InterRobotEdge2> inter_robot_edges;
  std::vector<lie::SE2> anchors;  // initial Δ_r (AnchorGuess::as_given); empty = identity for all
};

struct MultiRobotGraph3D {
  std::vector<graph::PoseGraph3D> robots;
  std::vector<InterRobotEdge3> inter_robot_edges;
  std::vector<lie::SE3> anchors;
};

}  // namespace keel::pgo
