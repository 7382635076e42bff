// The combinatorial solution of eq. 2.5 on 1D worlds (exhaustive = pruned = brute-force / exact maximum
// clique on random worlds), inconsistent-pair counts, SCGP's discretizations, and the Monte-Carlo study of
// Figs. 2.2–2.3.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "eval/world1d_study.hpp"
#include "kit/test_kit.hpp"
#include "pcm/clique.hpp"
#include "pcm/selection.hpp"
#include "sim/world1d.hpp"

using namespace keel::eval;
using namespace keel::pcm;
using namespace keel::sim;
using keel::testkit::contains;
using keel::testkit::message_of;

TEST_CASE("combinatorial eq. 2.5 = brute-force and exact maximum clique on random worlds (m <= 20)") {
  World1DOptions o;  // 8..22 measurements by default; keep m <= 20 here
  o.inliers_max = 8;
  const double gammas[] = {consistency_threshold(0.11, 1), consistency_threshold(0.01, 1), 0.5};
  long long tied_worlds = 0;
  for (int i = 0; i < 1500; ++i) {
    const auto w = generate_world1d(o, 2018, i);
    REQUIRE(w.size() <= 20);
    const auto Q = world1d_consistency_matrix(w);
    const double gamma = gammas[i % 3];
    const auto ex = max_consistent_set_combinatorial(Q, gamma, CombinatorialMethod::exhaustive);
    const auto pr = max_consistent_set_combinatorial(Q, gamma, CombinatorialMethod::pruned);
    const auto g = ConsistencyGraph::from_threshold(Q.n, Q.q, gamma);
    CliqueOptions ties;
    ties.report_ties = true;
    ties.max_ties = 100000;
    const auto bf = maximum_clique_brute_force(g, ties);
    const auto exact = maximum_clique_exact(g);
    CAPTURE(i);
    REQUIRE(ex.selected.size() == pr.selected.size());
    CHECK(ex.selected.size() == bf.clique.size());
    CHECK(ex.selected.size() == exact.clique.size());
    CHECK(ex.optimal_sets == pr.optimal_sets);
    CHECK(ex.optimal_sets == static_cast<long long>(bf.ties.size()) + 1);
    CHECK(ex.subsets_visited == (1LL << w.size()));
    CHECK(pr.subsets_visited < ex.subsets_visited);
    CHECK(count_inconsistent_pairs(Q, ex.selected, gamma) == 0);
    CHECK(count_inconsistent_pairs(Q, pr.selected, gamma) == 0);
    CHECK(g.is_clique(pr.selected));
    tied_worlds += ex.optimal_sets > 1;
  }
  MESSAGE(tied_worlds << " of 1500 worlds have more than one maximum consistent set");
}

TEST_CASE("combinatorial: small hand cases and limits") {
  // Chain 0-1-2 (0 and 2 inconsistent): two maximum sets of size 2.
  ConsistencyMatrix Q;
  Q.n = 3;
  Q.q = {0, 1, 9, 1, 0, 1, 9, 1, 0};
  for (auto m : {CombinatorialMethod::exhaustive, CombinatorialMethod::pruned}) {
    const auto r = max_consistent_set_combinatorial(Q, 2.0, m);
    CHECK(r.selected.size() == 2);
    CHECK(r.optimal_sets == 2);
    CHECK(combinatorial_method_from_string(to_string(m)) == m);
  }
  CHECK(max_consistent_set_combinatorial(Q, 2.0, CombinatorialMethod::exhaustive).selected ==
        std::vector<int>{0, 1});

  ConsistencyMatrix big;
  big.n = kCombinatorialExhaustiveMax + 1;
  big.q.assign(static_cast<std::size_t>(big.n) * big.n, 0.0);
  CHECK(contains(
      message_of([&] { (void)max_consistent_set_combinatorial(big, 1.0, CombinatorialMethod::exhaustive); }),
      "exceeds the limit 30"));
  // The pruned search handles it (all consistent: one set of everything).
  const auto all = max_consistent_set_combinatorial(big, 1.0, CombinatorialMethod::pruned);
  CHECK(all.selected.size() == static_cast<std::size_t>(big.n));
  CHECK(all.optimal_sets == 1);
  CHECK(contains(message_of([&] { (void)max_consistent_set_combinatorial(Q, 0.0); }), "gamma"));
  CHECK(contains(message_of([] { (void)combinatorial_method_from_string("greedy"); }), "greedy"));
}

TEST_CASE("count_inconsistent_pairs") {
  ConsistencyMatrix Q;
  Q.n = 4;
  Q.q = {0, 1, 5, 1,   //
         1, 0, 1, 1,   //
         5, 1, 0, 7,   //
         1, 1, 2, 0};  // asymmetric (2, 3): 7 vs 2
  CHECK(count_inconsistent_pairs(Q, {}, 3.0) == 0);
  CHECK(count_inconsistent_pairs(Q, {1}, 3.0) == 0);
  CHECK(count_inconsistent_pairs(Q, {0, 1, 3}, 3.0) == 0);
  CHECK(count_inconsistent_pairs(Q, {0, 2}, 3.0) == 1);
  CHECK(count_inconsistent_pairs(Q, {3, 2}, 3.0) == 1);  // one direction is enough
  CHECK(count_inconsistent_pairs(Q, {0, 1, 2, 3}, 3.0) == 2);
  CHECK(count_inconsistent_pairs(Q, {0, 1, 2, 3}, 10.0) == 0);
  CHECK(contains(message_of([&] { (void)count_inconsistent_pairs(Q, {0, 4}, 3.0); }), "out of range"));
  CHECK(contains(message_of([&] { (void)count_inconsistent_pairs(Q, {1, 1}, 3.0); }), "repeated"));
}

TEST_CASE("the Monte-Carlo study is independent of the thread count and consistent with its parts") {
  World1DStudyOptions o;
  o.pcm_gamma = consistency_threshold(0.11, 1);
  o.ransac_gamma = consistency_threshold(0.01, 1);
  o.seed = 77;
  o.worlds = 300;
  o.threads = 1;
  const auto a = run_world1d_study(o);
  o.threads = 2;
  const auto b = run_world1d_study(o);
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
    const auto w = generate_world1d(o.world, o.seed, i);
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
  const auto c = run_world1d_study(o);
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
