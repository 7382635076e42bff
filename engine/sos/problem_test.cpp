// Unit tests of engine/sos/problem: the polynomial cost against keel.pgo's residuals (eqs. 4.8–4.10, 4.13),
// and bad inputs (the problem, segments and relaxation options).
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/random.hpp"
#include "graph/residuals.hpp"
#include "kit/test_kit.hpp"
#include "sos/problem.hpp"
#include "sos/relaxation.hpp"
#include "sos/test_graphs.hpp"

using namespace keel::sos;
using namespace keel::sos::test;
using keel::core::Rng;
using keel::graph::Edge2;
using keel::graph::PoseGraph2D;
using keel::lie::SE2;
using keel::lie::Vec2;

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
