// Unit tests of engine/sos: the polynomial cost against keel.pgo's residuals, the relaxations as lower
// bounds, tightness on noise-free data, the structures and solvers against each other, the counterexample to
// the exactness claim of Theorems 4.5.3–4.5.4, and bad inputs.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "core/random.hpp"
#include "graph/residuals.hpp"
#include "kit/test_kit.hpp"
#include "sos/certify.hpp"
#include "sos/problem.hpp"
#include "sos/relaxation.hpp"
#include "convex/sdp.hpp"

using namespace keel::sos;
using keel::core::Rng;
using keel::graph::Edge2;
using keel::graph::PoseGraph2D;
using keel::lie::SE2;
using keel::lie::Vec2;

namespace {

// The counterexample: 4 poses, complete graph, rotation-only measurements, unit weights (ω_R = ω_x = ω_y = 1,
// i.e. Ω = diag(1, 1, 2) in keel's χ² convention).
PoseGraph2D counterexample() {
  const double theta[6] = {0.23, 0.43, 1.13, -1.81, 1.36, -1.35};
  const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  PoseGraph2D g;
  g.poses.assign(4, SE2::identity());
  for (int k = 0; k < 6; ++k) {
    Edge2 e;
    e.i = pairs[k][0], e.j = pairs[k][1];
    e.measurement = SE2(0, 0, theta[k]);
    e.information = keel::lie::Mat3(Eigen::Vector3d(1, 1, 2).asDiagonal());
    g.edges.push_back(e);
  }
  return g;
}

// A random planar graph: odometry chain plus loop closures, poses from a random walk, measurements with
// noise.
struct World {
  PoseGraph2D graph;
  std::vector<SE2> truth;
  std::vector<Vec2> landmarks;
};
World random_world(Rng& rng, int n, int closures, double noise, int landmarks = 0) {
  World w;
  w.truth.push_back(SE2::identity());
  for (int i = 1; i < n; ++i)
    w.truth.push_back(w.truth.back() * SE2(1.0, rng.uniform(-0.3, 0.3), rng.uniform(-0.6, 0.6)));
  auto edge = [&](int i, int j) {
    const SE2 z = w.truth[i].inverse() * w.truth[j];
    Edge2 e;
    e.i = i, e.j = j;
    e.measurement = SE2(z.translation().x() + noise * rng.normal(),
                        z.translation().y() + noise * rng.normal(), z.angle() + noise * rng.normal());
    e.information = keel::lie::Mat3(Eigen::Vector3d(4, 4, 9).asDiagonal());
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
        keel::graph::LandmarkMeasurement2 m;
        m.pose = i, m.landmark = l;
        m.position = w.truth[i].inverse().act(w.landmarks.back()) + noise * Vec2(rng.normal(), rng.normal());
        m.information = keel::lie::Mat2(Eigen::Vector2d(4, 4).asDiagonal());
        w.graph.landmark_measurements.push_back(m);
      }
  }
  w.graph.poses = w.truth;
  return w;
}

}  // namespace

TEST_CASE("the polynomial cost is keel's χ² with the chordal rotation term (eq. 4.8–4.10, 4.13)") {
  Rng rng(11);
  World w = random_world(rng, 12, 6, 0.05, 3);
  const PlanarProblem p = planar_problem(w.graph);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<SE2> poses;
    for (int i = 0; i < p.poses; ++i) poses.push_back(keel::testkit::random_pose<SE2>(rng, 2.0, 5.0));
    std::vector<Vec2> lms;
    for (int l = 0; l < p.landmarks; ++l) lms.push_back(5.0 * Vec2(rng.normal(), rng.normal()));
    double expect = 0.0;
    for (const Edge2& e : w.graph.edges) {
      const keel::lie::Vec3 r = keel::graph::edge_residual(e.measurement, poses[e.i], poses[e.j]);
      expect += e.information(0, 0) * r(0) * r(0) + e.information(1, 1) * r(1) * r(1) +
                2.0 * e.information(2, 2) * (1.0 - std::cos(r(2)));
    }
    for (const auto& m : w.graph.landmark_measurements) {
      const Vec2 r = keel::graph::landmark_residual(m.position, poses[m.pose], lms[m.landmark]);
      expect += m.information(0, 0) * r(0) * r(0) + m.information(1, 1) * r(1) * r(1);
    }
    const double got = polynomial_cost(p, unknowns_of(p, poses, lms));
    CHECK(got == doctest::Approx(expect).epsilon(1e-10));
  }
}

TEST_CASE("order-1 relaxations are lower bounds; dense and cliques agree; DSDP and SDPA agree") {
  Rng rng(5);
  World w = random_world(rng, 10, 5, 0.1, 2);
  const PlanarProblem p = planar_problem(w.graph);
  const RelaxationResult dense = relax(p);
  RelaxationOptions co;
  co.structure = Structure::cliques;
  const RelaxationResult cliques = relax(p, co);
  CHECK(dense.primal_residual < 1e-7);
  CHECK(cliques.primal_residual < 1e-7);
  CHECK(dense.lower_bound == doctest::Approx(cliques.lower_bound).epsilon(1e-5));
  RelaxationOptions so;
  so.sdp.solver = keel::convex::SdpSolver::sdpa;
  const RelaxationResult sdpa = relax(p, so);
  CHECK(sdpa.lower_bound == doctest::Approx(dense.lower_bound).epsilon(1e-6));
  // Below the cost of any feasible point: the truth and random poses.
  CHECK(dense.lower_bound <= polynomial_cost(p, unknowns_of(p, w.truth, w.landmarks)) + 1e-9);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<SE2> poses;
    for (int i = 0; i < p.poses; ++i) poses.push_back(keel::testkit::random_pose<SE2>(rng, 3.0, 3.0));
    std::vector<Vec2> lms(static_cast<std::size_t>(p.landmarks), Vec2(1, 2));
    CHECK(dense.lower_bound <= polynomial_cost(p, unknowns_of(p, poses, lms)));
  }
}

TEST_CASE("noise-free data: the relaxation is tight, certified, and returns the ground truth") {
  Rng rng(7);
  World w = random_world(rng, 15, 8, 0.0, 3);
  const CertifiedSolution s = solve_certified(w.graph);
  CHECK(s.status == keel::core::SearchStatus::optimal);
  CHECK(s.certified_order == 1);
  CHECK(s.first.rank_ratio < 1e-6);
  CHECK(s.bound.upper < 1e-8);
  for (std::size_t i = 0; i < w.truth.size(); ++i) {
    CHECK((s.estimate.poses[i].translation() - w.truth[i].translation()).norm() < 1e-5);
    CHECK(std::abs(keel::lie::SO2(s.estimate.poses[i].angle() - w.truth[i].angle()).angle()) < 1e-5);
  }
}

TEST_CASE("the exactness claim fails on the counterexample; order 2 certifies it") {
  const PoseGraph2D g = counterexample();
  const PlanarProblem p = planar_problem(g);
  const RelaxationResult r1 = relax(p);
  CHECK(r1.lower_bound == doctest::Approx(9.8531).epsilon(1e-4));
  CHECK(r1.rank_ratio > 0.1);
  const CertifiedSolution s = solve_certified(g);
  CHECK(s.escalated);
  CHECK(s.status == keel::core::SearchStatus::optimal);
  CHECK(s.certified_order == 2);
  CHECK(s.bound.upper == doctest::Approx(10.4625).epsilon(1e-4));
  CHECK(s.second.lower_bound == doctest::Approx(10.4625).epsilon(1e-4));
  // Brute force over a grid of the three free angles agrees with the certified minimum.
  double best = 1e300;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(p.unknowns());
  const int steps = 90;
  for (int a = 0; a < steps; ++a)
    for (int b = 0; b < steps; ++b)
      for (int c = 0; c < steps; ++c) {
        const double t[3] = {2 * M_PI * a / steps, 2 * M_PI * b / steps, 2 * M_PI * c / steps};
        for (int i = 0; i < 3; ++i) z(4 * i) = std::cos(t[i]), z(4 * i + 1) = std::sin(t[i]);
        best = std::min(best, polynomial_cost(p, z));
      }
  CHECK(best >= s.bound.upper - 1e-9);
  CHECK(best <= s.bound.upper + 0.05);  // a 4° grid
}

TEST_CASE(
    "order 2 closes the counterexample's gap on both structures (rotations only, and the full cliques)") {
  const PlanarProblem p = planar_problem(counterexample());
  RelaxationOptions dense;
  dense.order = 2;
  const RelaxationResult d = relax(p, dense);
  RelaxationOptions cliques = dense;
  cliques.structure = Structure::cliques;
  const RelaxationResult c = relax(p, cliques);
  CHECK(d.lower_bound == doctest::Approx(10.4625).epsilon(1e-4));
  CHECK(c.lower_bound == doctest::Approx(10.4625).epsilon(1e-4));
  CHECK(d.moments < c.moments);  // the translations are minimised out before the moments are built
  CHECK(d.rank_ratio < 1e-4);
}

TEST_CASE("the certificate does not certify a relaxation that is not tight without escalation") {
  CertifyOptions o;
  o.escalate = false;
  const CertifiedSolution s = solve_certified(counterexample(), o);
  CHECK(s.status == keel::core::SearchStatus::unproven);
  CHECK(s.relative_gap() > 0.05);
}

TEST_CASE("bad inputs give clear errors") {
  PoseGraph2D g = counterexample();
  SUBCASE("disconnected") {
    PoseGraph2D d;
    d.poses.assign(4, SE2::identity());
    d.edges = {g.edges[0], g.edges[5]};  // (0,1) and (2,3)
    CHECK(keel::testkit::throws_with<std::invalid_argument>([&] { (void)planar_problem(d); },
                                                            "not connected: pose 2"));
  }
  SUBCASE("information not positive definite") {
    g.edges[2].information(2, 2) = -1;
    CHECK(keel::testkit::throws_with<std::invalid_argument>([&] { (void)planar_problem(g); },
                                                            "not positive definite"));
  }
  SUBCASE("information with cross terms") {
    g.edges[1].information(0, 1) = g.edges[1].information(1, 0) = 0.5;
    CHECK(keel::testkit::throws_with<std::invalid_argument>([&] { (void)planar_problem(g); }, "cross term"));
  }
  SUBCASE("a single pose") {
    PoseGraph2D one;
    one.poses.assign(1, SE2::identity());
    CHECK(
        keel::testkit::throws_with<std::invalid_argument>([&] { (void)planar_problem(one); }, "at least 2"));
  }
  SUBCASE("empty segment") {
    CHECK(keel::testkit::throws_with<std::invalid_argument>([&] { (void)extract_segment(g, 0, 0); },
                                                            "empty segment"));
  }
  SUBCASE("segment outside the graph") {
    CHECK(keel::testkit::throws_with<std::invalid_argument>([&] { (void)extract_segment(g, 2, 5); },
                                                            "outside the graph"));
  }
  SUBCASE("order 4") {
    RelaxationOptions o;
    o.order = 4;
    CHECK(keel::testkit::throws_with<std::invalid_argument>([&] { (void)relax(planar_problem(g), o); },
                                                            "order must be 1, 2 or 3"));
  }
  SUBCASE("too many moments") {
    RelaxationOptions o;
    o.structure = Structure::cliques, o.order = 2, o.max_moments = 10;
    CHECK(keel::testkit::throws_with<std::length_error>([&] { (void)relax(planar_problem(g), o); },
                                                        "more than 10 moments"));
  }
}
