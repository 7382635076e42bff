// How the report grades our numbers against the thesis's (docs/GRADING.md): the statistics behind the rules
// of [thesis.agreement] and [thesis.orderings] that go beyond an absolute or relative tolerance.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace keel::repro {

// Two rates, each a fraction of n trials, agree when their difference is within z standard errors of a
// difference of two independent binomial proportions (Agresti and Caffo 2000: each rate adjusted by adding
// one success and one failure, p̃ = (x + 1) / (n + 2)), widened by `rounding`: half the unit of the last digit
// the thesis printed (0.0005 for a table of rates printed as 0.997). The adjustment keeps the interval honest
// at rates near 0 or 1, where the plain Wald interval collapses.
struct BinomialComparison {
  double difference = 0, allowed = 0;  // |ours - thesis| and the bound it is tested against
  bool agrees = false;
};
[[nodiscard]] BinomialComparison compare_rates(double ours, double n_ours, double thesis, double n_thesis,
                                               double z = 2.0, double rounding = 0.0);

// A paired comparison of two methods run on the same trials (docs/GRADING.md, "Paired orderings"): the
// statistic of `a` minus that of `b`, a percentile bootstrap interval for it (trials resampled with
// replacement, the same resample for both methods, so the pairing is kept), and an exact two-sided sign test
// on the per-trial differences a_i − b_i (ties, |a_i − b_i| ≤ 1e-12 · max(|a_i|, |b_i|), dropped). An
// ordering "a below b" holds only when the whole interval lies below 0; "no significant difference" when it
// contains 0.
struct PairedComparison {
  double difference = 0;               // statistic(a) − statistic(b) on the trials as they are
  double low = 0, high = 0;            // the bootstrap interval (level `confidence`)
  int below = 0, above = 0, ties = 0;  // trials with a_i < b_i, a_i > b_i, a_i = b_i
  double sign_p = 1;                   // two-sided exact binomial p of below against above
  [[nodiscard]] bool lower() const { return high < 0; }  // a significantly below b
  [[nodiscard]] bool higher() const { return low > 0; }  // a significantly above b
};
// `statistic` maps a sample to a number (the median of the differences is the usual one: pass
// `median_of_differences = true` and the statistic is applied to the per-trial differences a_i − b_i instead
// of to a and b separately). Deterministic for a given seed. Throws std::invalid_argument when a and b differ
// in size or are empty, resamples < 100, or confidence is not in (0, 1).
[[nodiscard]] PairedComparison paired_comparison(const std::vector<double>& a, const std::vector<double>& b,
                                                 const std::function<double(std::vector<double>)>& statistic,
                                                 bool median_of_differences, int resamples = 2000,
                                                 double confidence = 0.95, std::uint64_t seed = 1);
// The exact two-sided sign test: P(X ≤ min(k, n − k)) · 2 (capped at 1) for X ~ Binomial(n, 1/2).
[[nodiscard]] double sign_test_p(int below, int above);

// Whether our values put the quantities in the thesis's order: every pair the thesis orders strictly (a < b)
// must not be reversed in ours beyond a relative tie tolerance (ties in ours fit either order; thesis ties
// impose nothing). Returns the pairs reversed, as "a > b" texts with the names given.
[[nodiscard]] std::vector<std::string> ordering_reversals(const std::vector<std::string>& names,
                                                          const std::vector<double>& thesis,
                                                          const std::vector<double>& ours,
                                                          double tie_rel = 1e-9);

// "a < b < c" with "=" where adjacent values tie (relative 1e-9): the order a set of values puts names in.
[[nodiscard]] std::string ordering_text(const std::vector<std::string>& names,
                                        const std::vector<double>& values);

}  // namespace keel::repro
