// Densest-subgraph selector (pcm/densest.hpp): planted cliques above the √n barrier are recovered, the
// repaired selection is always a maximal clique no larger than the maximum, weighted and binary affinities
// agree when the weights are 1, and bad inputs give clear errors.
#include <doctest/doctest.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "kit/test_kit.hpp"
#include "pcm/clique.hpp"
#include "pcm/densest.hpp"
#include "sim/random_graph.hpp"

using namespace keel::pcm;
using keel::sim::random_graph;
using keel::testkit::contains;
using keel::testkit::message_of;

namespace {

bool maximal(const ConsistencyGraph& g, const std::vector<int>& s) {
  for (int v = 0; v < g.size(); ++v) {
    if (std::binary_search(s.begin(), s.end(), v)) continue;
    bool all = true;
    for (int w : s) all = all && g.adjacent(v, w);
    if (all) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("densest subgraph: a planted clique well above √n is recovered exactly") {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const auto [g, planted] = keel::sim::planted_clique_graph(300, 60, 0.1, seed);
    const auto r = densest_subgraph(g);
    INFO("seed " << seed);
    CHECK(r.converged);
    CHECK(r.violations == 0);
    CHECK(r.raw == planted);
    CHECK(r.selection == planted);
    CHECK(r.objective == doctest::Approx(60.0).epsilon(1e-3));
  }
}

TEST_CASE("densest subgraph: the repaired selection is a maximal clique, never above the maximum") {
  auto rng = keel::core::Rng::stream(17, 0);
  for (int trial = 0; trial < 150; ++trial) {
    const int n = 3 + static_cast<int>(rng.uniform(0.0, 38.0));
    const double p = rng.uniform(0.05, 0.95);
    const auto g = random_graph(n, p, 1000 + static_cast<std::uint64_t>(trial));
    const auto r = densest_subgraph(g);
    INFO("trial " << trial << ": n " << n << ", p " << p);
    REQUIRE(!r.selection.empty());
    CHECK(g.is_clique(r.selection));
    CHECK(maximal(g, r.selection));
    CHECK(static_cast<int>(r.selection.size()) <= static_cast<int>(maximum_clique_exact(g).clique.size()));
    CHECK(std::is_sorted(r.raw.begin(), r.raw.end()));
    long long v = 0;
    for (std::size_t a = 0; a < r.raw.size(); ++a)
      for (std::size_t b = a + 1; b < r.raw.size(); ++b) v += g.adjacent(r.raw[a], r.raw[b]) ? 0 : 1;
    CHECK(v == r.violations);
  }
}

TEST_CASE("densest subgraph: complete and empty graphs, determinism") {
  ConsistencyGraph k(12);
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j) k.add_edge(i, j);
  const auto all = densest_subgraph(k);
  CHECK(all.selection.size() == 12);
  CHECK(all.violations == 0);
  CHECK(all.objective == doctest::Approx(12.0));
  const auto none = densest_subgraph(ConsistencyGraph(9));
  CHECK(none.selection.size() == 1);
  CHECK(densest_subgraph(ConsistencyGraph(0)).selection.empty());
  const auto g = random_graph(120, 0.4, 5);
  const auto a = densest_subgraph(g), b = densest_subgraph(g);
  CHECK(a.selection == b.selection);
  CHECK(a.raw == b.raw);
  CHECK(a.objective == b.objective);
}

TEST_CASE("densest subgraph: unit weights equal the binary problem; weights steer the choice") {
  const auto g = keel::sim::planted_clique_graph(150, 35, 0.1, 9).graph;
  const int n = g.size();
  std::vector<double> ones(static_cast<std::size_t>(n) * n, 1.0);
  const auto w = densest_subgraph(g, ones), b = densest_subgraph(g);
  CHECK(w.selection == b.selection);
  CHECK(w.objective == doctest::Approx(b.objective));
  // Two disjoint triangles: the one with the heavier edges wins.
  ConsistencyGraph t(6, {{0, 1}, {1, 2}, {0, 2}, {3, 4}, {4, 5}, {3, 5}});
  std::vector<double> aff(36, 0.0);
  auto set = [&](int i, int j, double x) { aff[i * 6 + j] = aff[j * 6 + i] = x; };
  set(0, 1, 0.3), set(1, 2, 0.3), set(0, 2, 0.3), set(3, 4, 0.9), set(4, 5, 0.9), set(3, 5, 0.9);
  CHECK(densest_subgraph(t, aff).selection == std::vector<int>{3, 4, 5});
  set(0, 1, 1.0), set(1, 2, 1.0), set(0, 2, 1.0);
  CHECK(densest_subgraph(t, aff).selection == std::vector<int>{0, 1, 2});
}

TEST_CASE("densest subgraph: bad inputs give clear errors") {
  ConsistencyGraph g(3, {{0, 1}});
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, std::vector<double>(8, 0.5)); }),
                 "affinity has 8 entries, expected n² = 9"));
  std::vector<double> a(9, 0.5);
  a[1] = 1.5;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, a); }), "affinity(0, 1) = 1.5 is not in [0, 1]"));
  a[1] = 0.4;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, a); }), "not symmetric"));
  DensestOptions o;
  o.beta = 1.0;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, o); }), "beta must be in (0, 1)"));
  o = {};
  o.max_outer = 0;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, o); }), "max_outer must be >= 1"));
}
