// How the report grades our numbers against the thesis's (docs/GRADING.md): the statistics behind the rules
// of [thesis.agreement] and [thesis.orderings] that go beyond an absolute or relative tolerance.
#pragma once

#include <cstddef>
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

// A paired comparison of two methods run on the same trials (docs/GRADING.md, "Paired orderings").
//
// Two statistics, two intervals, each the inversion of its own test, so that the interval excludes 0 exactly
// when that test's p is at most alpha:
// * `paired_median`: the median of the per-trial differences d_i = a_i − b_i, with the distribution-free
//   order-statistic interval [d_(k), d_(n+1−k)], k the largest integer with P(X ≤ k − 1) ≤ alpha/2 for
//   X ~ Binomial(n, 1/2), and the exact two-sided sign test on all n differences with each tie
//   (|d_i| ≤ 1e-12 · max(|a_i|, |b_i|), set to 0) counted against rejection: p = min(1, 2 P(X ≤ m)), m the
//   count on the weaker side plus the ties. Below n = 6 (alpha = 0.05) no k exists: the interval is
//   (−inf, inf) and p > alpha. The difference of the two medians is reported beside.
// * `paired_statistic`: statistic(a) − statistic(b) (a spread, a rate), with a bootstrap over the trials (the
//   same resample for both methods, so the pairing is kept): the interval is [b_(j), b_(R+1−j)] of the R
//   sorted resampled values, j = floor(alpha/2 · (R + 1)), and p = min(1, 2 (c + 1) / (R + 1)) with c the
//   resampled values on the far side of 0 (≤ 0 for a difference above 0, ≥ 0 for one below).
// Trials that share data (overlapping terrain windows) carry a block per trial: each block contributes one
// value — the median of its per-trial differences, or statistic(a) − statistic(b) over its trials — and both
// statistics become the median of the block values with the order-statistic interval and sign test over
// blocks.
//
// `adjusted_p` is the p after Holm's correction over the comparison's declared family (`PairedFamily`); it
// equals p for a comparison outside any family. An ordering "a below b" holds only when adjusted_p ≤ alpha
// and the interval lies below 0. A comparison that is not significant is never read as "no difference": that
// needs an equivalence margin stated before the run, and no experiment states one.
struct PairedOptions {
  double alpha = 0.05;     // 1 − the interval's level; the family-wise level of Holm's correction
  int resamples = 20000;   // bootstrap resamples (paired_statistic without blocks): p ≥ 2/(R + 1), which
                           // Holm over m comparisons can use only when 2m/(R + 1) ≤ alpha
  std::uint64_t seed = 1;  // of the bootstrap
  std::vector<std::size_t> blocks;  // per trial, the spatial block it lies in; empty: trials independent
};
struct PairedComparison {
  double difference = 0;               // the statistic (median of differences, or difference of statistics)
  double difference_of_medians = 0;    // median(a) − median(b), beside the median of differences
  double low = 0, high = 0;            // the interval (see above); ±inf where too few values for one
  int below = 0, above = 0, ties = 0;  // trials (or blocks) with a_i < b_i, a_i > b_i, a_i = b_i
  std::size_t units = 0;               // the values the interval rests on: trials, or blocks
  double p = 1;                        // of the test the interval inverts
  double adjusted_p = 1;               // Holm-adjusted within the family (p outside any family)
  double alpha = 0.05;
  [[nodiscard]] bool lower() const { return adjusted_p <= alpha && high < 0; }  // a significantly below b
  [[nodiscard]] bool higher() const { return adjusted_p <= alpha && low > 0; }  // a significantly above b
};
// * `paired_rate`: two success indicators per trial (a value > 0.5 is a success), the difference of the
// success
//   rates in percentage points with McNemar's exact test (the sign test on the discordant trials, concordant
//   ones dropped) and the interval that inverts it: the Clopper-Pearson interval [π_lo, π_hi] for the share π
//   of discordant trials where a succeeds, mapped to 100 (2π − 1) m/n (m discordant of n). Blocks: as
//   paired_statistic with the mean. A bootstrap p can never fall below 2/(R + 1), which Holm's correction
//   over a large family cannot use; the exact test has no such floor.
// All throw std::invalid_argument when a and b differ in size or are empty, blocks is neither empty nor of
// their size, resamples < 100, or alpha is not in (0, 1). Deterministic for a given seed.
[[nodiscard]] PairedComparison paired_median(const std::vector<double>& a, const std::vector<double>& b,
                                             const PairedOptions& options = {});
[[nodiscard]] PairedComparison paired_statistic(const std::vector<double>& a, const std::vector<double>& b,
                                                const std::function<double(std::vector<double>)>& statistic,
                                                const PairedOptions& options = {});
[[nodiscard]] PairedComparison paired_rate(const std::vector<double>& a, const std::vector<double>& b,
                                           const PairedOptions& options = {});

// The exact two-sided sign test with `ties` counted against rejection: min(1, 2 P(X ≤ min(below, above) +
// ties)) for X ~ Binomial(below + above + ties, 1/2).
[[nodiscard]] double sign_test_p(int below, int above, int ties = 0);

// Holm's step-down correction (Holm 1979): with p sorted ascending, p̃_(i) = max_{j ≤ i} min(1, (m − j + 1)
// p_(j)). It holds the family-wise error rate at alpha under any dependence between the comparisons. Returned
// in the order given.
[[nodiscard]] std::vector<double> holm_adjust(const std::vector<double>& p);

// A declared family of paired comparisons, corrected together: every comparison an experiment makes is added
// under its results key, then `adjust` applies Holm's correction; `at` returns a comparison only after that.
class PairedFamily {
 public:
  // Throws std::invalid_argument on a key already added, or after adjust().
  void add(const std::string& key, PairedComparison c);
  void adjust();
  [[nodiscard]] const PairedComparison& at(
      const std::string& key) const;  // throws before adjust() or if absent
  [[nodiscard]] std::size_t size() const { return keys_.size(); }
  [[nodiscard]] std::size_t significant() const;  // adjusted_p ≤ alpha and the interval off 0
  [[nodiscard]] const std::vector<std::string>& keys() const { return keys_; }

 private:
  std::vector<std::string> keys_;
  std::vector<PairedComparison> items_;
  bool adjusted_ = false;
};

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
