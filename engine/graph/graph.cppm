// keel.graph — the curated facade of engine/graph: the pose-graph data model (measurement z_ij ≈ T_i⁻¹ T_j,
// information over ρ(z_ij⁻¹ T_i⁻¹ T_j)), readers and writers for g2o, iSAM text (square-root information),
// iSAM ground truth, derived pose lists and TUM trajectories, and the format-dispatching entry points (the
// benchmark files themselves are found by keel.datasets). Facade rules (docs/DESIGN.md):
// includes in the global module fragment, using-declarations in the export block, no import of another
// facade. The Lie-group types (SE2, SE3, Vec2, ...) are keel.lie's: import keel.lie to name them.
module;
#include "graph/g2o.hpp"
#include "graph/io.hpp"
#include "graph/residuals.hpp"
#include "graph/isam.hpp"
#include "graph/parse_error.hpp"
#include "graph/pose_graph.hpp"
#include "graph/trajectory.hpp"
#include "graph/trajectory_error.hpp"
export module keel.graph;

export namespace keel::graph {
// residuals of the measurement convention (pose_graph.hpp)
using keel::graph::edge_residual;
using keel::graph::landmark_residual;
// data model
using keel::graph::Edge2;
using keel::graph::Edge3;
using keel::graph::InformationCheck;
using keel::graph::LandmarkMeasurement2;
using keel::graph::PoseGraph2D;
using keel::graph::PoseGraph3D;
using keel::graph::PoseGraphFor;
using keel::graph::PoseGraphOf;
// errors
using keel::graph::ParseError;
// g2o
using keel::graph::G2oWriteOptions;
using keel::graph::read_g2o_2d;
using keel::graph::read_g2o_3d;
using keel::graph::read_g2o_edges_2d;
using keel::graph::read_g2o_edges_3d;
using keel::graph::write_g2o;
using keel::graph::write_g2o_edges;
// iSAM text and ground truth
using keel::graph::GroundTruth2D;
using keel::graph::GroundTruth3D;
using keel::graph::GroundTruthOptions;
using keel::graph::read_isam_2d;
using keel::graph::read_isam_3d;
using keel::graph::read_isam_ground_truth_2d;
using keel::graph::read_isam_ground_truth_3d;
using keel::graph::rpy_for_writing;
using keel::graph::write_isam;
// pose lists and TUM trajectories
using keel::graph::read_landmarks_2d;
using keel::graph::read_pose_list_2d;
using keel::graph::read_poses_2d;
using keel::graph::read_poses_3d;
using keel::graph::read_tum;
using keel::graph::TumPose;
using keel::graph::write_landmarks_2d;
using keel::graph::write_poses_2d;
using keel::graph::write_poses_3d;
using keel::graph::write_tum;
// trajectory errors
using keel::graph::absolute_trajectory_error;
using keel::graph::relative_pose_error;
// dispatch and comparison
using keel::graph::detect_graph_format;
using keel::graph::graph_difference;
using keel::graph::graph_format_from_string;
using keel::graph::GraphFormat;
using keel::graph::read_pose_graph_2d;
using keel::graph::read_pose_graph_3d;
using keel::graph::to_string;
using keel::graph::write_pose_graph;
}  // namespace keel::graph
