// The maximum-clique-at-scale studies: the first-moment clique number against a direct evaluation of
// C(n, k) p^(k(k−1)/2), the comparison of exact, heuristic and densest subgraph on small graphs against
// brute force, the pooled summaries, the planted and 1D studies (cells, determinism across threads), and the
// tally behind the experiment's checks.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "study/ch2/clique_scale.hpp"
#include "kit/test_kit.hpp"
#include "pcm/clique.hpp"
#include "pcm/consistency.hpp"
#include "sim/random_graph.hpp"
#include "sim/world1d.hpp"

using namespace keel::study::ch2;
using keel::core::Streams;
using keel::pcm::SearchStatus;
using keel::repro::RunContext;

namespace {

// Largest k with C(n, k) p^(k(k−1)/2) >= 1, the expectation computed as a running product in long double.
int omega0_direct(int n, double p) {
  int best = 1;
  long double e = n;  // k = 1
  for (int k = 1; k < n; ++k) {
    e *= static_cast<long double>(n - k) / (k + 1) * std::pow(static_cast<long double>(p), k);
    if (e >= 1.0L) best = k + 1;
  }
  return best;
}

}  // namespace

TEST_CASE("first_moment_clique_number = the direct expectation; limits and errors") {
  for (int n : {1, 2, 3, 5, 10, 20, 40, 60, 100})
    for (double p : {0.01, 0.05, 0.2, 0.5, 0.7, 0.9, 0.99}) {
      CAPTURE(n);
      CAPTURE(p);
      CHECK(first_moment_clique_number(n, p) == omega0_direct(n, p));
    }
  CHECK(first_moment_clique_number(50, 1.0) == 50);
  CHECK(first_moment_clique_number(50, 0.0) == 1);
  // Grows like 2 log_{1/p} n: larger for denser and for larger graphs.
  CHECK(first_moment_clique_number(2000, 0.5) > first_moment_clique_number(100, 0.5));
  CHECK(first_moment_clique_number(1000, 0.7) > first_moment_clique_number(1000, 0.5));
  CHECK_THROWS_AS((void)first_moment_clique_number(0, 0.5), std::invalid_argument);
  CHECK_THROWS_AS((void)first_moment_clique_number(10, 1.5), std::invalid_argument);
}

TEST_CASE("compare_clique_methods on small planted graphs: exact = brute force, every output a clique") {
  CliqueScaleOptions o;
  o.reference_max_vertices = 20;  // the n = 28 graphs are left without the colouring-only reference
  int graphs = 0, densest_below = 0;
  for (int n : {12, 20, 28})
    for (double p : {0.2, 0.5, 0.8})
      for (int k : {2, 5, 9})
        for (std::uint64_t seed = 0; seed < 4; ++seed) {
          const auto pc = keel::sim::planted_clique_graph(n, k, p, 1000 * n + 10 * k + seed);
          const auto out = compare_clique_methods(pc.graph, pc.planted, o);
          const auto brute = keel::pcm::maximum_clique_brute_force(pc.graph);
          const auto& ex = out.of(CliqueScaleMethod::exact);
          const auto& he = out.of(CliqueScaleMethod::heuristic);
          const auto& de = out.of(CliqueScaleMethod::densest);
          ++graphs;
          CHECK(out.vertices == n);
          CHECK(out.reference == k);
          CHECK(out.edges == pc.graph.num_edges());
          CHECK(ex.status == SearchStatus::optimal);
          CHECK(ex.size == static_cast<int>(brute.clique.size()));
          CHECK(out.reference_size == (n <= 20 ? ex.size : -1));
          CHECK(ex.upper_bound == ex.size);
          CHECK(ex.size >= k);  // the planted set is a clique
          for (const auto* m : {&ex, &he, &de}) {
            CHECK(m->violations == 0);
            CHECK(m->size <= ex.size);
            CHECK(m->hits <= std::min(m->size, k));
            CHECK(m->time_s >= 0.0);
          }
          CHECK(he.upper_bound >= ex.size);
          CHECK(de.raw_size >= 1);
          densest_below += de.size < ex.size;
        }
  CHECK(graphs == 108);
  MESSAGE("densest below the maximum on " << densest_below << " of " << graphs << " graphs");
}

TEST_CASE("compare_clique_methods: the node limit stops the exact search with a valid bound") {
  const auto pc = keel::sim::planted_clique_graph(200, 4, 0.5, 7);
  CliqueScaleOptions o;
  o.exact_node_limit = 1;
  const auto out = compare_clique_methods(pc.graph, pc.planted, o);
  const auto& ex = out.of(CliqueScaleMethod::exact);
  CHECK(ex.status == SearchStatus::node_limit);
  CHECK(ex.upper_bound > ex.size);
  CHECK(ex.size >= out.of(CliqueScaleMethod::heuristic).size);  // it starts from the heuristic's clique
  CHECK(ex.violations == 0);
  o.exact_node_limit = 0;
  CHECK_THROWS_AS((void)compare_clique_methods(pc.graph, pc.planted, o), std::invalid_argument);
  o.exact_node_limit = 10;
  o.reference_max_vertices = -1;
  CHECK_THROWS_AS((void)compare_clique_methods(pc.graph, pc.planted, o), std::invalid_argument);
  o.reference_max_vertices = 0;
  CHECK_THROWS_AS((void)compare_clique_methods(pc.graph, {3, 3}, o), std::invalid_argument);
  CHECK_THROWS_AS((void)compare_clique_methods(pc.graph, {200}, o), std::invalid_argument);
}

TEST_CASE("non_adjacent_pairs and summarize_clique_method (pooled precision and recall)") {
  keel::pcm::ConsistencyGraph g(4, {{0, 1}, {1, 2}});
  CHECK(non_adjacent_pairs(g, {}) == 0);
  CHECK(non_adjacent_pairs(g, {0, 1}) == 0);
  CHECK(non_adjacent_pairs(g, {0, 1, 2}) == 1);
  CHECK(non_adjacent_pairs(g, {0, 1, 2, 3}) == 4);  // 6 pairs, 2 edges

  std::vector<CliqueGraphOutcome> v(3);
  v[0].reference = 4;
  v[1].reference = 6;
  v[2].reference = 100;
  auto& a = v[0].methods[0];
  a.size = 5, a.hits = 4, a.upper_bound = 5, a.status = SearchStatus::optimal, a.time_s = 1.0;
  auto& b = v[1].methods[0];
  b.size = 3, b.hits = 1, b.upper_bound = 7, b.status = SearchStatus::node_limit, b.time_s = 3.0;
  b.raw_violations = 2;
  const auto s = summarize_clique_method(v, 0, 2, CliqueScaleMethod::exact);
  CHECK(s.graphs == 2);
  CHECK(s.size_mean == doctest::Approx(4.0));
  CHECK(s.size_min == 3);
  CHECK(s.size_max == 5);
  CHECK(s.precision == doctest::Approx(5.0 / 8.0));
  CHECK(s.recall == doctest::Approx(5.0 / 10.0));
  CHECK(s.optimal_graphs == 1);
  CHECK(s.gap_mean == doctest::Approx(2.0));
  CHECK(s.gap_max == 4);
  CHECK(s.raw_violating_graphs == 1);
  CHECK(s.time_mean_s == doctest::Approx(2.0));
  CHECK(s.time_max_s == doctest::Approx(3.0));
  CHECK_THROWS_AS((void)summarize_clique_method(v, 2, 2, CliqueScaleMethod::exact), std::invalid_argument);
  CHECK_THROWS_AS((void)summarize_clique_method(v, 0, 4, CliqueScaleMethod::exact), std::invalid_argument);
}

TEST_CASE("planted study: cells (k rounded, repeats left out) and one answer for any thread count") {
  PlantedCliqueStudyOptions o;
  o.sizes = {50, 120};
  o.clique_fractions = {0.01, 0.02, 0.3};
  o.densities = {0.2, 0.6};
  o.seeds = 2;
  const auto cells = o.cells();
  // n = 50: k = max(2, round(0.5)) = 2, max(2, 1) = 2 (left out), 15; n = 120: 2, 2 (left out), 36.
  REQUIRE(cells.size() == 8);
  CHECK(cells[0].k == 2);
  CHECK(cells[2].k == 15);
  CHECK(cells[4].n == 120);
  CHECK(cells[6].k == 36);
  for (const auto& c : cells) CHECK(c.omega0 == first_moment_clique_number(c.n, c.p));
  CHECK_FALSE(cells[0].planted_is_maximum());
  CHECK(cells[6].planted_is_maximum());
  const auto one = run_planted_clique_study(o, RunContext(Streams(99), 1));
  const auto two = run_planted_clique_study(o, RunContext(Streams(99), 2));
  REQUIRE(one.outcomes.size() == 16);
  REQUIRE(two.outcomes.size() == 16);
  for (std::size_t t = 0; t < one.outcomes.size(); ++t) {
    CHECK(one.outcomes[t].edges == two.outcomes[t].edges);
    for (std::size_t m = 0; m < kCliqueScaleMethods; ++m) {
      CHECK(one.outcomes[t].methods[m].size == two.outcomes[t].methods[m].size);
      CHECK(one.outcomes[t].methods[m].hits == two.outcomes[t].methods[m].hits);
      CHECK(one.outcomes[t].methods[m].raw_violations == two.outcomes[t].methods[m].raw_violations);
    }
    const auto& ex = one.outcomes[t].of(CliqueScaleMethod::exact);
    CHECK(ex.size >= cells[t / 2].k);
    CHECK(one.outcomes[t].reference == cells[t / 2].k);
  }
  // The two seeds of a cell are different graphs.
  CHECK(one.outcomes[6].edges != one.outcomes[7].edges);
  o.clique_fractions = {1.5};
  CHECK_THROWS_AS((void)o.cells(), std::invalid_argument);
}

TEST_CASE("1D-world clique study: inliers as reference, exact >= heuristic, outputs are cliques") {
  World1DCliqueOptions o;
  o.world = keel::sim::world1d_options_with_total(o.world, 60, 0.5, 0.25);
  o.gamma = keel::pcm::consistency_threshold(0.11, 1);
  o.worlds = 5;
  const auto out = run_world1d_clique_study(o, RunContext(Streams(3)));
  REQUIRE(out.size() == 5);
  for (const auto& w : out) {
    CHECK(w.vertices == 60);
    CHECK(w.reference == 30);
    const auto& ex = w.of(CliqueScaleMethod::exact);
    CHECK(ex.status == SearchStatus::optimal);
    CHECK(ex.size >= w.of(CliqueScaleMethod::heuristic).size);
    CHECK(ex.size >= w.of(CliqueScaleMethod::densest).size);
    for (const auto& m : w.methods) CHECK(m.violations == 0);
  }
  o.gamma = 0.0;
  CHECK_THROWS_AS((void)run_world1d_clique_study(o, RunContext(Streams(3))), std::invalid_argument);
}

TEST_CASE("CliqueScaleTally counts each failure the checks look for, and nothing on consistent outcomes") {
  auto outcome = [](int exact_size, int bound, SearchStatus status, int heuristic_size) {
    CliqueGraphOutcome g;
    auto& ex = g.methods[static_cast<std::size_t>(CliqueScaleMethod::exact)];
    ex.size = exact_size;
    ex.upper_bound = bound;
    ex.status = status;
    g.methods[static_cast<std::size_t>(CliqueScaleMethod::heuristic)].size = heuristic_size;
    g.methods[static_cast<std::size_t>(CliqueScaleMethod::densest)].size = heuristic_size;
    return g;
  };
  std::vector<CliqueGraphOutcome> all{outcome(10, 10, SearchStatus::optimal, 9),
                                      outcome(8, 12, SearchStatus::node_limit, 9),  // exact below heuristic
                                      outcome(7, 7, SearchStatus::optimal, 7)};     // below the planted 8
  all[2].methods[static_cast<std::size_t>(CliqueScaleMethod::densest)].violations = 1;
  all[2].methods[static_cast<std::size_t>(CliqueScaleMethod::densest)].raw_violations = 2;
  all[0].reference_size = 10;
  all[2].reference_size = 8;
  CliqueScaleTally t;
  t.add(all, 0, 1, 8);  // consistent: nothing counted but the graph and its proof
  CHECK(t.graphs == 1);
  CHECK(t.optimal == 1);
  CHECK(t.reference_checked == 1);
  CHECK(t.exact_below_heuristic + t.not_cliques + t.above_bound + t.optimal_inconsistent + t.below_planted +
            t.densest_raw_violating + t.reference_mismatch ==
        0);
  t.add(all, 1, 3, 8);
  CHECK(t.graphs == 3);
  CHECK(t.exact_below_heuristic == 1);
  CHECK(t.above_bound == 0);  // the heuristic's 9 is below the stopped search's bound 12
  CHECK(t.optimal == 2);
  CHECK(t.below_planted == 1);
  CHECK(t.not_cliques == 1);
  CHECK(t.densest_raw_violating == 1);
  CHECK(t.reference_checked == 2);
  CHECK(t.reference_mismatch == 1);  // proven 7 against the reference's 8
}
