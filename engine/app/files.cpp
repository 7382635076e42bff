#include "app/files.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/random.hpp"
#include "core/timing.hpp"
#include "graph/g2o.hpp"
#include "graph/io.hpp"
#include "graph/parse_error.hpp"
#include "graph/text_records.hpp"
#include "pgo/optimize.hpp"

namespace keel::app {

namespace {

// Union–find over the variables (poses, then landmarks).
struct Components {
  std::vector<int> parent;
  explicit Components(int n) : parent(static_cast<std::size_t>(n)) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  int find(int v) {
    while (parent[static_cast<std::size_t>(v)] != v) {
      parent[static_cast<std::size_t>(v)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
      v = parent[static_cast<std::size_t>(v)];
    }
    return v;
  }
  void join(int a, int b) { parent[static_cast<std::size_t>(find(a))] = find(b); }
};

// √diag Ω⁻¹ without a determinant: Ω is scaled by its largest entry s (so Ω/s has entries in [−1, 1] and
// neither 1e110 nor 1e-110 over- or underflows), factored by LDLᵀ with pivoting, and Ω⁻¹ = (Ω/s)⁻¹ / s.
template <int N>
Eigen::Matrix<double, N, 1> sigmas(const Eigen::Matrix<double, N, N>& W) {
  const double s = W.cwiseAbs().maxCoeff();
  const Eigen::Matrix<double, N, N> scaled = W / s;
  const Eigen::Matrix<double, N, N> inv = scaled.ldlt().solve(Eigen::Matrix<double, N, N>::Identity());
  return inv.diagonal().cwiseMax(0.0).cwiseSqrt() / std::sqrt(s);
}

// λ_max and λ_min of a symmetric matrix, computed on the matrix scaled by its largest entry.
template <int N>
std::pair<double, double> eigen_range(const Eigen::Matrix<double, N, N>& W) {
  const double s = W.cwiseAbs().maxCoeff();
  if (!(s > 0.0) || !std::isfinite(s)) return {s, 0.0};
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(W / s, Eigen::EigenvaluesOnly);
  return {eig.eigenvalues().maxCoeff() * s, eig.eigenvalues().minCoeff() * s};
}

// Counts, duplicates, noise levels of the edges; `dof` 3 (2D: x, y, θ) or 6 (3D: t, φ).
template <class Edge>
void summarize_edges(const std::vector<Edge>& edges, int translation_dims, GraphSummary& s, Components& cc) {
  std::set<std::pair<int, int>> seen;
  double st_min = std::numeric_limits<double>::infinity(), st_max = 0.0;
  double sr_min = std::numeric_limits<double>::infinity(), sr_max = 0.0;
  for (const auto& e : edges) {
    (std::abs(e.i - e.j) == 1 ? s.odometry : s.loop_closures) += 1;
    if (!seen.insert({std::min(e.i, e.j), std::max(e.i, e.j)}).second) ++s.duplicate_edges;
    const auto& W = e.information;
    const bool cross = (W - decltype(W)(W.diagonal().asDiagonal())).cwiseAbs().maxCoeff() > 0.0;
    if (cross) ++s.cross_term_edges;
    const auto sigma_of = sigmas(W);
    for (int k = 0; k < W.rows(); ++k) {
      const double sigma = sigma_of(k);
      if (k < translation_dims) {
        st_min = std::min(st_min, sigma);
        st_max = std::max(st_max, sigma);
      } else {
        sr_min = std::min(sr_min, sigma);
        sr_max = std::max(sr_max, sigma);
      }
    }
    const auto [lmax, lmin] = eigen_range(W);
    s.condition_max = std::max(s.condition_max, lmax / lmin);
    cc.join(e.i, e.j);
  }
  if (!edges.empty()) {
    s.sigma_translation_min = st_min;
    s.sigma_translation_max = st_max;
    s.sigma_rotation_min = sr_min;
    s.sigma_rotation_max = sr_max;
  }
}

constexpr double kEpsilon = 2.220446049250313e-16;  // 2⁻⁵², the rounding unit of a double

// M of check_numeric_range: max(1, largest vertex coordinate, Σ over edges of |t_z|∞).
template <class Graph>
double coordinate_scale(const Graph& g) {
  double m = 1.0, sum = 0.0;
  for (const auto& T : g.poses) m = std::max(m, T.translation().cwiseAbs().maxCoeff());
  for (const auto& e : g.edges) sum += e.measurement.translation().cwiseAbs().maxCoeff();
  if constexpr (requires { g.landmark_measurements; }) {
    for (const auto& p : g.landmarks) m = std::max(m, p.cwiseAbs().maxCoeff());
    for (const auto& lm : g.landmark_measurements) sum += lm.position.cwiseAbs().maxCoeff();
  }
  return std::max(m, sum);
}

template <class W>
void check_weight(const std::string& file, int line, const char* tag, const W& information, double M) {
  const auto [lmax, lmin] = eigen_range(information);
  (void)lmin;
  const double unit = kEpsilon * M;
  const double cost = lmax * unit * unit;
  if (std::isfinite(M) && std::isfinite(cost) && cost <= 1.0) return;
  const std::string where = line > 0 ? fmt::format("{}:{}", file, line) : file;
  if (!std::isfinite(M)) {
    throw std::invalid_argument(fmt::format(
        "{}: {}: the measured translations sum beyond the largest double: keel cannot solve at this scale",
        where, tag));
  }
  throw std::invalid_argument(fmt::format(
      "{}: {}: information of largest eigenvalue {:.4g} at coordinates up to M = {:.4g} (the largest vertex "
      "coordinate or the sum of the measured translations): one rounding unit of a coordinate (ε·M = {:.3g}) "
      "would cost {:.3g} > 1, so the solved cost would be rounding noise; keel refuses λ_max(Ω)·(ε·M)² > 1 "
      "(here: λ_max above {:.4g}, or smaller coordinates)",
      where, tag, lmax, M, unit, cost, 1.0 / (unit * unit)));
}

void count_components(GraphSummary& s, Components& cc, int variables) {
  std::map<int, int> size;
  for (int v = 0; v < variables; ++v) ++size[cc.find(v)];
  s.components = static_cast<int>(size.size());
  for (const auto& [root, n] : size) s.largest_component = std::max(s.largest_component, n);
}

}  // namespace

void check_numeric_range(const graph::PoseGraph2D& g) {
  const double M = coordinate_scale(g);
  for (const auto& e : g.edges) check_weight(g.source, e.line, "EDGE_SE2", e.information, M);
  for (const auto& m : g.landmark_measurements) check_weight(g.source, m.line, "LANDMARK", m.information, M);
}

void check_numeric_range(const graph::PoseGraph3D& g) {
  const double M = coordinate_scale(g);
  for (const auto& e : g.edges) check_weight(g.source, e.line, "EDGE_SE3:QUAT", e.information, M);
}

int graph_dimension(std::string_view text, const std::string& name) {
  graph::RecordScanner sc(text, name);
  while (sc.next()) {
    const std::string_view tag = sc.tag();
    if (tag == "FIX") continue;  // g2o's FIX line holds no dimension
    return (tag == "EDGE_SE3:QUAT" || tag == "VERTEX_SE3:QUAT" || tag == "EDGE3") ? 3 : 2;
  }
  return 2;
}

int graph_dimension(const std::filesystem::path& file) {
  return graph_dimension(graph::read_file_text(file), file.string());
}

GraphSummary summarize(const std::filesystem::path& file) {
  GraphSummary s;
  s.file = file.string();
  // The file is read once (a pipe or FIFO works) and parsed from memory.
  const std::string text = graph::read_file_text(file);
  s.dimension = graph_dimension(text, s.file);
  const auto format = graph::detect_graph_format(text, file);
  s.format = format ? std::string(graph::to_string(*format)) : "unknown";
  std::istringstream in(text);
  if (s.dimension == 2) {
    const auto g = graph::read_pose_graph_2d(in, s.file);
    check_numeric_range(g);  // what solve refuses, check refuses
    s.poses = static_cast<int>(g.poses.size());
    s.edges = static_cast<int>(g.edges.size());
    s.landmarks = static_cast<int>(g.landmarks.size());
    s.landmark_measurements = static_cast<int>(g.landmark_measurements.size());
    s.has_initial_poses = g.has_initial_poses;
    Components cc(s.poses + s.landmarks);
    summarize_edges(g.edges, 2, s, cc);
    for (const auto& m : g.landmark_measurements) cc.join(m.pose, s.poses + m.landmark);
    count_components(s, cc, s.poses + s.landmarks);
  } else {
    const auto g = graph::read_pose_graph_3d(in, s.file);
    check_numeric_range(g);
    s.poses = static_cast<int>(g.poses.size());
    s.edges = static_cast<int>(g.edges.size());
    s.has_initial_poses = g.has_initial_poses;
    Components cc(s.poses);
    summarize_edges(g.edges, 3, s, cc);
    count_components(s, cc, s.poses);
  }
  return s;
}

sim::CandidateSet2 split_files(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& ground_truth,
                               const SplitFilesOptions& options, const std::filesystem::path& dir) {
  const auto scenario = sim::split_two_robots(graph, ground_truth, options.split);
  auto set = sim::generate_candidates(scenario, options.candidates, options.seed, 0);
  std::filesystem::create_directories(dir);
  // The local graphs with vertices: the input's poses re-expressed (split_two_robots), or chained odometry.
  auto with_poses = [](graph::PoseGraph2D g) {
    if (g.poses.empty()) {
      pgo::Options o;
      o.initial_guess = pgo::InitialGuess::odometry;
      g.poses = pgo::initial_estimate(g, o).poses;
    }
    return g;
  };
  graph::write_pose_graph(with_poses(scenario.robot_a), dir / "a.g2o");
  graph::write_pose_graph(with_poses(scenario.robot_b), dir / "b.g2o");
  std::vector<graph::Edge2> edges;
  std::string labels = "# candidate kind group (written by keel split; inlier = a true loop closure)\n";
  for (std::size_t k = 0; k < set.candidates.size(); ++k) {
    const auto& c = set.candidates[k];
    edges.push_back({c.pose_a, c.pose_b, c.z, set.information[k], 0});
    labels += fmt::format("{} {} {}\n", k, sim::to_string(set.labels[k].kind), set.labels[k].group);
  }
  graph::write_g2o_edges(edges, dir / "candidates.g2o");
  graph::write_file_atomically(dir / "labels.txt", labels);
  const auto& T = scenario.true_anchor;
  graph::write_file_atomically(
      dir / "truth.txt", fmt::format("# T_ab: x y theta of robot b's frame in robot a's frame\n{} {} {}\n",
                                     graph::fmt17(T.translation().x()), graph::fmt17(T.translation().y()),
                                     graph::fmt17(T.angle())));
  return set;
}

namespace {

template <class Graph>
int robot_files_impl(const Graph& input, const RobotFilesOptions& o, const std::filesystem::path& dir) {
  if (o.robots < 1)
    throw std::invalid_argument(fmt::format("RobotFilesOptions: robots must be >= 1 (got {})", o.robots));
  o.wrong.validate();
  // The wrong closures (appended after the graph's own edges), then the cut.
  Graph g = input;
  std::vector<char> wrong(g.edges.size(), 0);
  if (o.wrong.rate > 0.0) {
    const auto corrupted = sim::add_wrong_loop_closures(input, o.wrong, core::Streams(o.seed), 0);
    g = corrupted.graph;
    wrong.assign(g.edges.size(), 0);
    for (const int k : corrupted.outliers) wrong[static_cast<std::size_t>(k)] = 1;
  }
  const auto split = sim::split_into_robots(g, o.robots);
  std::filesystem::create_directories(dir);
  std::string lines =
      "# i j file edge kind (written by keel split: every loop closure, its ids global, the file and edge "
      "index "
      "it went to; kind true or wrong)\n";
  auto line = [&](int graph_edge, const std::string& file, std::size_t k) {
    const auto& e = g.edges[static_cast<std::size_t>(graph_edge)];
    if (std::abs(e.j - e.i) == 1) return;  // odometry
    lines += fmt::format("{} {} {} {} {}\n", e.i, e.j, file, k,
                         wrong[static_cast<std::size_t>(graph_edge)] ? "wrong" : "true");
  };
  for (int r = 0; r < o.robots; ++r) {
    const std::string file = fmt::format("robot{}.g2o", r);
    graph::write_g2o(split.robots[static_cast<std::size_t>(r)], dir / file);
    for (std::size_t k = 0; k < split.robot_edge[static_cast<std::size_t>(r)].size(); ++k)
      line(split.robot_edge[static_cast<std::size_t>(r)][k], file, k);
  }
  if (o.robots > 1) {
    graph::write_g2o_edges(split.inter, dir / "candidates.g2o");
    for (std::size_t k = 0; k < split.inter.size(); ++k) line(split.inter_edge[k], "candidates.g2o", k);
  }
  graph::write_file_atomically(dir / "closures.txt", lines);
  return static_cast<int>(std::count(wrong.begin(), wrong.end(), 1));
}

}  // namespace

int robot_files(const graph::PoseGraph2D& graph, const RobotFilesOptions& options,
                const std::filesystem::path& dir) {
  return robot_files_impl(graph, options, dir);
}
int robot_files(const graph::PoseGraph3D& graph, const RobotFilesOptions& options,
                const std::filesystem::path& dir) {
  return robot_files_impl(graph, options, dir);
}

std::vector<bool> read_labels(const std::filesystem::path& file) {
  const std::string text = graph::read_file_text(file);
  graph::RecordScanner sc(text, file.string(), "label");
  static constexpr std::array<const char*, 3> kNames = {"candidate", "kind", "group"};
  std::vector<bool> inlier;
  while (sc.next()) {
    sc.expect(kNames);
    const int k = sc.id(1);
    if (k != static_cast<int>(inlier.size())) {
      sc.fail_field(
          1, fmt::format("expected candidate {} (labels list the candidates in order)", inlier.size()));
    }
    const std::string kind(sc.field(2));
    try {
      inlier.push_back(sim::measurement_label_from_string(kind) == sim::MeasurementLabel::inlier);
    } catch (const std::invalid_argument& e) {
      sc.fail_field(2, e.what());
    }
  }
  if (inlier.empty()) graph::fail_at(file.string(), 0, "no label");
  return inlier;
}

}  // namespace keel::app
