#include "sim/random_graph.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kit/test_kit.hpp"

using keel::sim::planted_clique_graph;
using keel::sim::random_graph;
using keel::testkit::throws_with;

TEST_CASE("random_graph is deterministic per seed and its edge count matches the density") {
  const auto a = random_graph(200, 0.3, 7), b = random_graph(200, 0.3, 7), c = random_graph(200, 0.3, 8);
  long long same = 0, differ = 0;
  for (int i = 0; i < 200; ++i)
    for (int j = i + 1; j < 200; ++j) {
      same += a.adjacent(i, j) == b.adjacent(i, j);
      differ += a.adjacent(i, j) != c.adjacent(i, j);
    }
  const long long edges_a = a.num_edges();
  const double pairs = 200.0 * 199.0 / 2.0;
  CHECK(same == static_cast<long long>(pairs));
  CHECK(differ > 0);
  // Binomial(19 900, 0.3): standard deviation 64.6 edges; 5 standard deviations.
  CHECK(std::abs(static_cast<double>(edges_a) - 0.3 * pairs) < 5.0 * 64.6);
  CHECK(random_graph(10, 0.0, 1).size() == 10);
}

TEST_CASE("random_graph rejects a density outside [0, 1] and a negative size") {
  CHECK(
      throws_with<std::invalid_argument>([] { (void)random_graph(3, 1.5, 1); }, "density 1.5 not in [0, 1]"));
  CHECK(throws_with<std::invalid_argument>([] { (void)random_graph(-1, 0.5, 1); }, "n = -1"));
}

TEST_CASE("planted_clique_graph: the planted set is a clique of k distinct vertices, the rest is G(n, p)") {
  for (std::uint64_t seed : {3u, 4u}) {
    const auto p = planted_clique_graph(300, 40, 0.2, seed);
    REQUIRE(p.planted.size() == 40);
    CHECK(std::is_sorted(p.planted.begin(), p.planted.end()));
    CHECK(std::adjacent_find(p.planted.begin(), p.planted.end()) == p.planted.end());
    CHECK(p.graph.is_clique(p.planted));
    // Outside the planted set the edges are random_graph's, unchanged.
    const auto base = random_graph(300, 0.2, seed);
    long long differ = 0;
    for (int i = 0; i < 300; ++i)
      for (int j = i + 1; j < 300; ++j)
        if (!(std::binary_search(p.planted.begin(), p.planted.end(), i) &&
              std::binary_search(p.planted.begin(), p.planted.end(), j)))
          differ += p.graph.adjacent(i, j) != base.adjacent(i, j);
    CHECK(differ == 0);
  }
  CHECK(planted_clique_graph(10, 10, 0.0, 1).graph.num_edges() == 45);
  CHECK(planted_clique_graph(10, 0, 0.0, 1).planted.empty());
  CHECK(throws_with<std::invalid_argument>([] { (void)planted_clique_graph(5, 6, 0.5, 1); },
                                           "k = 6 must be in"));
}
