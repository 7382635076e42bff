// keel::graph — the in-memory pose graphs every reader produces and every solver consumes.
//
// Measurement convention (all formats are converted to it on reading and back on writing):
//   an edge (i, j) measures z_ij ≈ T_i⁻¹ T_j, the pose of j in the frame of i;
//   its residual at poses T_i, T_j is r = ρ(E) with E = z_ij⁻¹ T_i⁻¹ T_j and
//     2D: ρ(E) = (x_E, y_E, θ_E)            (θ wrapped to (−π, π]) — the iSAM and g2o convention;
//     3D: ρ(E) = (t_E, Log(R_E))            (translation, then rotation vector);
//   `information` Ω is the inverse covariance of r (Ω = RᵀR for the iSAM files, which store the square-root
//   R). g2o's EDGE_SE3:QUAT information is over (t, q_vec) with q_vec ≈ φ/2, so it is converted with J =
//   diag(I₃, ½ I₃): Ω = Jᵀ Ω_g2o J; iSAM's EDGE3 (x, y, z, roll, pitch, yaw) is taken as (t, φ) to first
//   order.
// Landmark measurements (2D) measure the landmark position in the frame of the pose: r = R_iᵀ (l − t_i) − z.
#pragma once

#include <string>
#include <vector>

#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"

namespace keel::graph {

using lie::Mat2;
using lie::Mat3;
using lie::Mat6;
using lie::SE2;
using lie::SE3;
using lie::Vec2;

struct Edge2 {
  int i = 0, j = 0;
  SE2 measurement;  // z_ij
  Mat3 information = Mat3::Identity();
  int line = 0;  // 1-based source line (0 if generated)
};

struct Edge3 {
  int i = 0, j = 0;
  SE3 measurement;
  Mat6 information = Mat6::Identity();
  int line = 0;
};

struct LandmarkMeasurement2 {
  int pose = 0, landmark = 0;    // landmark ids are their own namespace (0-based, contiguous after reading)
  Vec2 position = Vec2::Zero();  // landmark in the frame of the pose
  Mat2 information = Mat2::Identity();
  int line = 0;
};

// What a reader demands of each edge's information matrix. positive_definite: the whole matrix (the
// anisotropic maximum-likelihood model of eq. 2.1 needs it). diagonal_blocks: only the translation and the
// rotation blocks (the isotropic model of pgo::solve_certified uses nothing else); edges whose whole matrix
// is then not positive definite are counted in the graph's `indefinite_information`. Only g2o files can hold
// such matrices (iSAM text stores a square root).
enum class InformationCheck { positive_definite, diagonal_blocks };

struct PoseGraph2D {
  std::vector<SE2> poses;  // initial estimate (VERTEX lines, or chained odometry, or ground truth)
  std::vector<Edge2> edges;
  std::vector<Vec2> landmarks;  // initial landmark positions (world frame)
  std::vector<LandmarkMeasurement2> landmark_measurements;
  std::string source;              // file the graph was read from
  bool has_initial_poses = false;  // true when the file itself carried vertex estimates
  int indefinite_information = 0;  // edges read under InformationCheck::diagonal_blocks whose Ω is not PD
  int gauge_pose = 0;  // the pose every solve holds at its input value (the gauge; g2o's "FIX id" line)
};

struct PoseGraph3D {
  std::vector<SE3> poses;
  std::vector<Edge3> edges;
  std::string source;
  bool has_initial_poses = false;
  int indefinite_information = 0;  // as in PoseGraph2D
  int gauge_pose = 0;              // as in PoseGraph2D
};

// The pose-graph type of a group: PoseGraph2D for SE(2), PoseGraph3D for SE(3).
template <class G>
struct PoseGraphFor;
template <>
struct PoseGraphFor<lie::SE2> {
  using type = PoseGraph2D;
};
template <>
struct PoseGraphFor<lie::SE3> {
  using type = PoseGraph3D;
};
template <class G>
using PoseGraphOf = typename PoseGraphFor<G>::type;

}  // namespace keel::graph
