// keel::graph — g2o text files.
//
// 2D: `VERTEX_SE2 id x y theta`, `EDGE_SE2 i j dx dy dtheta I11 I12 I13 I22 I23 I33` (upper triangle of the
//     information over (x, y, theta), already the convention of pose_graph.hpp).
// 3D: `VERTEX_SE3:QUAT id x y z qx qy qz qw`, `EDGE_SE3:QUAT i j x y z qx qy qz qw` + 21 numbers (upper
// triangle of the
//     information over (t, q_vec)); converted on reading to (t, φ) with J = diag(I₃, ½I₃): Ω = Jᵀ Ω_g2o J,
//     and back on writing (Ω_g2o = K Ω K, K = diag(I₃, 2I₃)).
// Files without VERTEX lines (SE-Sync's manhattan.g2o) get their initial estimate by chaining the odometry
// edges (i, i+1) from the identity (has_initial_poses = false); a missing odometry edge is an error. Strict:
// every malformed line, unknown tag, non-finite number, non-positive-definite information, duplicate or
// missing vertex id, negative id, self-loop or vertex no edge uses throws ParseError naming file, line and
// field. Comments (# to end of line) and blank lines are allowed; fields are separated by spaces or tabs;
// CRLF is accepted.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "graph/pose_graph.hpp"

namespace keel::graph {

/// `information`: what each edge's information matrix must satisfy (pose_graph.hpp, InformationCheck).
PoseGraph2D read_g2o_2d(const std::filesystem::path& file,
                        InformationCheck information = InformationCheck::positive_definite);
/// In-memory variant (the fuzzers use it): `name` is the file name used in error messages and in `source`.
PoseGraph2D read_g2o_2d(std::istream& in, const std::string& name,
                        InformationCheck information = InformationCheck::positive_definite);
PoseGraph3D read_g2o_3d(const std::filesystem::path& file,
                        InformationCheck information = InformationCheck::positive_definite);
PoseGraph3D read_g2o_3d(std::istream& in, const std::string& name,
                        InformationCheck information = InformationCheck::positive_definite);

struct G2oWriteOptions {
  bool write_vertices =
      true;  // false: edges only (a reader then chains the odometry edges for the initial estimate)
};

/// Numbers are written with %.17g, so read_g2o(write_g2o(g)) reproduces g to the last bit of every field
/// (angles are written as angle() in (−π, π], quaternions with w ≥ 0). Throws std::invalid_argument for a 2D
/// graph with landmarks (g2o landmark records are not supported; use write_isam) or an edge naming a pose
/// outside the graph.
void write_g2o(const PoseGraph2D& graph, std::ostream& out, const G2oWriteOptions& options = {});
void write_g2o(const PoseGraph3D& graph, std::ostream& out, const G2oWriteOptions& options = {});
/// File variants write to a temporary name and rename it (a failed write leaves no half file).
void write_g2o(const PoseGraph2D& graph, const std::filesystem::path& file,
               const G2oWriteOptions& options = {});
void write_g2o(const PoseGraph3D& graph, const std::filesystem::path& file,
               const G2oWriteOptions& options = {});

/// Edge-only g2o files: the inter-robot candidate loop closures of `keel pcm` (docs/USING.md). Every record
/// is an `EDGE_SE2` (2D) or `EDGE_SE3:QUAT` (3D) line in the format above; `i` is a pose id of robot a and
/// `j` a pose id of robot b (two id spaces, so i = j is allowed), and the edge measures z ≈ (T^a_i)⁻¹ T^b_j
/// with the information of its residual as in pose_graph.hpp. Throws ParseError (file, line, field) for a
/// malformed record, any other tag, or a file without edges.
std::vector<Edge2> read_g2o_edges_2d(const std::filesystem::path& file);
std::vector<Edge2> read_g2o_edges_2d(std::istream& in, const std::string& name);
std::vector<Edge3> read_g2o_edges_3d(const std::filesystem::path& file);
std::vector<Edge3> read_g2o_edges_3d(std::istream& in, const std::string& name);
/// Writes the edges in the same format (%.17g: a read gives back every field to the last bit), atomically.
void write_g2o_edges(const std::vector<Edge2>& edges, const std::filesystem::path& file);
void write_g2o_edges(const std::vector<Edge3>& edges, const std::filesystem::path& file);

}  // namespace keel::graph
