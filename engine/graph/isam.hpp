// keel::graph — iSAM text files (Kaess et al.) and their noise-free ground-truth companions.
//
// 2D records (square-root information R, upper triangle row by row; Ω = RᵀR):
//   ODOMETRY | EDGE2 | Constraint2   i j dx dy dtheta  r_xx r_xy r_xt r_yy r_yt r_tt
//   LANDMARK                         i l x y           r_xx r_xy r_yy      (l: landmark id, its own
//   namespace)
// 3D record:
//   EDGE3  i j x y z roll pitch yaw  + 21 numbers (upper triangle of the 6×6 R over (x, y, z, roll, pitch,
//   yaw)), rotation R = Rz(yaw) Ry(pitch) Rx(roll); the information over (t, roll, pitch, yaw) is taken as
//   the information over (t, φ) (first order, as pose_graph.hpp states).
// The files carry no vertices: poses are initialised by chaining the odometry edges (i, i+1) from the
// identity (the first such edge when a pair repeats), landmarks from their first measurement. A missing
// odometry edge, a gap in the landmark ids, and every malformed line are ParseErrors naming file, line and
// field (see g2o.hpp for the rules).
//
// Ground-truth files (iSAM's data/groundtruth/*.txt) hold the same records with the noise removed and
// placeholder noise numbers (parsed, but not checked): read_isam_ground_truth_* chain them into ground-truth
// poses.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "graph/pose_graph.hpp"

namespace keel::graph {

PoseGraph2D read_isam_2d(const std::filesystem::path& file);
PoseGraph2D read_isam_2d(std::istream& in, const std::string& name);
PoseGraph3D read_isam_3d(const std::filesystem::path& file);
PoseGraph3D read_isam_3d(std::istream& in, const std::string& name);

/// Writes EDGE2 lines (2D) with LANDMARK lines placed after the first edge that reaches their pose (time
/// order, as the iSAM files have it), or EDGE3 lines (3D); the square-root information is the transposed
/// Cholesky factor of Ω.
/// %.17g throughout. The format has no vertex records, so read_isam(write_isam(g)) gives back g's edges,
/// landmark measurements and information, and poses/landmarks equal to the chained odometry / first
/// observations — equal to g's own when g came from an iSAM file. Throws std::invalid_argument when an
/// information matrix is not positive definite, an index is out of range, or the graph cannot be chained (no
/// records, a missing odometry edge (i, i+1), or a last pose no record names). The 3D writer extracts roll,
/// pitch, yaw so that Rz Ry Rx reproduces the rotation to rounding even next to gimbal lock.
void write_isam(const PoseGraph2D& graph, std::ostream& out);
void write_isam(const PoseGraph3D& graph, std::ostream& out);
void write_isam(const PoseGraph2D& graph, const std::filesystem::path& file);
void write_isam(const PoseGraph3D& graph, const std::filesystem::path& file);

/// Optional snapping of noise-free values printed with few digits (iSAM prints 6 significant digits): a value
/// within `tolerance` of a multiple of the step is replaced by that multiple — measurements before chaining,
/// and the chained poses and landmark positions after. Steps of 0 (the default) switch snapping off. For the
/// iSAM grid worlds (Manhattan3500, City10000, CityTrees10000) translation_step = 0.5, angle_step = π/2
/// reproduces the exact ground truth the SOURCE.md files describe.
struct GroundTruthOptions {
  double translation_step = 0.0;
  double angle_step = 0.0;
  double tolerance = 1e-5;
};

struct GroundTruth2D {
  std::vector<SE2> poses;       // chained odometry from the identity
  std::vector<Vec2> landmarks;  // world position from the first observation
  std::string source;
  // Consistency of the whole file with the chain (0 for exact ground truth): over every edge, the largest
  // |translation| and |angle| of z_ij⁻¹ T_i⁻¹ T_j; over every landmark observation, the largest distance from
  // the landmark's position.
  double max_edge_translation_error = 0.0;
  double max_edge_rotation_error = 0.0;
  double max_landmark_error = 0.0;
};

struct GroundTruth3D {
  std::vector<SE3> poses;
  std::string source;
  double max_edge_translation_error = 0.0;
  double max_edge_rotation_error = 0.0;  // |Log(R_E)|
};

GroundTruth2D read_isam_ground_truth_2d(const std::filesystem::path& file,
                                        const GroundTruthOptions& options = {});
GroundTruth2D read_isam_ground_truth_2d(std::istream& in, const std::string& name,
                                        const GroundTruthOptions& options = {});
GroundTruth3D read_isam_ground_truth_3d(const std::filesystem::path& file,
                                        const GroundTruthOptions& options = {});
GroundTruth3D read_isam_ground_truth_3d(std::istream& in, const std::string& name,
                                        const GroundTruthOptions& options = {});

/// rpy of R such that rotation_from_rpy(rpy) reproduces R to rounding everywhere, gimbal lock included (roll
/// is taken from the residual Ry(pitch)ᵀ Rz(yaw)ᵀ R, so the errors of yaw and roll cancel). Used by the 3D
/// iSAM writer.
lie::Vec3 rpy_for_writing(const Mat3& R);

}  // namespace keel::graph
