// keel::graph — what the readers share after scanning: the checks of an information matrix and the quaternion
// conversions (public: the Python module checks and converts with them), and, internal (detail), information
// matrices from upper triangles and the assembly of poses (vertices or chained odometry) and landmarks with
// their checks. Not part of the keel.graph facade.
#pragma once

#include <string>
#include <vector>

#include "graph/pose_graph.hpp"
#include "graph/text_records.hpp"

namespace keel::graph {

/// Empty when the matrix is finite and numerically positive definite (every diagonal entry > 0 and the
/// smallest eigenvalue of D^-1/2 W D^-1/2 above 1e-10, so it survives a write/read round trip); else what is
/// wrong, in words.
std::string information_problem(const Mat2& W);
std::string information_problem(const Mat3& W);
std::string information_problem(const Mat6& W);

/// Rotation of a quaternion (x, y, z, w) whose norm is within 1e-3 of 1 (it is normalised); else the reason
/// in `why`.
bool rotation_from_quaternion(const double* xyzw, Mat3& R, std::string& why);
/// (x, y, z, w) with w >= 0 of a rotation matrix.
void quaternion_from_rotation(const Mat3& R, double* xyzw);

}  // namespace keel::graph

namespace keel::graph::detail {

/// Symmetric N×N matrix from its upper triangle listed row by row.
template <int N>
Eigen::Matrix<double, N, N> symmetric_from_upper(const double* v) {
  Eigen::Matrix<double, N, N> m;
  for (int r = 0; r < N; ++r)
    for (int c = r; c < N; ++c) m(r, c) = m(c, r) = *v++;
  return m;
}

/// RᵀR for the upper-triangular R listed row by row (the iSAM square-root information).
template <int N>
Eigen::Matrix<double, N, N> information_from_sqrt_upper(const double* v) {
  Eigen::Matrix<double, N, N> R = Eigen::Matrix<double, N, N>::Zero();
  for (int r = 0; r < N; ++r)
    for (int c = r; c < N; ++c) R(r, c) = *v++;
  return R.transpose() * R;
}

struct Vertex2 {
  int id = 0;
  SE2 pose;
  int line = 0;
};
struct Vertex3 {
  int id = 0;
  SE3 pose;
  int line = 0;
};

/// Fills g.poses: from `vertices` when there are any (ids contiguous from 0, no duplicates, every edge
/// endpoint a vertex, no vertex without an edge when there are several), else by chaining the odometry edges
/// (i, i+1) (pose ids 0..max over edges and landmark measurements; a missing odometry edge is an error). Then
/// landmarks: ids contiguous from 0, initial position from the first measurement. has_initial_poses =
/// !vertices.empty(). `vertex_tag` and `edge_tag` name the records in messages. Throws ParseError.
void assemble(PoseGraph2D& g, const std::vector<Vertex2>& vertices, const std::string& vertex_tag,
              const std::string& edge_tag);
void assemble(PoseGraph3D& g, const std::vector<Vertex3>& vertices, const std::string& vertex_tag,
              const std::string& edge_tag);

/// Throws std::invalid_argument when an edge or landmark measurement names an index outside the graph
/// (writers).
void check_indices(const PoseGraph2D& g, const char* writer);
void check_indices(const PoseGraph3D& g, const char* writer);

}  // namespace keel::graph::detail
