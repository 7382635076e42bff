// Unit tests of engine/sos/certify: tightness and the ground truth on noise-free data, escalation on the
// counterexample to the exactness claim of Theorems 4.5.3–4.5.4, and no certificate without escalation.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "core/random.hpp"
#include "sos/certify.hpp"
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

TEST_CASE("the cliques structure reports its gap but never certifies (its translation box is unproven)") {
  Rng rng(7);
  World w = random_world(rng, 8, 4, 0.0, 3);
  CertifyOptions o;
  o.relaxation.structure = Structure::cliques;
  const CertifiedSolution s = solve_certified(w.graph, o);
  CHECK(s.status == keel::core::SearchStatus::unproven);
  CHECK(s.certified_order == 0);
  CHECK(s.relative_gap() < 1e-4);  // the bound itself is still tight on noise-free data
  CHECK(s.note.find("unproven translation box") != std::string::npos);
  // The dense structure certifies the same graph.
  CHECK(solve_certified(w.graph).status == keel::core::SearchStatus::optimal);
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

TEST_CASE("the certificate does not certify a relaxation that is not tight without escalation") {
  CertifyOptions o;
  o.escalate = false;
  const CertifiedSolution s = solve_certified(counterexample(), o);
  CHECK(s.status == keel::core::SearchStatus::unproven);
  CHECK(s.relative_gap() > 0.05);
}
