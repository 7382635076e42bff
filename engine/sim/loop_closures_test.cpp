#include "sim/loop_closures.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "graph/io.hpp"
#include "kit/test_kit.hpp"

using keel::core::Streams;
using keel::sim::corrupt_loop_closures;
using keel::sim::LoopClosureCorruption;
using keel::testkit::throws_with;
namespace graph = keel::graph;
namespace lie = keel::lie;

namespace {

// A chain of n poses on a circle with odometry (i, i + 1) and a loop closure (i, i + 7) at every third i.
template <class Graph>
Graph ring(int n) {
  Graph g;
  g.source = "ring";
  using Pose = std::remove_cvref_t<decltype(g.poses[0])>;
  for (int i = 0; i < n; ++i) {
    const double a = 0.1 * i;
    if constexpr (std::is_same_v<Pose, lie::SE2>)
      g.poses.push_back(lie::SE2(10 * std::cos(a), 10 * std::sin(a), a + 1.5));
    else
      g.poses.push_back(lie::SE3(lie::SO3::exp(lie::Vec3(0.1, 0.2, a)),
                                 lie::Vec3(10 * std::cos(a), 10 * std::sin(a), 0.01 * i)));
  }
  auto edge = [&](int i, int j) {
    typename decltype(g.edges)::value_type e;
    e.i = i, e.j = j;
    e.measurement = g.poses[i].inverse() * g.poses[j];
    e.information *= 4.0 + i;
    g.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) {
    edge(i, i + 1);
    if (i % 3 == 0 && i + 7 < n) edge(i, i + 7);
  }
  return g;
}

double angle_of(const lie::SE2& a, const lie::SE2& b) { return (a.inverse() * b).angle(); }
lie::Vec3 angle_of(const lie::SE3& a, const lie::SE3& b) { return (a.so3().inverse() * b.so3()).log(); }

}  // namespace

TEST_CASE("corrupt_loop_closures: the first poses, their edges, and only loop closures touched") {
  const auto g = ring<graph::PoseGraph2D>(100);
  LoopClosureCorruption o;
  o.first_poses = 60;
  o.rotation_noise = 0.3;
  o.outlier_fraction = 0.25;
  const auto c = corrupt_loop_closures(g, o, Streams(11), 0);
  REQUIRE(c.graph.poses.size() == 60);
  std::size_t kept = 0;
  for (const auto& e : g.edges) kept += e.i < 60 && e.j < 60;
  REQUIRE(c.graph.edges.size() == kept);
  CHECK(c.loop_closures.size() == 18);  // i = 0, 3, …, 51 with i + 7 < 60
  CHECK(c.outliers.size() == 5);        // round(0.25 · 18) = round(4.5), away from zero
  CHECK(std::includes(c.loop_closures.begin(), c.loop_closures.end(), c.outliers.begin(), c.outliers.end()));
  std::size_t k = 0;
  for (std::size_t e = 0; e < c.graph.edges.size(); ++e) {
    const auto& h = c.graph.edges[e];
    while (k < g.edges.size() && !(g.edges[k].i == h.i && g.edges[k].j == h.j)) ++k;
    REQUIRE(k < g.edges.size());
    CHECK(h.information == g.edges[k].information);
    const bool closure = std::abs(h.i - h.j) != 1;
    CHECK(closure == std::binary_search(c.loop_closures.begin(), c.loop_closures.end(), static_cast<int>(e)));
    if (!closure) {  // odometry exactly as read
      CHECK(h.measurement.translation() == g.edges[k].measurement.translation());
      CHECK(h.measurement.angle() == g.edges[k].measurement.angle());
    } else if (!std::binary_search(c.outliers.begin(), c.outliers.end(), static_cast<int>(e))) {
      CHECK(h.measurement.translation() ==
            g.edges[k].measurement.translation());  // noise on the rotation only
    }
  }
  // Deterministic per (streams, index); another index is another draw.
  const auto again = corrupt_loop_closures(g, o, Streams(11), 0);
  const auto other = corrupt_loop_closures(g, o, Streams(11), 1);
  CHECK(graph::graph_difference(c.graph, again.graph).empty());
  CHECK(!graph::graph_difference(c.graph, other.graph).empty());
  // No corruption: the subset as read.
  LoopClosureCorruption none;
  const auto same = corrupt_loop_closures(g, none, Streams(11), 0);
  CHECK(graph::graph_difference(same.graph, g).empty());
  CHECK(same.outliers.empty());
}

TEST_CASE("corrupt_loop_closures: common random numbers across levels") {
  const auto g2 = ring<graph::PoseGraph2D>(200);
  const auto g3 = ring<graph::PoseGraph3D>(200);
  LoopClosureCorruption a, b, f1, f2;
  a.rotation_noise = 0.01, b.rotation_noise = 0.05;
  f1.outlier_fraction = 0.1, f2.outlier_fraction = 0.4;
  const Streams s(5);
  const auto a2 = corrupt_loop_closures(g2, a, s, 3), b2 = corrupt_loop_closures(g2, b, s, 3);
  const auto a3 = corrupt_loop_closures(g3, a, s, 3), b3 = corrupt_loop_closures(g3, b, s, 3);
  for (int e : a2.loop_closures) {  // the same direction, five times the angle
    const auto& ref = g2.edges[static_cast<std::size_t>(e)].measurement;
    CHECK(angle_of(ref, b2.graph.edges[static_cast<std::size_t>(e)].measurement) ==
          doctest::Approx(5 * angle_of(ref, a2.graph.edges[static_cast<std::size_t>(e)].measurement))
              .epsilon(1e-9));
  }
  for (int e : a3.loop_closures) {
    const auto& ref = g3.edges[static_cast<std::size_t>(e)].measurement;
    const lie::Vec3 da = angle_of(ref, a3.graph.edges[static_cast<std::size_t>(e)].measurement);
    const lie::Vec3 db = angle_of(ref, b3.graph.edges[static_cast<std::size_t>(e)].measurement);
    CHECK((db - 5 * da).norm() <= 1e-9 * db.norm());
  }
  // A larger outlier fraction replaces a superset, with the same random poses.
  const auto o1 = corrupt_loop_closures(g3, f1, s, 3), o2 = corrupt_loop_closures(g3, f2, s, 3);
  CHECK(o2.outliers.size() > o1.outliers.size());
  CHECK(std::includes(o2.outliers.begin(), o2.outliers.end(), o1.outliers.begin(), o1.outliers.end()));
  for (int e : o1.outliers) {
    const auto& m1 = o1.graph.edges[static_cast<std::size_t>(e)].measurement;
    const auto& m2 = o2.graph.edges[static_cast<std::size_t>(e)].measurement;
    CHECK(m1.translation() == m2.translation());
    CHECK(m1.rotation() == m2.rotation());
  }
}

TEST_CASE("corrupt_loop_closures: Monte-Carlo moments of the noise and of the outliers") {
  // 2D: θ noise N(0, σ²); 3D: E‖Log(R̃⁻¹ R)‖² = 3σ². Outliers: 2D angle uniform on (−π, π] (E|θ| = π/2);
  // 3D Haar rotations (E tr R = 0, Var tr R = 1); translation coordinates uniform in [−s, s] (within, mean
  // 0).
  const auto g2 = ring<graph::PoseGraph2D>(300);
  const auto g3 = ring<graph::PoseGraph3D>(300);
  LoopClosureCorruption noise, outliers;
  noise.rotation_noise = 0.05;
  outliers.outlier_fraction = 1.0;
  double ss2 = 0, ss3 = 0, abs_angle = 0, trace = 0, trace2 = 0, t_max = 0, t_mean = 0;
  int n2 = 0, n3 = 0, no = 0;
  double span = 0;
  for (const auto& e : g3.edges)
    if (std::abs(e.i - e.j) != 1) span = std::max(span, e.measurement.translation().cwiseAbs().maxCoeff());
  for (std::uint64_t draw = 0; draw < 40; ++draw) {
    const auto c2 = corrupt_loop_closures(g2, noise, Streams(9), draw);
    for (int e : c2.loop_closures) {
      const double d = angle_of(g2.edges[static_cast<std::size_t>(e)].measurement,
                                c2.graph.edges[static_cast<std::size_t>(e)].measurement);
      ss2 += d * d, ++n2;
    }
    const auto c3 = corrupt_loop_closures(g3, noise, Streams(9), draw);
    for (int e : c3.loop_closures) {
      ss3 += angle_of(g3.edges[static_cast<std::size_t>(e)].measurement,
                      c3.graph.edges[static_cast<std::size_t>(e)].measurement)
                 .squaredNorm();
      ++n3;
    }
    const auto o2 = corrupt_loop_closures(g2, outliers, Streams(9), draw);
    for (int e : o2.outliers)
      abs_angle += std::abs(o2.graph.edges[static_cast<std::size_t>(e)].measurement.angle());
    const auto o3 = corrupt_loop_closures(g3, outliers, Streams(9), draw);
    for (int e : o3.outliers) {
      const auto& m = o3.graph.edges[static_cast<std::size_t>(e)].measurement;
      const double tr = m.rotation().trace();
      trace += tr, trace2 += tr * tr, ++no;
      t_max = std::max(t_max, m.translation().cwiseAbs().maxCoeff());
      t_mean += m.translation().sum() / 3;
    }
  }
  REQUIRE(n2 > 3000);
  REQUIRE(no == n3);
  // σ̂² / σ² ~ χ²_n / n: standard deviation √(2/n) ≈ 0.025; five of them.
  CHECK(std::abs(ss2 / n2 / (0.05 * 0.05) - 1) < 5 * std::sqrt(2.0 / n2));
  CHECK(std::abs(ss3 / n3 / (3 * 0.05 * 0.05) - 1) <
        5 * std::sqrt(2.0 / (3.0 * n3)) + 0.01);  // + Log's curvature
  // |θ| uniform on [0, π]: standard deviation π/√12 per draw.
  CHECK(std::abs(abs_angle / n2 - lie::kPi / 2) < 5 * lie::kPi / std::sqrt(12.0 * n2));
  CHECK(std::abs(trace / no) < 5 / std::sqrt(static_cast<double>(no)));
  CHECK(std::abs(trace2 / no - 1) < 5 * std::sqrt(2.0 / no) + 0.05);
  CHECK(t_max <= span);
  CHECK(t_max > 0.95 * span);
  CHECK(std::abs(t_mean / no) < 5 * span / std::sqrt(9.0 * no));
}

TEST_CASE("corrupt_loop_closures: bad inputs are refused with the field named") {
  const auto g = ring<graph::PoseGraph2D>(20);
  LoopClosureCorruption o;
  o.first_poses = -1;
  CHECK(throws_with<std::invalid_argument>([&] { (void)corrupt_loop_closures(g, o, Streams(1), 0); },
                                           "first_poses = -1"));
  o = {};
  o.first_poses = 21;
  CHECK(throws_with<std::invalid_argument>([&] { (void)corrupt_loop_closures(g, o, Streams(1), 0); },
                                           "first_poses = 21 but ring has 20 poses"));
  o = {};
  o.rotation_noise = std::numeric_limits<double>::quiet_NaN();
  CHECK(throws_with<std::invalid_argument>([&] { (void)corrupt_loop_closures(g, o, Streams(1), 0); },
                                           "rotation_noise = nan"));
  o = {};
  o.rotation_noise = -0.1;
  CHECK(throws_with<std::invalid_argument>([&] { (void)corrupt_loop_closures(g, o, Streams(1), 0); },
                                           "rotation_noise = -0.1"));
  o = {};
  o.outlier_fraction = 1.5;
  CHECK(throws_with<std::invalid_argument>([&] { (void)corrupt_loop_closures(g, o, Streams(1), 0); },
                                           "outlier_fraction = 1.5"));
  auto with_landmarks = g;
  with_landmarks.landmarks.push_back(lie::Vec2(1, 2));
  CHECK(throws_with<std::invalid_argument>(
      [&] { (void)corrupt_loop_closures(with_landmarks, LoopClosureCorruption{}, Streams(1), 0); },
      "has landmarks"));
}

TEST_CASE("add_wrong_loop_closures: the rate's count appended, originals untouched, higher rates add") {
  const auto g = ring<graph::PoseGraph2D>(100);  // 31 loop closures
  using keel::sim::add_wrong_loop_closures;
  using keel::sim::WrongClosureKind;
  using keel::sim::WrongClosures;
  for (const auto kind : {WrongClosureKind::random, WrongClosureKind::aliased}) {
    CAPTURE(keel::sim::to_string(kind));
    WrongClosures lo, hi;
    lo.kind = hi.kind = kind;
    lo.rate = 0.2;
    hi.rate = 0.5;
    const auto a = add_wrong_loop_closures(g, lo, Streams(5), 3);
    const auto b = add_wrong_loop_closures(g, hi, Streams(5), 3);
    CHECK(a.outliers.size() == 8);   // round(0.2 / 0.8 · 31) = round(7.75)
    CHECK(b.outliers.size() == 31);  // as many wrong as true
    REQUIRE(a.graph.edges.size() == g.edges.size() + 8);
    CHECK(a.loop_closures.size() == 31 + 8);
    for (std::size_t k = 0; k < g.edges.size(); ++k) {  // the input's edges as read, in order
      CHECK(a.graph.edges[k].i == g.edges[k].i);
      CHECK(a.graph.edges[k].measurement.angle() == g.edges[k].measurement.angle());
    }
    for (std::size_t k = 0; k < a.outliers.size();
         ++k) {  // a lower rate's wrong closures are a higher's first
      const auto& x = a.graph.edges[static_cast<std::size_t>(a.outliers[k])];
      const auto& y = b.graph.edges[static_cast<std::size_t>(b.outliers[k])];
      CHECK(x.i == y.i);
      CHECK(x.j == y.j);
      CHECK(x.measurement.angle() == y.measurement.angle());
    }
    for (const int e : b.outliers) {  // no odometry pair, and a true closure's information
      const auto& w = b.graph.edges[static_cast<std::size_t>(e)];
      CHECK(std::abs(w.i - w.j) >= 2);
      CHECK(std::any_of(g.edges.begin(), g.edges.end(), [&](const auto& t) {
        return std::abs(t.i - t.j) != 1 && t.information == w.information;
      }));
    }
  }
}

TEST_CASE("add_wrong_loop_closures: an aliased group agrees on one wrong alignment, groups differ") {
  auto g = ring<graph::PoseGraph3D>(120);
  for (auto& e : g.edges) e.information *= 1e8;  // noise ~1e-4: the groups' agreement shows plainly
  keel::sim::WrongClosures o;
  o.kind = keel::sim::WrongClosureKind::aliased;
  o.rate = 0.5;  // 38 wrong closures: 7 groups of 5 and one of 3
  const auto c = keel::sim::add_wrong_loop_closures(g, o, Streams(9), 0);
  REQUIRE(c.outliers.size() == 38);
  // The chained odometry (the ring's poses, pose 0 moved to the identity); member (i, j)'s implied anchor
  // O_i z O_j⁻¹ is its group's.
  std::vector<lie::SE3> chain;
  for (const auto& p : g.poses) chain.push_back(g.poses[0].inverse() * p);
  std::vector<lie::SE3> anchors;
  for (const int e : c.outliers) {
    const auto& w = c.graph.edges[static_cast<std::size_t>(e)];
    anchors.push_back(chain[static_cast<std::size_t>(w.i)] * w.measurement *
                      chain[static_cast<std::size_t>(w.j)].inverse());
  }
  const auto gap = [](const lie::SE3& x, const lie::SE3& y) {
    const lie::SE3 d = x.inverse() * y;
    return d.translation().norm() + d.so3().log().norm();
  };
  for (std::size_t k = 0; k < anchors.size(); ++k) {
    const std::size_t group = k / 5;
    const auto& w = c.graph.edges[static_cast<std::size_t>(c.outliers[k])];
    const auto& first = c.graph.edges[static_cast<std::size_t>(c.outliers[group * 5])];
    CHECK(w.i - first.i == static_cast<int>(k % 5));  // consecutive blocks a + k → b + k
    CHECK(w.j - first.j == static_cast<int>(k % 5));
    CHECK(gap(anchors[k], anchors[group * 5]) < 1e-2);
    if (group > 0) CHECK(gap(anchors[k], anchors[(group - 1) * 5]) > 1e-1);
  }
}

TEST_CASE("split_into_robots: blocks re-indexed, inter-robot candidates with global ids, joins dropped") {
  const auto g = ring<graph::PoseGraph2D>(100);
  const auto s = keel::sim::split_into_robots(g, 4);
  REQUIRE(s.robots.size() == 4);
  std::size_t edges = s.inter.size();
  for (int r = 0; r < 4; ++r) {
    const auto& h = s.robots[static_cast<std::size_t>(r)];
    CHECK(h.poses.size() == 25);
    edges += h.edges.size();
    for (std::size_t k = 0; k < h.edges.size(); ++k) {
      const auto& e = g.edges[static_cast<std::size_t>(s.robot_edge[static_cast<std::size_t>(r)][k])];
      CHECK(h.edges[k].i == e.i - 25 * r);
      CHECK(h.edges[k].j == e.j - 25 * r);
      CHECK(h.edges[k].measurement.angle() == e.measurement.angle());
    }
  }
  CHECK(edges + 3 == g.edges.size());  // the three odometry edges between blocks are dropped
  for (std::size_t k = 0; k < s.inter.size(); ++k) {
    const auto& e = g.edges[static_cast<std::size_t>(s.inter_edge[k])];
    CHECK(s.inter[k].i == e.i);
    CHECK(s.inter[k].j == e.j);
    CHECK(e.i / 25 != e.j / 25);
    CHECK(std::abs(e.i - e.j) != 1);
  }
  // robot_of_pose names the block split_into_robots puts each pose in, also when blocks differ in size.
  const auto seven = keel::sim::split_into_robots(g, 7);
  int id = 0;
  for (int r = 0; r < 7; ++r)
    for (std::size_t k = 0; k < seven.robots[static_cast<std::size_t>(r)].poses.size(); ++k, ++id)
      CHECK(keel::sim::robot_of_pose(id, 100, 7) == r);
  CHECK(id == 100);
  const auto one = keel::sim::split_into_robots(g, 1);
  CHECK(one.robots[0].edges.size() == g.edges.size());
  CHECK(one.inter.empty());
}

TEST_CASE("add_wrong_loop_closures and split_into_robots: bad inputs are refused") {
  const auto g = ring<graph::PoseGraph2D>(20);
  keel::sim::WrongClosures o;
  o.rate = 1.0;
  CHECK(throws_with<std::invalid_argument>(
      [&] { (void)keel::sim::add_wrong_loop_closures(g, o, Streams(1), 0); }, "rate = 1"));
  o = {};
  o.group_size = 0;
  CHECK(throws_with<std::invalid_argument>(
      [&] { (void)keel::sim::add_wrong_loop_closures(g, o, Streams(1), 0); }, "group_size = 0"));
  auto bare = g;
  std::erase_if(bare.edges, [](const auto& e) { return std::abs(e.i - e.j) != 1; });
  o = {};
  o.rate = 0.5;
  CHECK(throws_with<std::invalid_argument>(
      [&] { (void)keel::sim::add_wrong_loop_closures(bare, o, Streams(1), 0); }, "has no loop closure"));
  auto gap = g;
  std::erase_if(gap.edges, [](const auto& e) { return e.i == 7 && e.j == 8; });
  CHECK(throws_with<std::invalid_argument>(
      [&] { (void)keel::sim::add_wrong_loop_closures(gap, o, Streams(1), 0); },
      "pose 8 has no odometry edge from pose 7"));
  CHECK(throws_with<std::invalid_argument>([&] { (void)keel::sim::split_into_robots(g, 0); },
                                           "0 robots asked of ring with 20 poses"));
  CHECK_THROWS_AS((void)keel::sim::wrong_closure_kind_from_string("clustered"), std::invalid_argument);
}
