// How the report grades our numbers against the thesis's (docs/GRADING.md): the statistics behind the rules
// of [thesis.agreement] and [thesis.orderings] that go beyond an absolute or relative tolerance.
#pragma once

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
