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

// Ranks 1 … n of a sample, ties given the mean of the ranks they span.
inline std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<std::size_t> order(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) order[i] = i;
  // std::sort with the index as tie-break (std::stable_sort pulls in libstdc++ 12's deprecated
  // get_temporary_buffer, an error under -Werror with clang 19).
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return v[a] < v[b] || (v[a] == v[b] && a < b); });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && v[order[j + 1]] == v[order[i]]) ++j;
    const double mean_rank = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) r[order[k]] = mean_rank;
    i = j + 1;
  }
  return r;
}

// Spearman's rank correlation: Pearson's correlation of the ranks (ties at their mean rank). 0 when either
// sample is constant, the sizes differ or there are fewer than two pairs.
inline double spearman(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.size() < 2) return 0.0;
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double mean = 0.5 * static_cast<double>(a.size() + 1);  // the mean rank, ties or not
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (ra[i] - mean) * (rb[i] - mean), saa += (ra[i] - mean) * (ra[i] - mean);
    sbb += (rb[i] - mean) * (rb[i] - mean);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
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
