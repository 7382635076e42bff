#include "sim/loop_closures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "core/names.hpp"
#include "sim/random_pose.hpp"

namespace keel::sim {

void LoopClosureCorruption::validate() const {
  if (first_poses < 0)
    throw std::invalid_argument(
        fmt::format("LoopClosureCorruption.first_poses = {}: must be >= 0 (0: every pose)", first_poses));
  if (!(rotation_noise >= 0) || !std::isfinite(rotation_noise))
    throw std::invalid_argument(fmt::format(
        "LoopClosureCorruption.rotation_noise = {}: must be a finite angle >= 0 (rad)", rotation_noise));
  if (!(outlier_fraction >= 0 && outlier_fraction <= 1))
    throw std::invalid_argument(
        fmt::format("LoopClosureCorruption.outlier_fraction = {}: must be in [0, 1]", outlier_fraction));
}

namespace {

lie::SE2 noisy(const lie::SE2& z, double sigma, core::Rng& rng) {
  const double n = rng.normal();
  return lie::SE2(lie::SO2(z.angle() + sigma * n), z.translation());
}
lie::SE3 noisy(const lie::SE3& z, double sigma, core::Rng& rng) {
  lie::Vec3 n;
  for (int k = 0; k < 3; ++k) n(k) = rng.normal();
  return lie::SE3(z.so3() * lie::SO3::exp(sigma * n), z.translation());
}

// The first `first_poses` poses of g (0: all) and the edges among them, as read; `loop_closures` filled,
// `outliers` empty. `what` names the caller in errors.
template <class Graph>
CorruptedGraph<Graph> first_poses_of(const Graph& g, int first_poses, const char* what) {
  using Pose = std::remove_cvref_t<decltype(g.poses[0])>;
  if constexpr (std::is_same_v<Pose, lie::SE2>) {
    if (!g.landmarks.empty() || !g.landmark_measurements.empty())
      throw std::invalid_argument(
          fmt::format("{}: {} has landmarks (pose graphs without landmarks only)", what, g.source));
  }
  const int n = static_cast<int>(g.poses.size());
  if (first_poses > n)
    throw std::invalid_argument(
        fmt::format("{}: first_poses = {} but {} has {} poses", what, first_poses, g.source, n));
  const int keep = first_poses == 0 ? n : first_poses;
  CorruptedGraph<Graph> out;
  Graph& h = out.graph;
  h.poses.assign(g.poses.begin(), g.poses.begin() + keep);
  h.has_initial_poses = g.has_initial_poses;
  h.indefinite_information = g.indefinite_information;  // the source's count (a bound for a subset)
  h.gauge_pose = g.gauge_pose < keep ? g.gauge_pose : 0;
  h.source = g.source;
  for (const auto& e : g.edges) {
    if (e.i >= keep || e.j >= keep) continue;
    if (std::abs(e.i - e.j) != 1) out.loop_closures.push_back(static_cast<int>(h.edges.size()));
    h.edges.push_back(e);
  }
  return out;
}

// s of the random measurements: the largest absolute coordinate of any loop closure's measured translation (1
// if all are zero).
template <class Graph>
double closure_span(const CorruptedGraph<Graph>& c) {
  double span = 0;
  for (int e : c.loop_closures)
    span = std::max(
        span, c.graph.edges[static_cast<std::size_t>(e)].measurement.translation().cwiseAbs().maxCoeff());
  return span > 0 ? span : 1.0;
}

template <class Graph>
CorruptedGraph<Graph> corrupt(const Graph& g, const LoopClosureCorruption& o, const core::Streams& streams,
                              std::uint64_t index) {
  o.validate();
  using Pose = std::remove_cvref_t<decltype(g.poses[0])>;
  constexpr int kDim = std::is_same_v<Pose, lie::SE2> ? 2 : 3;
  CorruptedGraph<Graph> out = first_poses_of(g, o.first_poses, "corrupt_loop_closures");
  Graph& h = out.graph;
  // The outliers: a uniformly random ordering of the loop closures (Fisher–Yates), its first round(f·L).
  const auto L = out.loop_closures.size();
  std::vector<int> order = out.loop_closures;
  core::Rng order_rng = streams.child("order").stream(index);
  for (std::size_t k = L; k > 1; --k) {
    const auto r =
        std::min<std::size_t>(static_cast<std::size_t>(order_rng.uniform() * static_cast<double>(k)), k - 1);
    std::swap(order[k - 1], order[r]);
  }
  const auto outliers = static_cast<std::size_t>(std::llround(o.outlier_fraction * static_cast<double>(L)));
  out.outliers.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(outliers));
  std::sort(out.outliers.begin(), out.outliers.end());
  std::vector<char> is_outlier(h.edges.size(), 0);
  for (int e : out.outliers) is_outlier[static_cast<std::size_t>(e)] = 1;
  const double span = closure_span(out);
  // Every loop closure draws its noise direction and its outlier pose, in edge order, whatever it becomes.
  core::Rng noise_rng = streams.child("noise").stream(index);
  core::Rng outlier_rng = streams.child("outlier").stream(index);
  for (int e : out.loop_closures) {
    auto& edge = h.edges[static_cast<std::size_t>(e)];
    const Pose with_noise = noisy(edge.measurement, o.rotation_noise, noise_rng);
    const auto R = detail::random_rotation(outlier_rng, static_cast<const Pose*>(nullptr));
    typename Pose::Point t;
    for (int d = 0; d < kDim; ++d) t(d) = outlier_rng.uniform(-span, span);
    edge.measurement = is_outlier[static_cast<std::size_t>(e)] ? Pose(R, t) : with_noise;
  }
  return out;
}

template <class Graph>
CorruptedGraph<Graph> add_wrong(const Graph& g, const WrongClosures& o, const core::Streams& streams,
                                std::uint64_t index) {
  o.validate();
  using Pose = std::remove_cvref_t<decltype(g.poses[0])>;
  constexpr int kDim = std::is_same_v<Pose, lie::SE2> ? 2 : 3;
  CorruptedGraph<Graph> out = first_poses_of(g, o.first_poses, "add_wrong_loop_closures");
  Graph& h = out.graph;
  const int n = static_cast<int>(h.poses.size());
  const auto L = out.loop_closures.size();
  const auto m = static_cast<std::size_t>(std::llround(o.rate / (1.0 - o.rate) * static_cast<double>(L)));
  if (L == 0 && o.rate > 0)
    throw std::invalid_argument(fmt::format(
        "add_wrong_loop_closures: {} has no loop closure among its first {} poses, so no information to copy",
        g.source, n));
  if (m == 0) return out;
  // The poses chained from the odometry, pose 0 at the identity.
  std::vector<Pose> chain(static_cast<std::size_t>(n));
  std::vector<int> odometry(static_cast<std::size_t>(n), -1);  // the edge that reaches pose k from k − 1
  for (std::size_t k = 0; k < h.edges.size(); ++k) {
    const auto& e = h.edges[k];
    if (std::abs(e.i - e.j) == 1 && odometry[static_cast<std::size_t>(std::max(e.i, e.j))] < 0)
      odometry[static_cast<std::size_t>(std::max(e.i, e.j))] = static_cast<int>(k);
  }
  for (int k = 1; k < n; ++k) {
    const int e = odometry[static_cast<std::size_t>(k)];
    if (e < 0)
      throw std::invalid_argument(fmt::format(
          "add_wrong_loop_closures: {}: pose {} has no odometry edge from pose {}", g.source, k, k - 1));
    const auto& edge = h.edges[static_cast<std::size_t>(e)];
    const Pose step = edge.j == k ? Pose(edge.measurement) : Pose(edge.measurement.inverse());
    chain[static_cast<std::size_t>(k)] = chain[static_cast<std::size_t>(k) - 1] * step;
  }
  const double span = closure_span(out);
  core::Rng rng = streams.child("wrong").stream(index);
  const auto uniform_below = [&](int k) {
    return std::min(static_cast<int>(rng.uniform() * static_cast<double>(k)), k - 1);
  };
  const auto random_pose = [&] {
    const auto R = detail::random_rotation(rng, static_cast<const Pose*>(nullptr));
    typename Pose::Point t;
    for (int d = 0; d < kDim; ++d) t(d) = rng.uniform(-span, span);
    return Pose(R, t);
  };
  const auto information = [&] {
    return h
        .edges[static_cast<std::size_t>(
            out.loop_closures[static_cast<std::size_t>(uniform_below(static_cast<int>(L)))])]
        .information;
  };
  auto edge_like = h.edges[static_cast<std::size_t>(out.loop_closures[0])];
  edge_like.line = 0;
  const std::size_t first_wrong = h.edges.size();
  if (o.kind == WrongClosureKind::random) {
    if (n < 3)
      throw std::invalid_argument(
          fmt::format("add_wrong_loop_closures: {} poses hold no pair two or more apart", n));
    while (h.edges.size() - first_wrong < m) {
      const int i = uniform_below(n), j = uniform_below(n);
      if (std::abs(i - j) < 2) continue;
      auto e = edge_like;
      e.i = i, e.j = j;
      e.measurement = random_pose();
      e.information = information();
      h.edges.push_back(e);
    }
  } else {
    const int gs = o.group_size;
    if (n < 2 * gs + 1)
      throw std::invalid_argument(fmt::format(
          "add_wrong_loop_closures: aliased groups of {} need two blocks of {} poses one apart; {} has {}",
          gs, gs, g.source, n));
    while (h.edges.size() - first_wrong < m) {
      int a = 0, b = 0;
      do {
        a = uniform_below(n - gs + 1);
        b = uniform_below(n - gs + 1);
      } while (std::abs(a - b) < gs + 1);
      const Pose A = random_pose();
      const Pose anchor =
          chain[static_cast<std::size_t>(a)] * A * chain[static_cast<std::size_t>(b)].inverse();
      for (int k = 0; k < gs && h.edges.size() - first_wrong < m; ++k) {
        auto e = edge_like;
        e.i = a + k, e.j = b + k;
        e.information = information();
        const Pose z_bar = Pose(chain[static_cast<std::size_t>(e.i)].inverse() * anchor *
                                chain[static_cast<std::size_t>(e.j)]);
        e.measurement = detail::redraw(rng, z_bar, e.information, 1.0);
        h.edges.push_back(e);
      }
    }
  }
  for (std::size_t k = first_wrong; k < h.edges.size(); ++k) {
    out.loop_closures.push_back(static_cast<int>(k));
    out.outliers.push_back(static_cast<int>(k));
  }
  return out;
}

template <class Graph>
RobotSplit<Graph> split(const Graph& g, int robots) {
  const int n = static_cast<int>(g.poses.size());
  if (robots < 1 || robots > n)
    throw std::invalid_argument(fmt::format(
        "split_into_robots: {} robots asked of {} with {} poses (1 … poses)", robots, g.source, n));
  RobotSplit<Graph> out;
  std::vector<int> first(static_cast<std::size_t>(robots) + 1);
  for (int r = 0; r <= robots; ++r)
    first[static_cast<std::size_t>(r)] = static_cast<int>(static_cast<long long>(r) * n / robots);
  const auto robot_of = [&](int id) { return robot_of_pose(id, n, robots); };
  out.robots.resize(static_cast<std::size_t>(robots));
  out.robot_edge.resize(static_cast<std::size_t>(robots));
  for (int r = 0; r < robots; ++r) {
    Graph& h = out.robots[static_cast<std::size_t>(r)];
    h.poses.assign(g.poses.begin() + first[static_cast<std::size_t>(r)],
                   g.poses.begin() + first[static_cast<std::size_t>(r) + 1]);
    h.has_initial_poses = g.has_initial_poses;
    h.source = robots == 1 ? g.source : fmt::format("{} robot {}", g.source, r);
  }
  for (std::size_t k = 0; k < g.edges.size(); ++k) {
    auto e = g.edges[k];
    const int ra = robot_of(e.i), rb = robot_of(e.j);
    if (ra == rb) {
      e.i -= first[static_cast<std::size_t>(ra)];
      e.j -= first[static_cast<std::size_t>(ra)];
      out.robots[static_cast<std::size_t>(ra)].edges.push_back(e);
      out.robot_edge[static_cast<std::size_t>(ra)].push_back(static_cast<int>(k));
    } else if (std::abs(e.i - e.j) != 1) {
      out.inter.push_back(e);
      out.inter_edge.push_back(static_cast<int>(k));
    }
  }
  return out;
}

}  // namespace

constexpr core::NameTable<WrongClosureKind, 2> kWrongClosureKinds{
    "sim::WrongClosureKind",
    {{{WrongClosureKind::random, "random"}, {WrongClosureKind::aliased, "aliased"}}}};

std::string_view to_string(WrongClosureKind kind) { return kWrongClosureKinds.name(kind); }
WrongClosureKind wrong_closure_kind_from_string(std::string_view text) {
  return kWrongClosureKinds.parse(text);
}

void WrongClosures::validate() const {
  if (first_poses < 0)
    throw std::invalid_argument(
        fmt::format("WrongClosures.first_poses = {}: must be >= 0 (0: every pose)", first_poses));
  if (!(rate >= 0 && rate < 1))
    throw std::invalid_argument(fmt::format(
        "WrongClosures.rate = {}: must be in [0, 1) (the share of wrong closures among all loop closures)",
        rate));
  if (group_size < 1)
    throw std::invalid_argument(fmt::format("WrongClosures.group_size = {}: must be >= 1", group_size));
}

CorruptedGraph2 add_wrong_loop_closures(const graph::PoseGraph2D& g, const WrongClosures& o,
                                        const core::Streams& streams, std::uint64_t index) {
  return add_wrong(g, o, streams, index);
}
CorruptedGraph3 add_wrong_loop_closures(const graph::PoseGraph3D& g, const WrongClosures& o,
                                        const core::Streams& streams, std::uint64_t index) {
  return add_wrong(g, o, streams, index);
}
int robot_of_pose(int id, int poses, int robots) {
  // Robot r holds [⌊r n / R⌋, ⌊(r + 1) n / R⌋): the largest r whose first pose is at most id.
  int r = static_cast<int>(static_cast<long long>(id) * robots / poses);
  while (r > 0 && static_cast<long long>(r) * poses / robots > id) --r;
  while (r + 1 < robots && static_cast<long long>(r + 1) * poses / robots <= id) ++r;
  return r;
}

RobotSplit<graph::PoseGraph2D> split_into_robots(const graph::PoseGraph2D& g, int robots) {
  return split(g, robots);
}
RobotSplit<graph::PoseGraph3D> split_into_robots(const graph::PoseGraph3D& g, int robots) {
  return split(g, robots);
}

CorruptedGraph2 corrupt_loop_closures(const graph::PoseGraph2D& g, const LoopClosureCorruption& o,
                                      const core::Streams& streams, std::uint64_t index) {
  return corrupt(g, o, streams, index);
}
CorruptedGraph3 corrupt_loop_closures(const graph::PoseGraph3D& g, const LoopClosureCorruption& o,
                                      const core::Streams& streams, std::uint64_t index) {
  return corrupt(g, o, streams, index);
}

}  // namespace keel::sim
