// Summary statistics of a sample, shared by studies and drivers.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace keel::core {

struct MeanStd {
  double mean = 0.0;  // arithmetic mean
  double std = 0.0;   // sample standard deviation (n − 1); 0 for fewer than two values
  double min = 0.0, max = 0.0;
};

// Mean, sample standard deviation, minimum and maximum; all zero for an empty sample.
inline MeanStd mean_std(const std::vector<double>& v) {
  MeanStd s;
  if (v.empty()) return s;
  s.min = s.max = v[0];
  for (double x : v) {
    s.mean += x;
    s.min = std::min(s.min, x);
    s.max = std::max(s.max, x);
  }
  s.mean /= static_cast<double>(v.size());
  if (v.size() > 1) {
    for (double x : v) s.std += (x - s.mean) * (x - s.mean);
    s.std = std::sqrt(s.std / static_cast<double>(v.size() - 1));
  }
  return s;
}

// The q-quantile (q in [0, 1]) of an ascending sample by linear interpolation between order statistics at
// position q · (n − 1); 0 for an empty sample.
inline double quantile_sorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const double pos = q * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (pos - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

// Median (mean of the two middle values for an even count); 0 for an empty sample.
inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

// The Wilson score interval of a binomial proportion: `successes` of `n` trials, z standard normal quantiles
// wide (1.96: 95 %). Unlike the Wald interval p ± z √(p(1 − p)/n) it does not collapse to a point at 0 or n
// successes: 0 of 300 gives [0, 0.0126]. n ≤ 0 gives [0, 1].
struct Proportion {
  double rate = 0.0, low = 0.0, high = 1.0;
};
inline Proportion wilson_interval(double successes, double n, double z = 1.959963984540054) {
  Proportion p;
  if (!(n > 0)) return p;
  p.rate = successes / n;
  const double z2 = z * z, denominator = 1.0 + z2 / n;
  const double centre = (p.rate + z2 / (2.0 * n)) / denominator;
  const double half = z * std::sqrt(p.rate * (1.0 - p.rate) / n + z2 / (4.0 * n * n)) / denominator;
  p.low = std::max(0.0, centre - half), p.high = std::min(1.0, centre + half);
  if (successes <= 0) p.low = 0.0;  // exact at the edges (the formula gives them to rounding)
  if (successes >= n) p.high = 1.0;
  return p;
}

}  // namespace keel::core
