// Small random pose graphs for the unit tests of engine/cov (test helper: not part of the keel.cov facade).
#pragma once

#include <random>
#include <vector>

#include "graph/pose_graph.hpp"
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

// Random SPD information (correlated) with standard deviations around `sigma`.
template <int D>
Eigen::Matrix<double, D, D> random_information(std::mt19937_64& rng, double sigma) {
  std::uniform_real_distribution<double> u(-0.3, 0.3), s(0.5, 1.5);
  Eigen::Matrix<double, D, D> C = Eigen::Matrix<double, D, D>::Identity();
  for (int r = 0; r < D; ++r)
    for (int c = 0; c < r; ++c) C(r, c) = u(rng);
  Eigen::Matrix<double, D, D> S = Eigen::Matrix<double, D, D>::Zero();
  for (int k = 0; k < D; ++k) S(k, k) = sigma * s(rng);
  const Eigen::Matrix<double, D, D> L = S * C;  // covariance L Lᵀ
  const Eigen::Matrix<double, D, D> Li =
      L.template triangularView<Eigen::Lower>().solve(Eigen::Matrix<double, D, D>::Identity());
  return Li.transpose() * Li;
}

// n poses on a wandering path that starts at `start` (default far from the origin), odometry + loop closures
// (i+3, i) and (0, n/2), m landmarks each seen by three poses. Measurements are the truth; the estimate is
// the truth perturbed by `noise`.
inline TestGraph2D small_graph_2d(int n, int m, unsigned seed, double noise,
                                  const lie::SE2& start = lie::SE2(60.0, 40.0, 0.3)) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  TestGraph2D tg;
  std::vector<lie::SE2> truth;
  lie::SE2 T = start;
  for (int i = 0; i < n; ++i) {
    truth.push_back(T);
    T = T * lie::SE2(2.0 + U(rng), U(rng), 0.6 * U(rng));
  }
  auto add_edge = [&](int i, int j) {
    graph::Edge2 e;
    e.i = i;
    e.j = j;
    e.measurement = truth[static_cast<std::size_t>(i)].inverse() * truth[static_cast<std::size_t>(j)];
    e.information = random_information<3>(rng, 0.1);
    tg.graph.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) add_edge(i, i + 1);
  for (int i = 0; i + 3 < n; i += 2) add_edge(i + 3, i);  // reversed direction on purpose
  if (n > 4) add_edge(0, n / 2);
  std::vector<lie::Vec2> lm_truth;
  for (int k = 0; k < m; ++k) {
    const int p = (k * 5) % n;
    const lie::Vec2 l = truth[static_cast<std::size_t>(p)] * lie::Vec2(3.0 * U(rng), 3.0 * U(rng));
    lm_truth.push_back(l);
    for (int s = 0; s < 3; ++s) {
      graph::LandmarkMeasurement2 lm;
      lm.pose = (p + 2 * s) % n;
      lm.landmark = k;
      lm.position = truth[static_cast<std::size_t>(lm.pose)].inverse() * l;
      lm.information = random_information<2>(rng, 0.1);
      tg.graph.landmark_measurements.push_back(lm);
    }
  }
  for (const auto& t : truth)
    tg.estimate.push_back(lie::SE2::exp(noise * lie::Vec3(N(rng), N(rng), N(rng))) * t);
  for (const auto& l : lm_truth) tg.landmarks.push_back(l + noise * lie::Vec2(N(rng), N(rng)));
  tg.graph.poses = truth;
  tg.graph.landmarks = lm_truth;
  return tg;
}

inline TestGraph3D small_graph_3d(int n, unsigned seed, double noise) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  TestGraph3D tg;
  std::vector<lie::SE3> truth;
  lie::Vec6 x0;
  x0 << 30.0, -20.0, 10.0, 0.3, -0.2, 0.5;
  lie::SE3 T = lie::SE3::exp(x0);
  for (int i = 0; i < n; ++i) {
    truth.push_back(T);
    lie::Vec6 step;
    step << 2.0 + U(rng), U(rng), 0.5 * U(rng), 0.4 * U(rng), 0.4 * U(rng), 0.6 * U(rng);
    T = T * lie::SE3::exp(step);
  }
  auto add_edge = [&](int i, int j) {
    graph::Edge3 e;
    e.i = i;
    e.j = j;
    e.measurement = truth[static_cast<std::size_t>(i)].inverse() * truth[static_cast<std::size_t>(j)];
    e.information = random_information<6>(rng, 0.1);
    tg.graph.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) add_edge(i, i + 1);
  for (int i = 0; i + 3 < n; i += 2) add_edge(i + 3, i);
  lie::Vec6 d;
  for (const auto& t : truth) {
    for (int k = 0; k < 6; ++k) d(k) = noise * N(rng);
    tg.estimate.push_back(lie::SE3::exp(d) * t);
  }
  tg.graph.poses = truth;
  return tg;
}

}  // namespace keel::cov::test
