// The combinatorial solution of eq. 2.5 (combinatorial.hpp) on 1D worlds from keel.sim: exhaustive = pruned =
// brute-force / exact maximum clique on random worlds, hand cases, limits, and inconsistent-pair counts.
#include <doctest/doctest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "kit/test_kit.hpp"
#include "pcm/clique.hpp"
#include "pcm/combinatorial.hpp"
#include "pcm/selection.hpp"
#include "sim/world1d.hpp"

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
