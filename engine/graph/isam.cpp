#include "graph/isam.hpp"

#include <fmt/format.h>
#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/parse.hpp"
#include "graph/build.hpp"
#include "graph/parse_error.hpp"
#include "graph/text_records.hpp"
#include "lie/euler.hpp"

namespace keel::graph {

using lie::SO3;
using lie::Vec3;

namespace {

constexpr std::array<const char*, 11> kEdge2 = {"i",    "j",    "dx",   "dy",   "dtheta", "r_xx",
                                                "r_xy", "r_xt", "r_yy", "r_yt", "r_tt"};
constexpr std::array<const char*, 7> kLandmark = {"i", "l", "x", "y", "r_xx", "r_xy", "r_yy"};
constexpr std::array<const char*, 29> kEdge3 = {"i",   "j",   "x",   "y",   "z",   "roll", "pitch", "yaw",
                                                "R11", "R12", "R13", "R14", "R15", "R16",  "R22",   "R23",
                                                "R24", "R25", "R26", "R33", "R34", "R35",  "R36",   "R44",
                                                "R45", "R46", "R55", "R56", "R66"};

bool is_2d_edge_tag(std::string_view t) { return t == "ODOMETRY" || t == "EDGE2" || t == "Constraint2"; }

// `check_information`: false for ground-truth files, whose noise numbers are placeholders (still parsed
// strictly).
PoseGraph2D parse_isam_2d(std::string_view text, const std::string& name, bool check_information) {
  RecordScanner sc(text, name);
  PoseGraph2D g;
  g.source = name;
  while (sc.next()) {
    const std::string_view tag = sc.tag();
    if (is_2d_edge_tag(tag)) {
      sc.expect(kEdge2);
      Edge2 e;
      e.i = sc.id(1);
      e.j = sc.id(2);
      if (e.i == e.j) sc.fail_field(2, fmt::format("the edge connects pose {} to itself", e.i));
      double v[9];
      sc.numbers(3, 11, v);
      e.measurement = SE2(v[0], v[1], v[2]);
      e.information = detail::information_from_sqrt_upper<3>(v + 3);
      if (check_information) {
        if (auto why = information_problem(e.information); !why.empty()) {
          sc.fail_fields(6, 11, fmt::format("the information RᵀR of the square-root numbers {}", why));
        }
      }
      e.line = sc.line();
      g.edges.push_back(e);
    } else if (tag == "LANDMARK") {
      sc.expect(kLandmark);
      LandmarkMeasurement2 m;
      m.pose = sc.id(1);
      m.landmark = sc.id(2);
      double v[5];
      sc.numbers(3, 7, v);
      m.position = Vec2(v[0], v[1]);
      m.information = detail::information_from_sqrt_upper<2>(v + 2);
      if (check_information) {
        if (auto why = information_problem(m.information); !why.empty()) {
          sc.fail_fields(5, 7, fmt::format("the information RᵀR of the square-root numbers {}", why));
        }
      }
      m.line = sc.line();
      g.landmark_measurements.push_back(m);
    } else if (tag == "EDGE3" || tag == "VERTEX_SE3:QUAT" || tag == "EDGE_SE3:QUAT") {
      sc.fail(fmt::format(
          "{} is a 3D record, but this is the 2D iSAM reader (use read_isam_3d or read_pose_graph_3d)",
          core::quote_token(tag)));
    } else {
      sc.fail(
          fmt::format("unknown tag {} (the 2D iSAM reader knows ODOMETRY, EDGE2, Constraint2 and LANDMARK)",
                      core::quote_token(tag)));
    }
  }
  detail::assemble(g, {}, "VERTEX", "edge");
  return g;
}

PoseGraph3D parse_isam_3d(std::string_view text, const std::string& name, bool check_information) {
  RecordScanner sc(text, name);
  PoseGraph3D g;
  g.source = name;
  while (sc.next()) {
    const std::string_view tag = sc.tag();
    if (tag == "EDGE3") {
      sc.expect(kEdge3);
      Edge3 e;
      e.i = sc.id(1);
      e.j = sc.id(2);
      if (e.i == e.j) sc.fail_field(2, fmt::format("the edge connects pose {} to itself", e.i));
      double v[27];
      sc.numbers(3, 29, v);
      e.measurement =
          SE3(SO3::from_matrix_unchecked(lie::rotation_from_rpy(v[3], v[4], v[5])), Vec3(v[0], v[1], v[2]));
      // Information over (x, y, z, roll, pitch, yaw) taken as the information over (t, φ) (pose_graph.hpp).
      e.information = detail::information_from_sqrt_upper<6>(v + 6);
      if (check_information) {
        if (auto why = information_problem(e.information); !why.empty()) {
          sc.fail_fields(9, 29, fmt::format("the information RᵀR of the square-root numbers {}", why));
        }
      }
      e.line = sc.line();
      g.edges.push_back(e);
    } else if (is_2d_edge_tag(tag) || tag == "LANDMARK" || tag == "VERTEX_SE2" || tag == "EDGE_SE2") {
      sc.fail(fmt::format(
          "{} is a 2D record, but this is the 3D iSAM reader (use read_isam_2d or read_pose_graph_2d)",
          core::quote_token(tag)));
    } else {
      sc.fail(fmt::format("unknown tag {} (the 3D iSAM reader knows EDGE3)", core::quote_token(tag)));
    }
  }
  detail::assemble(g, {}, "VERTEX", "EDGE3");
  return g;
}

void put(std::string& s, double v) {
  s += ' ';
  s += fmt17(v);
}

// iSAM text has no vertex records: a reader rebuilds the poses by chaining the edges (i, i+1), so the graph
// must have one for every pose, and at least one record.
template <class Graph>
void check_chainable(const Graph& g) {
  if (g.gauge_pose != 0) {
    throw std::invalid_argument(fmt::format(
        "write_isam: the graph holds pose {} fixed (the gauge, g2o's FIX line), which iSAM text cannot "
        "record (its solves fix pose 0): write g2o, or set the gauge pose to 0",
        g.gauge_pose));
  }
  bool records = !g.edges.empty();
  if constexpr (requires { g.landmark_measurements; }) records = records || !g.landmark_measurements.empty();
  if (!records) {
    throw std::invalid_argument(
        "write_isam: the graph has no edges (iSAM text has no vertex records, so an edgeless "
        "graph cannot be written)");
  }
  std::vector<char> odometry(g.poses.size(), 0);
  for (const auto& e : g.edges)
    if (e.j == e.i + 1) odometry[static_cast<std::size_t>(e.i)] = 1;
  for (std::size_t k = 0; k + 1 < g.poses.size(); ++k) {
    if (!odometry[k]) {
      throw std::invalid_argument(fmt::format(
          "write_isam: no odometry edge ({}, {}): iSAM text has no vertex records, and its readers chain "
          "the edges (i, i+1)",
          k, k + 1));
    }
  }
  int max_id = -1;
  for (const auto& e : g.edges) max_id = std::max({max_id, e.i, e.j});
  if constexpr (requires { g.landmark_measurements; }) {
    for (const auto& m : g.landmark_measurements) max_id = std::max(max_id, m.pose);
  }
  if (static_cast<std::size_t>(max_id) + 1 != g.poses.size()) {
    throw std::invalid_argument(
        fmt::format("write_isam: pose {} is named by no record (iSAM text has no vertex "
                    "records)",
                    g.poses.size() - 1));
  }
}

// Upper-triangular R with RᵀR = W (R = Lᵀ of the Cholesky factor W = L Lᵀ).
template <int N>
Eigen::Matrix<double, N, N> sqrt_information(const Eigen::Matrix<double, N, N>& W, const char* what) {
  Eigen::LLT<Eigen::Matrix<double, N, N>> llt(W);
  if (llt.info() != Eigen::Success || !W.allFinite()) {
    throw std::invalid_argument(
        fmt::format("write_isam: the information of {} is not positive definite", what));
  }
  return llt.matrixU();
}

std::string isam_text(const PoseGraph2D& g) {
  detail::check_indices(g, "write_isam");
  check_chainable(g);
  std::string s;
  s.reserve(96 * (g.edges.size() + g.landmark_measurements.size()));
  auto landmark_line = [&](const LandmarkMeasurement2& m) {
    const Mat2 R = sqrt_information<2>(m.information, "a landmark measurement");
    s += fmt::format("LANDMARK {} {}", m.pose, m.landmark);
    put(s, m.position.x());
    put(s, m.position.y());
    put(s, R(0, 0));
    put(s, R(0, 1));
    put(s, R(1, 1));
    s += '\n';
  };
  // Time order: a LANDMARK line follows the first edge that reaches its pose (landmarks of pose 0 may come
  // first).
  std::size_t next_landmark = 0;
  int reached = 0;
  auto flush = [&]() {
    while (next_landmark < g.landmark_measurements.size() &&
           g.landmark_measurements[next_landmark].pose <= reached) {
      landmark_line(g.landmark_measurements[next_landmark++]);
    }
  };
  flush();
  for (const auto& e : g.edges) {
    const Mat3 R = sqrt_information<3>(e.information, "an edge");
    s += fmt::format("EDGE2 {} {}", e.i, e.j);
    put(s, e.measurement.translation().x());
    put(s, e.measurement.translation().y());
    put(s, e.measurement.angle());
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) put(s, R(r, c));
    s += '\n';
    reached = std::max({reached, e.i, e.j});
    flush();
  }
  while (next_landmark < g.landmark_measurements.size())
    landmark_line(g.landmark_measurements[next_landmark++]);
  return s;
}

std::string isam_text(const PoseGraph3D& g) {
  detail::check_indices(g, "write_isam");
  check_chainable(g);
  std::string s;
  s.reserve(256 * g.edges.size());
  for (const auto& e : g.edges) {
    const Mat6 R = sqrt_information<6>(e.information, "an edge");
    s += fmt::format("EDGE3 {} {}", e.i, e.j);
    for (int a = 0; a < 3; ++a) put(s, e.measurement.translation()(a));
    const Vec3 rpy = rpy_for_writing(e.measurement.rotation());
    for (int a = 0; a < 3; ++a) put(s, rpy(a));
    for (int r = 0; r < 6; ++r)
      for (int c = r; c < 6; ++c) put(s, R(r, c));
    s += '\n';
  }
  return s;
}

double snap(double v, double step, double tol) {
  if (!(step > 0.0)) return v;
  const double k = std::round(v / step);
  const double snapped = k * step;
  return std::abs(v - snapped) <= tol ? snapped : v;
}

SE2 snap_pose(const SE2& T, const GroundTruthOptions& o) {
  return SE2(snap(T.translation().x(), o.translation_step, o.tolerance),
             snap(T.translation().y(), o.translation_step, o.tolerance),
             snap(T.angle(), o.angle_step, o.tolerance));
}

}  // namespace

lie::Vec3 rpy_for_writing(const Mat3& R) {
  const double pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  double yaw = std::atan2(R(1, 0), R(0, 0));
  if (std::hypot(R(0, 0), R(1, 0)) < 1e-12)
    yaw = std::atan2(-R(0, 1), R(1, 1));  // gimbal lock: roll absorbs the rest
  // Rx(roll) = Ry(pitch)ᵀ Rz(yaw)ᵀ R: taking roll from this residual makes Rz Ry Rx reproduce R even where
  // yaw and roll are individually ill-determined (|pitch| → π/2).
  const Mat3 res = lie::rotation_from_rpy(0.0, pitch, yaw).transpose() * R;
  const double roll = std::atan2(res(2, 1) - res(1, 2), res(1, 1) + res(2, 2));
  return Vec3(roll, pitch, yaw);
}

PoseGraph2D read_isam_2d(const std::filesystem::path& file) {
  return parse_isam_2d(read_file_text(file), file.string(), true);
}
PoseGraph2D read_isam_2d(std::istream& in, const std::string& name) {
  return parse_isam_2d(read_stream_text(in, name), name, true);
}
PoseGraph3D read_isam_3d(const std::filesystem::path& file) {
  return parse_isam_3d(read_file_text(file), file.string(), true);
}
PoseGraph3D read_isam_3d(std::istream& in, const std::string& name) {
  return parse_isam_3d(read_stream_text(in, name), name, true);
}

void write_isam(const PoseGraph2D& graph, std::ostream& out) { out << isam_text(graph); }
void write_isam(const PoseGraph3D& graph, std::ostream& out) { out << isam_text(graph); }
void write_isam(const PoseGraph2D& graph, const std::filesystem::path& file) {
  write_file_atomically(file, isam_text(graph));
}
void write_isam(const PoseGraph3D& graph, const std::filesystem::path& file) {
  write_file_atomically(file, isam_text(graph));
}

namespace {

GroundTruth2D ground_truth_2d(std::string_view text, const std::string& name, const GroundTruthOptions& o) {
  PoseGraph2D g = parse_isam_2d(text, name, false);
  const bool snapping = o.translation_step > 0.0 || o.angle_step > 0.0;
  if (snapping) {
    // Re-chain from snapped measurements, snapping each chained pose too (exact grid worlds).
    for (auto& e : g.edges) e.measurement = snap_pose(e.measurement, o);
    for (auto& m : g.landmark_measurements) {
      m.position = Vec2(snap(m.position.x(), o.translation_step, o.tolerance),
                        snap(m.position.y(), o.translation_step, o.tolerance));
    }
    std::vector<const Edge2*> odometry(g.poses.size(), nullptr);
    for (const auto& e : g.edges)
      if (e.j == e.i + 1 && !odometry[static_cast<std::size_t>(e.i)])
        odometry[static_cast<std::size_t>(e.i)] = &e;
    for (std::size_t k = 0; k + 1 < g.poses.size(); ++k) {
      g.poses[k + 1] = snap_pose(g.poses[k] * odometry[k]->measurement, o);
    }
    std::vector<char> done(g.landmarks.size(), 0);
    for (const auto& m : g.landmark_measurements) {
      auto& d = done[static_cast<std::size_t>(m.landmark)];
      if (d) continue;
      d = 1;
      const Vec2 p = g.poses[static_cast<std::size_t>(m.pose)] * m.position;
      g.landmarks[static_cast<std::size_t>(m.landmark)] =
          Vec2(snap(p.x(), o.translation_step, o.tolerance), snap(p.y(), o.translation_step, o.tolerance));
    }
  }
  GroundTruth2D gt;
  gt.poses = std::move(g.poses);
  gt.landmarks = std::move(g.landmarks);
  gt.source = name;
  for (const auto& e : g.edges) {
    const SE2 E = e.measurement.inverse() * gt.poses[static_cast<std::size_t>(e.i)].inverse() *
                  gt.poses[static_cast<std::size_t>(e.j)];
    gt.max_edge_translation_error = std::max(gt.max_edge_translation_error, E.translation().norm());
    gt.max_edge_rotation_error = std::max(gt.max_edge_rotation_error, std::abs(E.angle()));
  }
  for (const auto& m : g.landmark_measurements) {
    const Vec2 p = gt.poses[static_cast<std::size_t>(m.pose)] * m.position;
    gt.max_landmark_error =
        std::max(gt.max_landmark_error, (p - gt.landmarks[static_cast<std::size_t>(m.landmark)]).norm());
  }
  return gt;
}

GroundTruth3D ground_truth_3d(std::string_view text, const std::string& name, const GroundTruthOptions& o) {
  PoseGraph3D g = parse_isam_3d(text, name, false);
  if (o.translation_step > 0.0 || o.angle_step > 0.0) {
    throw std::invalid_argument("read_isam_ground_truth_3d: snapping is only defined for 2D grid worlds");
  }
  GroundTruth3D gt;
  gt.poses = std::move(g.poses);
  gt.source = name;
  for (const auto& e : g.edges) {
    const SE3 E = e.measurement.inverse() * gt.poses[static_cast<std::size_t>(e.i)].inverse() *
                  gt.poses[static_cast<std::size_t>(e.j)];
    gt.max_edge_translation_error = std::max(gt.max_edge_translation_error, E.translation().norm());
    gt.max_edge_rotation_error = std::max(gt.max_edge_rotation_error, E.so3().log().norm());
  }
  return gt;
}

}  // namespace

GroundTruth2D read_isam_ground_truth_2d(const std::filesystem::path& file,
                                        const GroundTruthOptions& options) {
  return ground_truth_2d(read_file_text(file), file.string(), options);
}
GroundTruth2D read_isam_ground_truth_2d(std::istream& in, const std::string& name,
                                        const GroundTruthOptions& options) {
  return ground_truth_2d(read_stream_text(in, name), name, options);
}
GroundTruth3D read_isam_ground_truth_3d(const std::filesystem::path& file,
                                        const GroundTruthOptions& options) {
  return ground_truth_3d(read_file_text(file), file.string(), options);
}
GroundTruth3D read_isam_ground_truth_3d(std::istream& in, const std::string& name,
                                        const GroundTruthOptions& options) {
  return ground_truth_3d(read_stream_text(in, name), name, options);
}

}  // namespace keel::graph
