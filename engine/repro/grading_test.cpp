// Grading statistics of the report (core/grading.hpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "repro/grading.hpp"

using namespace keel::repro;

namespace {

// Draws from keel's own generator (core/random.hpp): std's distributions are implementation-defined, so the
// samples, and a test near its threshold, would differ between standard libraries.
using keel::core::Rng;
int binomial(Rng& g, int n, double p) {
  int k = 0;
  for (int i = 0; i < n; ++i) k += g.uniform() < p ? 1 : 0;
  return k;
}
double exponential(Rng& g) { return -std::log1p(-g.uniform()); }

}  // namespace

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
  Rng rng(7);
  for (const double p : {0.001, 0.02, 0.3, 0.97}) {
    const int n = 2000, m = 1000, trials = 4000;
    int accepted = 0;
    for (int t = 0; t < trials; ++t) {
      // The thesis's rate is printed to 4 decimals, as a table would.
      const double thesis = std::round(1e4 * binomial(rng, m, p) / m) / 1e4;
      accepted += compare_rates(static_cast<double>(binomial(rng, n, p)) / n, n, thesis, m, 2.0, 5e-5).agrees;
    }
    INFO("p = " << p);
    CHECK(static_cast<double>(accepted) / trials >= 0.93);
  }
  // and rejects a real difference of 5 standard errors almost always.
  const double shifted = 0.10 + 5 * std::sqrt(2 * 0.1 * 0.9 / 2000);
  int accepted = 0;
  for (int t = 0; t < 2000; ++t)
    accepted +=
        compare_rates(binomial(rng, 2000, 0.10) / 2000.0, 2000, binomial(rng, 2000, shifted) / 2000.0, 2000)
            .agrees;
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

namespace {
double test_median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
// P(X ≤ k), X ~ Binomial(n, 1/2), by exact integer counting (n ≤ 60).
double binomial_cdf_exact(int n, int k) {
  double sum = 0, c = 1;  // C(n, 0)
  for (int i = 0; i <= k; ++i) {
    sum += c;
    c = c * (n - i) / (i + 1);
  }
  return sum / std::ldexp(1.0, n);
}
}  // namespace

TEST_CASE("paired comparison: the exact sign test, ties counted against rejection") {
  CHECK(sign_test_p(0, 0) == 1.0);
  CHECK(sign_test_p(5, 5) == 1.0);
  CHECK(sign_test_p(0, 10) == doctest::Approx(2.0 / 1024));
  CHECK(sign_test_p(8, 2) == doctest::Approx(2.0 * (1 + 10 + 45) / 1024));
  // Two ties among 12 trials join the weaker side: P(X ≤ 4) for n = 12.
  CHECK(sign_test_p(8, 2, 2) == doctest::Approx(2.0 * binomial_cdf_exact(12, 4)));
  // Large n, by the normal approximation: 600 against 400 is z = 6.3, p ~ 3e-10.
  CHECK(sign_test_p(600, 400) < 1e-9);
  CHECK(sign_test_p(600, 400) > 1e-11);
  CHECK_THROWS_AS((void)sign_test_p(-1, 2), std::invalid_argument);
}

TEST_CASE("paired comparison: the order-statistic interval excludes 0 exactly when the sign test rejects") {
  Rng g(3);
  const auto z = [](Rng& r) { return r.normal(); };
  const auto coin = [](Rng& r) { return static_cast<int>(4 * r.uniform()); };
  int excluded = 0;
  for (int n = 1; n <= 60; ++n) {
    for (int rep = 0; rep < 40; ++rep) {
      const double shift = 0.15 * (rep % 7 - 3);
      std::vector<double> a, b;
      for (int i = 0; i < n; ++i) {
        const double base = std::exp(z(g));
        b.push_back(base);
        a.push_back(coin(g) == 0 ? base : base + shift + 0.5 * z(g));  // a quarter of the trials tie
      }
      const PairedComparison c = paired_median(a, b);
      CHECK(c.units == static_cast<std::size_t>(n));
      CHECK(c.below + c.above + c.ties == n);
      CHECK(((c.high < 0) || (c.low > 0)) == (c.p <= 0.05));
      CHECK((c.lower() || c.higher()) == (c.p <= 0.05));
      excluded += c.p <= 0.05;
      // k from its definition, by exact binomial sums: the interval is [d_(k), d_(n+1−k)].
      int k = 0;
      while (k < n && binomial_cdf_exact(n, k) <= 0.025) ++k;
      std::vector<double> d;
      for (int i = 0; i < n; ++i) d.push_back(a[i] == b[i] ? 0.0 : a[i] - b[i]);
      std::sort(d.begin(), d.end());
      if (k == 0) {
        CHECK(std::isinf(c.low));
        CHECK(std::isinf(c.high));
        CHECK(c.p > 0.05);
      } else {
        CHECK(c.low == d[static_cast<std::size_t>(k - 1)]);
        CHECK(c.high == d[static_cast<std::size_t>(n - k)]);
      }
      CHECK(c.difference == test_median(d));
      CHECK(c.difference_of_medians == doctest::Approx(test_median(a) - test_median(b)));
    }
  }
  CHECK(excluded > 100);  // the test has power: both outcomes are exercised
}

TEST_CASE(
    "paired comparison: the order-statistic interval covers the median difference at least 95 % of the "
    "time") {
  Rng g(21);
  const auto e = [](Rng& r) { return exponential(r); };
  // d_i = a_i − b_i with a_i = b_i + 0.3 + (Exp(1) − ln 2): the median of d is 0.3 exactly.
  int covered = 0;
  const int runs = 2000;
  for (int r = 0; r < runs; ++r) {
    std::vector<double> a, b;
    for (int i = 0; i < 25; ++i) {
      const double x = e(g);
      b.push_back(x), a.push_back(x + 0.3 + e(g) - std::log(2.0));
    }
    const PairedComparison c = paired_median(a, b);
    covered += c.low <= 0.3 && 0.3 <= c.high;
  }
  // Exact coverage for n = 25 is 1 − 2 P(X ≤ 7) = 0.9567; 3 standard errors below it.
  CHECK(covered >= static_cast<int>(runs * (0.9567 - 3 * std::sqrt(0.9567 * 0.0433 / runs))));
}

TEST_CASE("paired comparison: a per-trial shift hidden by the spread between trials is found") {
  // Trial difficulty varies by orders of magnitude, method a is 10 % better on every trial: unpaired medians
  // are within each other's spread, the paired median difference is clearly below 0.
  Rng g(5);
  const auto difficulty = [](Rng& r) { return std::exp(2.0 * r.normal()); };  // lognormal(0, 2)
  const auto jitter = [](Rng& r) { return 0.02 * r.normal(); };
  std::vector<double> a, b;
  for (int i = 0; i < 200; ++i) {
    const double d = difficulty(g);
    b.push_back(d * (1 + jitter(g)));
    a.push_back(0.9 * d * (1 + jitter(g)));
  }
  const PairedComparison c = paired_median(a, b);
  CHECK(c.lower());
  CHECK_FALSE(c.higher());
  CHECK(c.below > 190);
  CHECK(c.p < 1e-40);
  CHECK(c.low <= c.difference);
  CHECK(c.difference <= c.high);
  // The reverse comparison is the mirror image.
  const PairedComparison r = paired_median(b, a);
  CHECK(r.higher());
  CHECK(r.below == c.above);
  // A statistic of each sample (not of the differences): the difference of the two medians, by the bootstrap.
  const PairedComparison m = paired_statistic(a, b, test_median);
  CHECK(m.difference == doctest::Approx(test_median(a) - test_median(b)));
  CHECK(m.lower());
  CHECK(((m.high < 0) || (m.low > 0)) == (m.p <= 0.05));
}

TEST_CASE("paired comparison: the bootstrap interval excludes 0 exactly when its p is at most alpha") {
  Rng g(8);
  const auto z = [](Rng& r) { return r.normal(); };
  int rejected = 0, kept = 0;
  for (int rep = 0; rep < 60; ++rep) {
    std::vector<double> a, b;
    const double shift = 0.1 * (rep % 9 - 4);
    for (int i = 0; i < 40; ++i) b.push_back(z(g)), a.push_back(b.back() + shift + 0.5 * z(g));
    const auto mean = [](std::vector<double> v) {
      return std::accumulate(v.begin(), v.end(), 0.0) / v.size();
    };
    PairedOptions o;
    o.resamples = 999, o.seed = 7u + static_cast<unsigned>(rep);
    const PairedComparison c = paired_statistic(a, b, mean, o);
    CHECK(((c.high < 0) || (c.low > 0)) == (c.p <= 0.05));
    (c.p <= 0.05 ? rejected : kept) += 1;
  }
  CHECK(rejected > 5);
  CHECK(kept > 5);
}

TEST_CASE("paired comparison: two rates by McNemar's exact test and the interval that inverts it") {
  // 10 trials where only a succeeds, none where only b does, 90 concordant: p = 2 / 2^10; the Clopper-Pearson
  // interval for π is [0.025^(1/10), 1], so the rate difference lies in [(2·0.025^0.1 − 1)·10, 10] points.
  std::vector<double> a(100, 0.0), b(100, 0.0);
  for (int i = 0; i < 10; ++i) a[static_cast<std::size_t>(i)] = 1;
  for (int i = 50; i < 80; ++i) a[static_cast<std::size_t>(i)] = b[static_cast<std::size_t>(i)] = 1;
  const PairedComparison c = paired_rate(a, b);
  CHECK(c.difference == doctest::Approx(10.0));
  CHECK(c.p == doctest::Approx(2.0 / 1024));
  CHECK(c.low == doctest::Approx((2 * std::pow(0.025, 0.1) - 1) * 10).epsilon(1e-9));
  CHECK(c.high == doctest::Approx(10.0));
  CHECK(c.higher());
  CHECK(c.ties == 90);
  // Random pairs of indicators: the interval excludes 0 exactly when the exact test's p is at most 0.05.
  Rng g(17);
  const auto u = [](Rng& r) { return r.uniform(); };
  int rejected = 0;
  for (int rep = 0; rep < 300; ++rep) {
    const double pa = 0.3 + 0.4 * u(g), pb = 0.3 + 0.4 * u(g);
    std::vector<double> x, y;
    for (int i = 0; i < 20 + rep % 60; ++i) x.push_back(u(g) < pa), y.push_back(u(g) < pb);
    const PairedComparison r = paired_rate(x, y);
    CHECK(((r.high < 0) || (r.low > 0)) == (r.p <= 0.05));
    CHECK(r.low <= r.difference + 1e-9);
    CHECK(r.difference <= r.high + 1e-9);
    rejected += r.p <= 0.05;
  }
  CHECK(rejected > 10);
}

TEST_CASE("paired comparison: trials in blocks are compared block by block") {
  // Four blocks of 50 trials; within a block every trial shares the block's difference, so the 200 trials
  // carry four independent values: no interval exists at n = 4 and nothing is significant, though all 200
  // differences are negative.
  std::vector<double> a, b;
  std::vector<std::size_t> blocks;
  for (std::size_t k = 0; k < 4; ++k)
    for (int i = 0; i < 50; ++i)
      b.push_back(1.0 + i), a.push_back(b.back() - 0.1 * (k + 1)), blocks.push_back(k);
  const PairedComparison flat = paired_median(a, b);
  CHECK(flat.lower());
  PairedOptions o;
  o.blocks = blocks;
  const PairedComparison c = paired_median(a, b, o);
  CHECK(c.units == 4);
  CHECK(c.below == 4);
  CHECK(std::isinf(c.high));
  CHECK_FALSE(c.lower());
  CHECK(c.p == doctest::Approx(2.0 / 16));
  CHECK(c.difference == doctest::Approx(-0.25));  // the median of the block medians −0.1, −0.2, −0.3, −0.4
  // The spread statistic block by block: the difference of the statistic within each block.
  const PairedComparison s = paired_statistic(a, b, test_median, o);
  CHECK(s.units == 4);
  CHECK(s.difference == doctest::Approx(-0.25));
  CHECK_THROWS_AS((void)paired_median(a, b, {.blocks = {0, 1}}), std::invalid_argument);
}

TEST_CASE("Holm's correction: the step-down adjustment and its family-wise error rate") {
  const std::vector<double> q = holm_adjust({0.01, 0.04, 0.03, 0.005});
  // Sorted 0.005, 0.01, 0.03, 0.04 times 4, 3, 2, 1: 0.02, 0.03, 0.06, 0.04 → monotone 0.02, 0.03, 0.06,
  // 0.06.
  CHECK(q[3] == doctest::Approx(0.02));
  CHECK(q[0] == doctest::Approx(0.03));
  CHECK(q[2] == doctest::Approx(0.06));
  CHECK(q[1] == doctest::Approx(0.06));
  CHECK(holm_adjust({0.5, 0.9}) == std::vector<double>{1.0, 1.0});
  CHECK(holm_adjust({}).empty());
  CHECK_THROWS_AS((void)holm_adjust({1.5}), std::invalid_argument);
  // Families of 20 comparisons of one distribution against itself: any rejection in at most ~5 % of families.
  Rng g(13);
  const auto e = [](Rng& r) { return exponential(r); };
  int families_with_rejection = 0, unadjusted_rejections = 0;
  const int runs = 300;
  for (int r = 0; r < runs; ++r) {
    PairedFamily f;
    for (int k = 0; k < 20; ++k) {
      std::vector<double> a, b;
      for (int i = 0; i < 41; ++i) a.push_back(e(g)), b.push_back(e(g));
      PairedComparison c = paired_median(a, b);
      unadjusted_rejections += c.lower() || c.higher();
      f.add("c" + std::to_string(k), c);
    }
    f.adjust();
    families_with_rejection += f.significant() > 0;
  }
  CHECK(families_with_rejection <= runs * 8 / 100);  // nominal ≤ 5 %; the binomial tail at this count
  CHECK(unadjusted_rejections > runs * 20 / 50);     // without the correction, ~1 in 20 comparisons (≥ 2 %)
}

TEST_CASE("PairedFamily: keys once, read only after the correction") {
  PairedFamily f;
  f.add("x", paired_median({1, 2, 3}, {2, 3, 4}));
  CHECK_THROWS_AS(f.add("x", PairedComparison{}), std::invalid_argument);
  CHECK_THROWS_AS((void)f.at("x"), std::logic_error);
  f.adjust();
  CHECK(f.at("x").adjusted_p == f.at("x").p);
  CHECK_THROWS_AS((void)f.at("y"), std::out_of_range);
  CHECK_THROWS_AS(f.add("z", PairedComparison{}), std::invalid_argument);
}

TEST_CASE("paired comparison: bad input is refused") {
  const auto id = [](std::vector<double> v) { return v.empty() ? 0.0 : v[0]; };
  CHECK_THROWS_AS((void)paired_median({1, 2}, {1}), std::invalid_argument);
  CHECK_THROWS_AS((void)paired_median({}, {}), std::invalid_argument);
  PairedOptions few, level;
  few.resamples = 10, level.alpha = 1.5;
  CHECK_THROWS_AS((void)paired_statistic({1}, {1}, id, few), std::invalid_argument);
  CHECK_THROWS_AS((void)paired_statistic({1}, {1}, id, level), std::invalid_argument);
}
