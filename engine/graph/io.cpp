#include "graph/io.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/parse.hpp"
#include "core/names.hpp"
#include "graph/g2o.hpp"
#include "graph/isam.hpp"
#include "graph/parse_error.hpp"
#include "graph/text_records.hpp"

namespace keel::graph {

namespace {

constexpr core::NameTable<GraphFormat, 2> kGraphFormat{
    "graph::GraphFormat", {{{GraphFormat::g2o, "g2o"}, {GraphFormat::isam, "isam"}}}};

}  // namespace

std::string_view to_string(GraphFormat format) { return kGraphFormat.name(format); }

GraphFormat graph_format_from_string(std::string_view s) { return kGraphFormat.parse(s); }

std::optional<GraphFormat> detect_graph_format(std::string_view text, const std::filesystem::path& name) {
  RecordScanner sc(text, name.string());
  bool fix = false;  // g2o's FIX line says nothing about the dimension: the next record decides
  while (sc.next()) {
    const std::string_view t = sc.tag();
    if (t == "FIX") {
      fix = true;
      continue;
    }
    if (t == "VERTEX_SE2" || t == "EDGE_SE2" || t == "VERTEX_SE3:QUAT" || t == "EDGE_SE3:QUAT")
      return GraphFormat::g2o;
    if (t == "ODOMETRY" || t == "EDGE2" || t == "Constraint2" || t == "LANDMARK" || t == "EDGE3") {
      return GraphFormat::isam;
    }
    return std::nullopt;
  }
  return fix || name.extension() == ".g2o" ? GraphFormat::g2o : GraphFormat::isam;
}

namespace {

GraphFormat format_or_throw(std::string_view text, const std::string& name) {
  if (auto f = detect_graph_format(text, name)) return *f;
  RecordScanner sc(text, name);
  while (sc.next() && sc.tag() == "FIX") {
  }
  sc.fail(
      fmt::format("unknown tag {} in the first record: neither g2o (VERTEX_SE2, EDGE_SE2, VERTEX_SE3:QUAT, "
                  "EDGE_SE3:QUAT) nor iSAM text (ODOMETRY, EDGE2, Constraint2, LANDMARK, EDGE3)",
                  core::quote_token(sc.tag())));
}

PoseGraph2D read_2d(const std::string& text, const std::string& name, InformationCheck information) {
  std::istringstream in(text);
  return format_or_throw(text, name) == GraphFormat::g2o ? read_g2o_2d(in, name, information)
                                                         : read_isam_2d(in, name);
}

PoseGraph3D read_3d(const std::string& text, const std::string& name, InformationCheck information) {
  std::istringstream in(text);
  return format_or_throw(text, name) == GraphFormat::g2o ? read_g2o_3d(in, name, information)
                                                         : read_isam_3d(in, name);
}

GraphFormat format_for_writing(const std::filesystem::path& file) {
  if (file.extension() == ".g2o") return GraphFormat::g2o;
  if (file.extension() == ".txt") return GraphFormat::isam;
  throw std::invalid_argument(fmt::format(
      "write_pose_graph: {}: unknown extension (use .g2o for g2o or .txt for iSAM text)", file.string()));
}

// |a - b| <= tol * max(1, |a|, |b|)
bool close(double a, double b, double tol) {
  return std::abs(a - b) <= tol * std::max({1.0, std::abs(a), std::abs(b)});
}

template <class M>
bool close_matrix(const M& a, const M& b, double tol) {
  for (Eigen::Index r = 0; r < a.rows(); ++r)
    for (Eigen::Index c = 0; c < a.cols(); ++c)
      if (!close(a(r, c), b(r, c), tol)) return false;
  return true;
}

template <class Graph>
std::string difference_common(const Graph& a, const Graph& b, double tol) {
  if (a.poses.size() != b.poses.size())
    return fmt::format("pose count {} vs {}", a.poses.size(), b.poses.size());
  if (a.edges.size() != b.edges.size())
    return fmt::format("edge count {} vs {}", a.edges.size(), b.edges.size());
  for (std::size_t k = 0; k < a.poses.size(); ++k) {
    if (!close_matrix(a.poses[k].matrix(), b.poses[k].matrix(), tol))
      return fmt::format("pose {} differs", k);
  }
  for (std::size_t k = 0; k < a.edges.size(); ++k) {
    const auto& x = a.edges[k];
    const auto& y = b.edges[k];
    if (x.i != y.i || x.j != y.j) return fmt::format("edge {} connects different poses", k);
    if (!close_matrix(x.measurement.matrix(), y.measurement.matrix(), tol))
      return fmt::format("edge {} measurement differs", k);
    if (!close_matrix(x.information, y.information, tol))
      return fmt::format("edge {} information differs", k);
  }
  return {};
}

}  // namespace

PoseGraph2D read_pose_graph_2d(const std::filesystem::path& file, InformationCheck information) {
  return read_2d(read_file_text(file), file.string(), information);
}
PoseGraph2D read_pose_graph_2d(std::istream& in, const std::string& name, InformationCheck information) {
  return read_2d(read_stream_text(in, name), name, information);
}
PoseGraph3D read_pose_graph_3d(const std::filesystem::path& file, InformationCheck information) {
  return read_3d(read_file_text(file), file.string(), information);
}
PoseGraph3D read_pose_graph_3d(std::istream& in, const std::string& name, InformationCheck information) {
  return read_3d(read_stream_text(in, name), name, information);
}

void write_pose_graph(const PoseGraph2D& graph, const std::filesystem::path& file) {
  if (format_for_writing(file) == GraphFormat::g2o) {
    write_g2o(graph, file);
  } else {
    write_isam(graph, file);
  }
}
void write_pose_graph(const PoseGraph3D& graph, const std::filesystem::path& file) {
  if (format_for_writing(file) == GraphFormat::g2o) {
    write_g2o(graph, file);
  } else {
    write_isam(graph, file);
  }
}

std::string graph_difference(const PoseGraph2D& a, const PoseGraph2D& b, double tol) {
  if (auto d = difference_common(a, b, tol); !d.empty()) return d;
  if (a.landmarks.size() != b.landmarks.size()) {
    return fmt::format("landmark count {} vs {}", a.landmarks.size(), b.landmarks.size());
  }
  if (a.landmark_measurements.size() != b.landmark_measurements.size()) {
    return fmt::format("landmark measurement count {} vs {}", a.landmark_measurements.size(),
                       b.landmark_measurements.size());
  }
  for (std::size_t k = 0; k < a.landmarks.size(); ++k) {
    if (!close_matrix(a.landmarks[k], b.landmarks[k], tol)) return fmt::format("landmark {} differs", k);
  }
  for (std::size_t k = 0; k < a.landmark_measurements.size(); ++k) {
    const auto& x = a.landmark_measurements[k];
    const auto& y = b.landmark_measurements[k];
    if (x.pose != y.pose || x.landmark != y.landmark)
      return fmt::format("landmark measurement {} has different ids", k);
    if (!close_matrix(x.position, y.position, tol))
      return fmt::format("landmark measurement {} position differs", k);
    if (!close_matrix(x.information, y.information, tol)) {
      return fmt::format("landmark measurement {} information differs", k);
    }
  }
  return {};
}

std::string graph_difference(const PoseGraph3D& a, const PoseGraph3D& b, double tol) {
  return difference_common(a, b, tol);
}

}  // namespace keel::graph
