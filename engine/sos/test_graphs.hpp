// Planar graphs shared by the unit tests of engine/sos (test helper: not part of the keel.sos facade): the
// counterexample to the exactness claim of Theorems 4.5.3–4.5.4, and random walks with loop closures and
// landmarks drawn from keel::core::Rng.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "core/random.hpp"
#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"
#include "lie/types.hpp"
#include "sos/certify.hpp"

namespace keel::sos::test {

// The counterexample of ch4_exactness: 4 poses, complete graph, rotation-only measurements, unit weights
// (sos::exactness_counterexample, certify.hpp).
inline graph::PoseGraph2D counterexample() { return exactness_counterexample(); }

// A random planar graph: odometry chain plus loop closures, poses from a random walk, measurements with
// noise.
struct World {
  graph::PoseGraph2D graph;
  std::vector<lie::SE2> truth;
  std::vector<lie::Vec2> landmarks;
};
inline World random_world(core::Rng& rng, int n, int closures, double noise, int landmarks = 0) {
  using lie::SE2;
  using lie::Vec2;
  World w;
  w.truth.push_back(SE2::identity());
  for (int i = 1; i < n; ++i)
    w.truth.push_back(w.truth.back() * SE2(1.0, rng.uniform(-0.3, 0.3), rng.uniform(-0.6, 0.6)));
  auto edge = [&](int i, int j) {
    const SE2 z = w.truth[i].inverse() * w.truth[j];
    graph::Edge2 e;
    e.i = i, e.j = j;
    e.measurement = SE2(z.translation().x() + noise * rng.normal(),
                        z.translation().y() + noise * rng.normal(), z.angle() + noise * rng.normal());
    e.information = lie::Mat3(Eigen::Vector3d(4, 4, 9).asDiagonal());
    w.graph.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) edge(i, i + 1);
  for (int k = 0; k < closures; ++k) {
    const int i = static_cast<int>(rng.uniform(0, n - 3)),
              j = i + 2 + static_cast<int>(rng.uniform(0, n - i - 2));
    if (j < n) edge(i, j);
  }
  for (int l = 0; l < landmarks; ++l) {
    const SE2& near = w.truth[static_cast<std::size_t>(rng.uniform(0, n - 1))];
    w.landmarks.push_back(near.translation() + Vec2(rng.uniform(-2, 2), rng.uniform(-2, 2)));
    for (int i = 0; i < n; ++i)
      if ((w.truth[i].translation() - w.landmarks.back()).norm() < 4.0) {
        graph::LandmarkMeasurement2 m;
        m.pose = i, m.landmark = l;
        m.position = w.truth[i].inverse().act(w.landmarks.back()) + noise * Vec2(rng.normal(), rng.normal());
        m.information = lie::Mat2(Eigen::Vector2d(4, 4).asDiagonal());
        w.graph.landmark_measurements.push_back(m);
      }
  }
  w.graph.poses = w.truth;
  return w;
}

}  // namespace keel::sos::test
