// keel::graph — format-dispatching entry points.
//
// The format is decided by the first record's tag (VERTEX_SE2 / EDGE_SE2 / VERTEX_SE3:QUAT / EDGE_SE3:QUAT →
// g2o; ODOMETRY / EDGE2 / Constraint2 / LANDMARK / EDGE3 → iSAM text); a file without records falls back to
// its extension
// (.g2o → g2o, anything else → iSAM), whose reader then reports the empty file. A 3D file given to the 2D
// entry point (and vice versa) is a ParseError that says which function to call.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>

#include "graph/pose_graph.hpp"

namespace keel::graph {

enum class GraphFormat {
  g2o,   // g2o (VERTEX_SE2, EDGE_SE2, VERTEX_SE3:QUAT, EDGE_SE3:QUAT)
  isam,  // iSAM text (ODOMETRY, EDGE2, Constraint2, LANDMARK, EDGE3)
};

std::string_view to_string(GraphFormat format);  // "g2o", "isam"
// The exact names printed by to_string; anything else throws std::invalid_argument naming the valid names.
[[nodiscard]] GraphFormat graph_format_from_string(std::string_view s);

/// By first tag, then by extension (see above); nullopt when neither decides (unknown first tag).
[[nodiscard]] std::optional<GraphFormat> detect_graph_format(std::string_view text,
                                                             const std::filesystem::path& name);

/// `information` applies to g2o files (iSAM text stores square roots, positive semidefinite by construction).
PoseGraph2D read_pose_graph_2d(const std::filesystem::path& file,
                               InformationCheck information = InformationCheck::positive_definite);
PoseGraph2D read_pose_graph_2d(std::istream& in, const std::string& name,
                               InformationCheck information = InformationCheck::positive_definite);
PoseGraph3D read_pose_graph_3d(const std::filesystem::path& file,
                               InformationCheck information = InformationCheck::positive_definite);
PoseGraph3D read_pose_graph_3d(std::istream& in, const std::string& name,
                               InformationCheck information = InformationCheck::positive_definite);

/// By extension: .g2o → g2o, .txt → iSAM text; anything else throws std::invalid_argument.
void write_pose_graph(const PoseGraph2D& graph, const std::filesystem::path& file);
void write_pose_graph(const PoseGraph3D& graph, const std::filesystem::path& file);

/// Empty when a and b hold the same poses, edges (i, j, measurement, information), landmarks and landmark
/// measurements within `tol` (relative to each number's magnitude, at least absolute `tol`); otherwise the
/// first difference in words. `source`, `line` and has_initial_poses are not compared.
[[nodiscard]] std::string graph_difference(const PoseGraph2D& a, const PoseGraph2D& b, double tol = 1e-12);
[[nodiscard]] std::string graph_difference(const PoseGraph3D& a, const PoseGraph3D& b, double tol = 1e-12);

}  // namespace keel::graph
