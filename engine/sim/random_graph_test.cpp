#include "sim/random_graph.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "kit/test_kit.hpp"

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
