// SCGP's discretizations on 1D worlds and the Monte-Carlo study of Figs. 2.2–2.3.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "study/ch2/world1d.hpp"
#include "kit/test_kit.hpp"
#include "pcm/clique.hpp"
#include "pcm/selection.hpp"
#include "sim/world1d.hpp"

using namespace keel::study::ch2;
using namespace keel::pcm;
using namespace keel::sim;
using keel::core::Streams;
using keel::repro::RunContext;
using keel::testkit::contains;
using keel::testkit::message_of;

TEST_CASE("the Monte-Carlo study is independent of the thread count and consistent with its parts") {
  World1DStudyOptions o;
  o.pcm_gamma = consistency_threshold(0.11, 1);
  o.ransac_gamma = consistency_threshold(0.01, 1);
  o.worlds = 300;
  const auto a = run_world1d_study(o, RunContext(Streams(77), 1));
  const auto b = run_world1d_study(o, RunContext(Streams(77), 2));
  REQUIRE(a.selectors.size() == 5);
  CHECK(a.measurements == b.measurements);
  CHECK(a.inliers == b.inliers);
  for (std::size_t s = 0; s < a.selectors.size(); ++s)
    for (std::size_t i = 0; i < o.worlds; ++i) {
      CHECK(a.outcome[s][i].size == b.outcome[s][i].size);
      CHECK(a.outcome[s][i].inconsistent_pairs == b.outcome[s][i].inconsistent_pairs);
      CHECK(a.outcome[s][i].inliers == b.outcome[s][i].inliers);
      CHECK(a.outcome[s][i].time_s >= 0.0);
    }
  const auto& comb = a.of(Selector1D::combinatorial);
  const auto& exact = a.of(Selector1D::pcm_exact);
  const auto& heur = a.of(Selector1D::pcm_heuristic);
  for (std::size_t i = 0; i < o.worlds; ++i) {
    // World i is the world generate_world1d(…, seed, i) would give on its own.
    const auto w = generate_world1d(o.world, 77, i);
    CHECK(a.measurements[i] == w.size());
    CHECK(exact[i].size == comb[i].size);
    CHECK(heur[i].size <= exact[i].size);
    CHECK(exact[i].inconsistent_pairs == 0);
    CHECK(heur[i].inconsistent_pairs == 0);
    CHECK(comb[i].inconsistent_pairs == 0);
    const auto Q = world1d_consistency_matrix(w);
    CHECK(a.of(Selector1D::ransac)[i].size ==
          static_cast<int>(select_ransac(Q, o.ransac_gamma).selected.size()));
  }
  CHECK(contains(message_of([&] { (void)a.of(Selector1D::scgp); }), "<no throw>"));
  o.selectors = {Selector1D::ransac};
  const auto c = run_world1d_study(o, RunContext(Streams(77)));
  CHECK(contains(message_of([&] { (void)c.of(Selector1D::pcm_exact); }), "not run"));

  World1DStudyOptions bad = o;
  bad.pcm_gamma = 0.0;
  CHECK(contains(message_of([&] { bad.validate(); }), "pcm_gamma"));
  bad = o;
  bad.selectors = {Selector1D::scgp, Selector1D::scgp};
  CHECK(contains(message_of([&] { bad.validate(); }), "twice"));
  bad = o;
  bad.selectors = {Selector1D::combinatorial};
  bad.combinatorial = CombinatorialMethod::exhaustive;
  bad.world.random_min = bad.world.random_max = 20;
  CHECK(contains(message_of([&] { bad.validate(); }), "combinatorial limit of 30"));
  CHECK(selector1d_from_string("pcm_heuristic") == Selector1D::pcm_heuristic);
  CHECK(contains(message_of([] { (void)selector1d_from_string("jcbb"); }), "jcbb"));
}
TEST_CASE("SCGP: one candidate, affinity scale, and the two discretizations on 1D worlds") {
  ConsistencyMatrix one;
  one.n = 1;
  one.q = {0.0};
  const auto r = scgp(one);
  CHECK(r.selection.selected == std::vector<int>{0});
  CHECK(std::isinf(r.eigen_ratio));

  World1DOptions wo;
  int differ = 0;
  for (int i = 0; i < 300; ++i) {
    const auto Q = world1d_consistency_matrix(generate_world1d(wo, 11, i));
    ScgpOptions dot, ray;
    ray.discretization = ScgpDiscretization::rayleigh;
    const auto a = scgp(Q, dot), b = scgp(Q, ray);
    REQUIRE_FALSE(a.selection.selected.empty());
    REQUIRE_FALSE(b.selection.selected.empty());
    CHECK(a.lambda1 == doctest::Approx(b.lambda1));
    // The Rayleigh rule maximises λ(w) over the threshold sets, so it is never below the dot-product rule's
    // λ(w).
    CHECK(b.objective >= a.objective - 1e-12);
    CHECK(a.lambda1 >= b.objective - 1e-9);  // no indicator beats the relaxation
    differ += a.selection.selected != b.selection.selected;
  }
  MESSAGE("dot-product and Rayleigh discretizations differ on " << differ << " of 300 worlds");
}
