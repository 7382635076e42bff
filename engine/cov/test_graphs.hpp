// Small random pose graphs for the unit tests of engine/cov (test helper: not part of the keel.cov facade).
// Random numbers come from keel::core::Rng (identical on every standard library), drawn one per statement so
// that the graphs do not depend on the compiler's order of evaluating function arguments.
#pragma once

#include <vector>

#include "core/random.hpp"
#include "graph/pose_graph.hpp"
#include "kit/test_kit.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"

namespace keel::cov::test {

struct TestGraph2D {
  graph::PoseGraph2D graph;
  std::vector<lie::SE2> estimate;    // = truth perturbed by `noise` (the linearization point)
  std::vector<lie::Vec2> landmarks;  // estimate of the landmarks
};

struct TestGraph3D {
  graph::PoseGraph3D graph;
  std::vector<lie::SE3> estimate;
};

// n poses on a wandering path that starts at `start` (default far from the origin), odometry + loop closures
// (i+3, i) and (0, n/2), m landmarks each seen by three poses. Measurements are the truth; the estimate is
// the truth perturbed by `noise`.
inline TestGraph2D small_graph_2d(int n, int m, unsigned seed, double noise,
                                  const lie::SE2& start = lie::SE2(60.0, 40.0, 0.3)) {
  core::Rng rng(seed);
  auto U = [&rng] { return rng.uniform(-1.0, 1.0); };
  auto N = [&rng] { return rng.normal(); };
  TestGraph2D tg;
  std::vector<lie::SE2> truth;
  lie::SE2 T = start;
  for (int i = 0; i < n; ++i) {
    truth.push_back(T);
    const double dx = 2.0 + U(), dy = U(), dth = 0.6 * U();
    T = T * lie::SE2(dx, dy, dth);
  }
  auto add_edge = [&](int i, int j) {
    graph::Edge2 e;
    e.i = i;
    e.j = j;
    e.measurement = truth[static_cast<std::size_t>(i)].inverse() * truth[static_cast<std::size_t>(j)];
    e.information = testkit::random_information<3>(rng, testkit::InformationDraw::correlated, 0.1);
    tg.graph.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) add_edge(i, i + 1);
  for (int i = 0; i + 3 < n; i += 2) add_edge(i + 3, i);  // reversed direction on purpose
  if (n > 4) add_edge(0, n / 2);
  std::vector<lie::Vec2> lm_truth;
  for (int k = 0; k < m; ++k) {
    const int p = (k * 5) % n;
    const double lx = 3.0 * U(), ly = 3.0 * U();
    const lie::Vec2 l = truth[static_cast<std::size_t>(p)] * lie::Vec2(lx, ly);
    lm_truth.push_back(l);
    for (int s = 0; s < 3; ++s) {
      graph::LandmarkMeasurement2 lm;
      lm.pose = (p + 2 * s) % n;
      lm.landmark = k;
      lm.position = truth[static_cast<std::size_t>(lm.pose)].inverse() * l;
      lm.information = testkit::random_information<2>(rng, testkit::InformationDraw::correlated, 0.1);
      tg.graph.landmark_measurements.push_back(lm);
    }
  }
  for (const auto& t : truth) {
    lie::Vec3 d;
    for (int k = 0; k < 3; ++k) d(k) = noise * N();
    tg.estimate.push_back(lie::SE2::exp(d) * t);
  }
  for (const auto& l : lm_truth) {
    lie::Vec2 d;
    for (int k = 0; k < 2; ++k) d(k) = noise * N();
    tg.landmarks.push_back(l + d);
  }
  tg.graph.poses = truth;
  tg.graph.landmarks = lm_truth;
  return tg;
}

inline TestGraph3D small_graph_3d(int n, unsigned seed, double noise) {
  core::Rng rng(seed);
  auto U = [&rng] { return rng.uniform(-1.0, 1.0); };
  TestGraph3D tg;
  std::vector<lie::SE3> truth;
  lie::Vec6 x0;
  x0 << 30.0, -20.0, 10.0, 0.3, -0.2, 0.5;
  lie::SE3 T = lie::SE3::exp(x0);
  for (int i = 0; i < n; ++i) {
    truth.push_back(T);
    lie::Vec6 step;
    const double scale[6] = {1.0, 1.0, 0.5, 0.4, 0.4, 0.6};
    for (int k = 0; k < 6; ++k) step(k) = scale[k] * U();
    step(0) += 2.0;
    T = T * lie::SE3::exp(step);
  }
  auto add_edge = [&](int i, int j) {
    graph::Edge3 e;
    e.i = i;
    e.j = j;
    e.measurement = truth[static_cast<std::size_t>(i)].inverse() * truth[static_cast<std::size_t>(j)];
    e.information = testkit::random_information<6>(rng, testkit::InformationDraw::correlated, 0.1);
    tg.graph.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) add_edge(i, i + 1);
  for (int i = 0; i + 3 < n; i += 2) add_edge(i + 3, i);
  lie::Vec6 d;
  for (const auto& t : truth) {
    for (int k = 0; k < 6; ++k) d(k) = noise * rng.normal();
    tg.estimate.push_back(lie::SE3::exp(d) * t);
  }
  tg.graph.poses = truth;
  return tg;
}

}  // namespace keel::cov::test
