#include "graph/build.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "graph/parse_error.hpp"

namespace keel::graph::detail {

namespace {

template <int N>
std::string information_problem_n(const Eigen::Matrix<double, N, N>& W) {
  if (!W.allFinite()) return "has a non-finite entry (overflow)";
  Eigen::Matrix<double, N, 1> d;
  for (int k = 0; k < N; ++k) {
    if (!(W(k, k) > 0.0)) {
      return fmt::format("is not positive definite: diagonal entry ({},{}) = {:.6g} is not positive", k + 1,
                         k + 1, W(k, k));
    }
    d(k) = 1.0 / std::sqrt(W(k, k));
  }
  const Eigen::Matrix<double, N, N> S = d.asDiagonal() * W * d.asDiagonal();
  if (!S.allFinite()) return "has entries too large for its diagonal (not positive definite)";
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(S, Eigen::EigenvaluesOnly);
  const double lo = es.eigenvalues()(0);
  if (es.info() != Eigen::Success || !(lo > 1e-10)) {
    return fmt::format(
        "is not positive definite (smallest eigenvalue of the unit-diagonal scaled matrix: {:.3g})", lo);
  }
  return {};
}

struct Appearance {
  int line = 0;
  std::string what;
};

// First record (in file order) that names pose `id`.
template <class Graph>
Appearance first_appearance(const Graph& g, int id, const std::string& edge_tag) {
  Appearance best;
  for (const auto& e : g.edges) {
    if ((e.i == id || e.j == id) && (best.line == 0 || e.line < best.line)) {
      best.line = e.line;
      best.what = edge_tag + (e.i == id ? " field 1 (i)" : " field 2 (j)");
    }
  }
  if constexpr (requires { g.landmark_measurements; }) {
    for (const auto& m : g.landmark_measurements) {
      if (m.pose == id && (best.line == 0 || m.line < best.line)) {
        best.line = m.line;
        best.what = "LANDMARK field 1 (i)";
      }
    }
  }
  return best;
}

template <class Graph, class Vertex>
void assemble_poses(Graph& g, const std::vector<Vertex>& vertices, const std::string& vertex_tag,
                    const std::string& edge_tag) {
  const std::string& name = g.source;
  if (!vertices.empty()) {
    std::unordered_map<int, int> seen;  // id -> line
    for (const auto& v : vertices) {
      auto [it, fresh] = seen.emplace(v.id, v.line);
      if (!fresh) {
        fail_at(name, v.line,
                fmt::format("{} field 1 (id): duplicate vertex id {} (first defined on line {})", vertex_tag,
                            v.id, it->second));
      }
    }
    const std::size_t n = vertices.size();
    for (const auto& v : vertices) {
      if (static_cast<std::size_t>(v.id) >= n) {
        std::vector<char> have(n, 0);
        for (const auto& w : vertices)
          if (static_cast<std::size_t>(w.id) < n) have[static_cast<std::size_t>(w.id)] = 1;
        std::size_t missing = 0;
        while (missing < n && have[missing]) ++missing;
        fail_at(
            name, v.line,
            fmt::format("{} field 1 (id): vertex ids must be contiguous from 0, but id {} is missing ({} {} "
                        "lines, this one has id {})",
                        vertex_tag, missing, n, vertex_tag, v.id));
      }
    }
    std::vector<char> used(n, 0);
    for (const auto& e : g.edges) {
      if (static_cast<std::size_t>(e.i) >= n || !seen.count(e.i)) {
        fail_at(name, e.line,
                fmt::format("{} field 1 (i): pose {} has no {} line", edge_tag, e.i, vertex_tag));
      }
      if (static_cast<std::size_t>(e.j) >= n || !seen.count(e.j)) {
        fail_at(name, e.line,
                fmt::format("{} field 2 (j): pose {} has no {} line", edge_tag, e.j, vertex_tag));
      }
      used[static_cast<std::size_t>(e.i)] = used[static_cast<std::size_t>(e.j)] = 1;
    }
    if constexpr (requires { g.landmark_measurements; }) {
      for (const auto& m : g.landmark_measurements) {
        if (static_cast<std::size_t>(m.pose) >= n) {
          fail_at(name, m.line,
                  fmt::format("LANDMARK field 1 (i): pose {} has no {} line", m.pose, vertex_tag));
        }
        used[static_cast<std::size_t>(m.pose)] = 1;
      }
    }
    if (n > 1) {
      for (const auto& v : vertices) {
        if (!used[static_cast<std::size_t>(v.id)]) {
          fail_at(
              name, v.line,
              fmt::format("{} field 1 (id): vertex {} is used by no edge (a dangling vertex leaves the graph "
                          "disconnected)",
                          vertex_tag, v.id));
        }
      }
    }
    g.poses.assign(n, {});
    for (const auto& v : vertices) g.poses[static_cast<std::size_t>(v.id)] = v.pose;
    g.has_initial_poses = true;
    return;
  }

  // No vertices: chain the odometry edges (i, i+1).
  int max_id = -1;
  for (const auto& e : g.edges) max_id = std::max({max_id, e.i, e.j});
  if constexpr (requires { g.landmark_measurements; }) {
    for (const auto& m : g.landmark_measurements) max_id = std::max(max_id, m.pose);
  }
  if (max_id < 0) fail_at(name, 0, fmt::format("no {} or edge records (empty file?)", vertex_tag));
  std::unordered_map<int, std::size_t> odometry;  // i -> index of the first edge (i, i+1)
  for (std::size_t k = 0; k < g.edges.size(); ++k) {
    const auto& e = g.edges[k];
    if (e.j == e.i + 1) odometry.emplace(e.i, k);
  }
  // Terminates within edges.size() + 1 steps (each step needs a distinct odometry edge), so max_id cannot
  // make us allocate or loop more than the file's size allows.
  for (int k = 0; k < max_id; ++k) {
    if (!odometry.count(k)) {
      const std::string head = fmt::format(
          "no odometry edge ({}, {}): the file has no {} lines, so the initial estimate chains the edges (i, "
          "i+1), and "
          "pose {}",
          k, k + 1, vertex_tag, k + 1);
      const Appearance a = first_appearance(g, k + 1, edge_tag);
      if (a.line > 0) fail_at(name, 0, fmt::format("{} first appears on line {} ({})", head, a.line, a.what));
      const Appearance top = first_appearance(g, max_id, edge_tag);
      fail_at(name, 0,
              fmt::format(
                  "{} is named by no record, though pose ids must be contiguous from 0 (the largest, {}, is "
                  "on line {} ({}))",
                  head, max_id, top.line, top.what));
    }
  }
  const std::size_t n = static_cast<std::size_t>(max_id) + 1;
  g.poses.assign(n, {});
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const auto& e = g.edges[odometry.at(static_cast<int>(k))];
    g.poses[k + 1] = g.poses[k] * e.measurement;
    if (!g.poses[k + 1].matrix().allFinite()) {
      fail_at(name, e.line,
              fmt::format("{}: chaining the odometry overflows at pose {} (measurement too large)", edge_tag,
                          k + 1));
    }
  }
  g.has_initial_poses = false;
}

}  // namespace

void assemble(PoseGraph2D& g, const std::vector<Vertex2>& vertices, const std::string& vertex_tag,
              const std::string& edge_tag) {
  assemble_poses(g, vertices, vertex_tag, edge_tag);
  // Landmarks: ids contiguous from 0, initial position from the first measurement.
  if (g.landmark_measurements.empty()) {
    g.landmarks.clear();
    return;
  }
  std::unordered_map<int, std::size_t> first;  // landmark id -> index of its first measurement
  for (std::size_t k = 0; k < g.landmark_measurements.size(); ++k)
    first.emplace(g.landmark_measurements[k].landmark, k);
  const std::size_t count = first.size();
  for (const auto& m : g.landmark_measurements) {
    if (static_cast<std::size_t>(m.landmark) >= count) {
      std::size_t missing = 0;
      while (first.count(static_cast<int>(missing))) ++missing;
      fail_at(g.source, m.line,
              fmt::format(
                  "LANDMARK field 2 (l): landmark ids must be contiguous from 0, but landmark {} is never "
                  "observed ({} distinct landmarks, this one has id {})",
                  missing, count, m.landmark));
    }
  }
  g.landmarks.assign(count, Vec2::Zero());
  for (const auto& [id, k] : first) {
    const auto& m = g.landmark_measurements[k];
    const Vec2 p = g.poses[static_cast<std::size_t>(m.pose)] * m.position;
    if (!p.allFinite()) fail_at(g.source, m.line, "LANDMARK: the landmark's initial position overflows");
    g.landmarks[static_cast<std::size_t>(id)] = p;
  }
}

void assemble(PoseGraph3D& g, const std::vector<Vertex3>& vertices, const std::string& vertex_tag,
              const std::string& edge_tag) {
  assemble_poses(g, vertices, vertex_tag, edge_tag);
}

// The gauge pose names a pose of the graph (pose 0 of an empty graph is the default).
template <class Graph>
void check_gauge(const Graph& g, const char* writer) {
  if (g.gauge_pose == 0) return;
  if (g.gauge_pose < 0 || static_cast<std::size_t>(g.gauge_pose) >= g.poses.size()) {
    throw std::invalid_argument(fmt::format("{}: the gauge pose {} is outside the graph ({} poses)", writer,
                                            g.gauge_pose, g.poses.size()));
  }
}

void check_indices(const PoseGraph2D& g, const char* writer) {
  check_gauge(g, writer);
  const auto n = static_cast<int>(g.poses.size());
  for (const auto& e : g.edges) {
    if (e.i < 0 || e.j < 0 || e.i >= n || e.j >= n) {
      throw std::invalid_argument(
          fmt::format("{}: edge ({}, {}) names a pose outside the graph ({} poses)", writer, e.i, e.j, n));
    }
  }
  const auto l = static_cast<int>(g.landmarks.size());
  for (const auto& m : g.landmark_measurements) {
    if (m.pose < 0 || m.pose >= n || m.landmark < 0 || m.landmark >= l) {
      throw std::invalid_argument(
          fmt::format("{}: landmark measurement ({}, {}) names a pose or landmark outside the graph", writer,
                      m.pose, m.landmark));
    }
  }
}

void check_indices(const PoseGraph3D& g, const char* writer) {
  check_gauge(g, writer);
  const auto n = static_cast<int>(g.poses.size());
  for (const auto& e : g.edges) {
    if (e.i < 0 || e.j < 0 || e.i >= n || e.j >= n) {
      throw std::invalid_argument(
          fmt::format("{}: edge ({}, {}) names a pose outside the graph ({} poses)", writer, e.i, e.j, n));
    }
  }
}

}  // namespace keel::graph::detail

namespace keel::graph {

std::string information_problem(const Mat2& W) { return detail::information_problem_n<2>(W); }
std::string information_problem(const Mat3& W) { return detail::information_problem_n<3>(W); }
std::string information_problem(const Mat6& W) { return detail::information_problem_n<6>(W); }

bool rotation_from_quaternion(const double* q, Mat3& R, std::string& why) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-3) {
    why = fmt::format("quaternion norm {:.6g} is not 1 (tolerance 1e-3)", n);
    return false;
  }
  const Eigen::Quaterniond quat(q[3] / n, q[0] / n, q[1] / n, q[2] / n);
  R = quat.toRotationMatrix();
  return true;
}

void quaternion_from_rotation(const Mat3& R, double* q) {
  Eigen::Quaterniond quat(R);
  quat.normalize();
  if (quat.w() < 0.0) quat.coeffs() *= -1.0;
  q[0] = quat.x();
  q[1] = quat.y();
  q[2] = quat.z();
  q[3] = quat.w();
}

}  // namespace keel::graph
