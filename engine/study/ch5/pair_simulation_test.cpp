#include <doctest/doctest.h>

#include <cmath>

#include "kit/test_kit.hpp"
#include "lie/euler.hpp"
#include "study/ch5/pair_simulation.hpp"

using namespace keel::lie;
using namespace keel::study::ch5;
using keel::core::Streams;
using keel::repro::RunContext;
namespace testkit = keel::testkit;

TEST_CASE("pair study: joint prediction agrees with Monte Carlo, independent does not, deterministic" *
          doctest::test_suite("monte_carlo")) {
  std::vector<SE2> poses = {SE2(0, 0, 0), SE2(10, 5, 1.0), SE2(-4, 8, -2.0)};
  // Strongly correlated pair covariance (like poses far apart along a chain with a common drift).
  Mat6 S = Mat6::Zero();
  const Vec3 sd(0.05, 0.04, 0.01);
  for (int a = 0; a < 3; ++a) {
    S(a, a) = S(a + 3, a + 3) = sd(a) * sd(a);
    S(a, a + 3) = S(a + 3, a) = 0.9 * sd(a) * sd(a);
  }
  PairStudySetup setup;
  setup.samples = 20000;
  const std::vector<std::pair<int, int>> pairs = {{1, 2}, {0, 1}};
  const auto a = simulate_pairs_2d(poses, pairs, {S, S}, setup, RunContext(Streams(7), 1));
  const auto b = simulate_pairs_2d(poses, pairs, {S, S}, setup, RunContext(Streams(7), 2));
  REQUIRE(a.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) {
    CHECK(a[k].error_joint == b[k].error_joint);
    CHECK(a[k].normalized_error_ssc == b[k].normalized_error_ssc);
    CHECK(a[k].corr_x == doctest::Approx(0.9));
    CHECK(a[k].corr_theta == doctest::Approx(0.9));
    // Small noise: the joint first-order prediction is within Monte-Carlo error (normalized ε ~ sqrt(2/M)),
    // ignoring the 0.9 correlation is off by a large factor.
    CHECK(a[k].normalized_error_lie < 0.05);
    CHECK(a[k].error_independent > 10 * a[k].error_joint);
    // SSC at small noise is first-order accurate too in its own parameters.
    CHECK(a[k].normalized_error_ssc < 0.05);
  }
  CHECK(a[0].i == 1);
  CHECK(a[0].j == 2);
}

TEST_CASE("pair study: bad inputs are rejected with clear messages") {
  std::vector<SE2> poses = {SE2(0, 0, 0), SE2(1, 0, 0)};
  PairStudySetup setup;
  setup.samples = 10;
  CHECK_THROWS_WITH_AS(
      (void)simulate_pairs_2d(poses, {{0, 5}}, {Mat6::Identity()}, setup, RunContext(Streams(1))),
      doctest::Contains("outside [0, 2)"), std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)simulate_pairs_2d(poses, {{0, 1}}, {}, setup, RunContext(Streams(1))),
                       doctest::Contains("1 pairs but 0"), std::invalid_argument);
  Mat6 bad = Mat6::Identity();
  bad(0, 0) = -1;
  CHECK_THROWS_WITH_AS((void)simulate_pairs_2d(poses, {{0, 1}}, {bad}, setup, RunContext(Streams(1))),
                       doctest::Contains("pair (0, 1)"), std::runtime_error);
  setup.samples = 1;
  CHECK_THROWS_AS((void)simulate_pairs_2d(poses, {{0, 1}}, {Mat6::Identity()}, setup, RunContext(Streams(1))),
                  std::invalid_argument);
}
