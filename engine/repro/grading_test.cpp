// Grading statistics of the report (core/grading.hpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "repro/grading.hpp"

using namespace keel::repro;

TEST_CASE("two rates: the Table 2.1 cases") {
  // PCM's FPR 4 of 8100 against the thesis's 0.001 of 8100: well inside sampling error.
  CHECK(compare_rates(4.0 / 8100, 8100, 0.001, 8100, 2.0, 5e-4).agrees);
  // RANSAC-3.5 %'s 0.0117 against 0.001: far outside.
  CHECK_FALSE(compare_rates(0.0117, 8100, 0.001, 8100, 2.0, 5e-4).agrees);
  // TPR 0.941 against 0.997 on 1215 inliers each: outside; 0.995 against 0.997: inside.
  CHECK_FALSE(compare_rates(0.941, 1215, 0.997, 1215).agrees);
  CHECK(compare_rates(0.995, 1215, 0.997, 1215).agrees);
  const auto c = compare_rates(0.5, 100, 0.5, 100, 2.0);
  CHECK(c.difference == 0);
  CHECK(c.allowed == doctest::Approx(2 * std::sqrt(2 * 0.25 / 102)));
  CHECK(compare_rates(0.5, 100, 0.5, 100, 2.0, 0.05).allowed == doctest::Approx(c.allowed + 0.05));
  CHECK_THROWS_AS((void)compare_rates(0.5, 0, 0.5, 10), std::invalid_argument);
}

TEST_CASE("two rates: the rule at z = 2 accepts two samples of one rate about 95 % of the time or more") {
  std::mt19937_64 rng(7);
  for (const double p : {0.001, 0.02, 0.3, 0.97}) {
    const int n = 2000, m = 1000, trials = 4000;
    std::binomial_distribution<int> a(n, p), b(m, p);
    int accepted = 0;
    for (int t = 0; t < trials; ++t) {
      // The thesis's rate is printed to 4 decimals, as a table would.
      const double thesis = std::round(1e4 * b(rng) / m) / 1e4;
      accepted += compare_rates(static_cast<double>(a(rng)) / n, n, thesis, m, 2.0, 5e-5).agrees;
    }
    INFO("p = " << p);
    CHECK(static_cast<double>(accepted) / trials >= 0.93);
  }
  // and rejects a real difference of 5 standard errors almost always.
  std::binomial_distribution<int> a(2000, 0.10), b(2000, 0.10 + 5 * std::sqrt(2 * 0.1 * 0.9 / 2000));
  int accepted = 0;
  for (int t = 0; t < 2000; ++t)
    accepted += compare_rates(a(rng) / 2000.0, 2000, b(rng) / 2000.0, 2000).agrees;
  CHECK(accepted < 100);
}

TEST_CASE("ordering: reversals are the pairs ours puts the other way round") {
  const std::vector<std::string> n{"dcs", "pcm", "ransac"};
  CHECK(ordering_reversals(n, {1, 2, 3}, {10, 20, 30}).empty());
  CHECK(ordering_reversals(n, {1, 2, 3}, {20, 10, 30}) == std::vector<std::string>{"dcs > pcm"});
  // ties in ours fit either order; ties in the thesis impose nothing.
  CHECK(ordering_reversals(n, {1, 2, 3}, {10, 10, 30}).empty());
  CHECK(ordering_reversals(n, {1, 1, 3}, {20, 10, 30}).empty());
  CHECK(ordering_reversals(n, {1, 2, 3}, {30, 20, 10}).size() == 3);
  CHECK(ordering_text(n, {3, 1, 1}) == "pcm = ransac < dcs");
  CHECK_THROWS_AS((void)ordering_reversals(n, {1, 2}, {1, 2, 3}), std::invalid_argument);
}

TEST_CASE("ordering: brute force over every permutation of four values") {
  std::vector<int> perm{0, 1, 2, 3};
  const std::vector<std::string> n{"a", "b", "c", "d"};
  const std::vector<double> thesis{1, 2, 3, 4};
  do {
    std::vector<double> ours(4);
    for (int i = 0; i < 4; ++i) ours[i] = perm[i];
    int inversions = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) inversions += perm[i] > perm[j];
    CHECK(ordering_reversals(n, thesis, ours).size() == static_cast<std::size_t>(inversions));
  } while (std::next_permutation(perm.begin(), perm.end()));
}

TEST_CASE("paired comparison: the exact sign test") {
  CHECK(sign_test_p(0, 0) == 1.0);
  CHECK(sign_test_p(5, 5) == 1.0);
  CHECK(sign_test_p(0, 10) == doctest::Approx(2.0 / 1024));
  CHECK(sign_test_p(8, 2) == doctest::Approx(2.0 * (1 + 10 + 45) / 1024));
  // Large n, by the normal approximation: 600 against 400 is z = 6.3, p ~ 3e-10.
  CHECK(sign_test_p(600, 400) < 1e-9);
  CHECK(sign_test_p(600, 400) > 1e-11);
}

TEST_CASE("paired comparison: a per-trial shift hidden by the spread between trials is found") {
  // Trial difficulty varies by orders of magnitude, method a is 10 % better on every trial: unpaired medians
  // are within each other's spread, the paired median difference is clearly below 0.
  std::mt19937_64 g(5);
  std::lognormal_distribution<double> difficulty(0.0, 2.0);
  std::normal_distribution<double> jitter(0.0, 0.02);
  std::vector<double> a, b;
  for (int i = 0; i < 200; ++i) {
    const double d = difficulty(g);
    b.push_back(d * (1 + jitter(g)));
    a.push_back(0.9 * d * (1 + jitter(g)));
  }
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  };
  const PairedComparison c = paired_comparison(a, b, median, true);
  CHECK(c.lower());
  CHECK_FALSE(c.higher());
  CHECK(c.below > 190);
  CHECK(c.sign_p < 1e-40);
  CHECK(c.low <= c.difference);
  CHECK(c.difference <= c.high);
  // The reverse comparison is the mirror image.
  const PairedComparison r = paired_comparison(b, a, median, true);
  CHECK(r.higher());
  CHECK(r.below == c.above);
  // A statistic of each sample (not of the differences): the difference of the two medians.
  const PairedComparison m = paired_comparison(a, b, median, false);
  CHECK(m.difference == doctest::Approx(median(a) - median(b)));
  CHECK(m.lower());
}

TEST_CASE("paired comparison: two samples of one distribution differ significantly about 5 % of the time") {
  std::mt19937_64 g(11);
  std::exponential_distribution<double> e(1.0);
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  int significant = 0;
  const int runs = 200;
  for (int k = 0; k < runs; ++k) {
    std::vector<double> a, b;
    for (int i = 0; i < 101; ++i) a.push_back(e(g)), b.push_back(e(g));
    const PairedComparison c =
        paired_comparison(a, b, median, true, 500, 0.95, static_cast<std::uint64_t>(k));
    significant += c.lower() || c.higher();
  }
  CHECK(significant <= runs / 10);  // nominal 5 %; 10 is the binomial tail at this count
}

TEST_CASE("paired comparison: bad input is refused") {
  const auto id = [](std::vector<double> v) { return v.empty() ? 0.0 : v[0]; };
  CHECK_THROWS_AS((void)paired_comparison({1, 2}, {1}, id, true), std::invalid_argument);
  CHECK_THROWS_AS((void)paired_comparison({}, {}, id, true), std::invalid_argument);
  CHECK_THROWS_AS((void)paired_comparison({1}, {1}, id, true, 10), std::invalid_argument);
  CHECK_THROWS_AS((void)paired_comparison({1}, {1}, id, true, 1000, 1.5), std::invalid_argument);
}
