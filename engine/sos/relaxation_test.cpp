// Unit tests of engine/sos/relaxation: the relaxations as lower bounds, the dense and clique structures and
// the DSDP and SDPA solvers against each other, and order 2 on the counterexample to Theorems 4.5.3–4.5.4.
#include <doctest/doctest.h>

#include <vector>

#include "convex/sdp.hpp"
#include "core/random.hpp"
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
