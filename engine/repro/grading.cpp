#include "repro/grading.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "core/random.hpp"
#include "core/statistics.hpp"

namespace keel::repro {

BinomialComparison compare_rates(double ours, double n_ours, double thesis, double n_thesis, double z,
                                 double rounding) {
  if (!(n_ours > 0) || !(n_thesis > 0))
    throw std::invalid_argument(
        fmt::format("compare_rates: trial counts must be positive (ours {}, thesis {})", n_ours, n_thesis));
  auto adjusted_variance = [](double rate, double n) {
    const double p = (rate * n + 1.0) / (n + 2.0);
    return p * (1.0 - p) / (n + 2.0);
  };
  BinomialComparison c;
  c.difference = std::fabs(ours - thesis);
  c.allowed = z * std::sqrt(adjusted_variance(ours, n_ours) + adjusted_variance(thesis, n_thesis)) + rounding;
  c.agrees = c.difference <= c.allowed;
  return c;
}

double sign_test_p(int below, int above) {
  const int n = below + above, k = std::min(below, above);
  if (n == 0) return 1.0;
  // Σ_{i ≤ k} C(n, i) / 2ⁿ in logs (n reaches thousands).
  double tail = 0;
  for (int i = 0; i <= k; ++i)
    tail +=
        std::exp(std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) - n * std::log(2.0));
  return std::min(1.0, 2.0 * tail);
}

PairedComparison paired_comparison(const std::vector<double>& a, const std::vector<double>& b,
                                   const std::function<double(std::vector<double>)>& statistic,
                                   bool median_of_differences, int resamples, double confidence,
                                   std::uint64_t seed) {
  if (a.size() != b.size() || a.empty())
    throw std::invalid_argument(fmt::format(
        "paired_comparison: {} and {} values: need the same, non-zero count", a.size(), b.size()));
  if (resamples < 100)
    throw std::invalid_argument(fmt::format("paired_comparison: resamples = {}: need >= 100", resamples));
  if (!(confidence > 0 && confidence < 1))
    throw std::invalid_argument(
        fmt::format("paired_comparison: confidence = {}: must be in (0, 1)", confidence));
  const std::size_t n = a.size();
  PairedComparison c;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::fabs(a[i] - b[i]) <= 1e-12 * std::max(std::fabs(a[i]), std::fabs(b[i])))
      ++c.ties;
    else if (a[i] < b[i])
      ++c.below;
    else
      ++c.above;
  }
  c.sign_p = sign_test_p(c.below, c.above);
  const auto value = [&](const std::vector<std::size_t>& index) {
    std::vector<double> x, y;
    x.reserve(n), y.reserve(n);
    for (std::size_t i : index) {
      if (median_of_differences)
        x.push_back(a[i] - b[i]);
      else
        x.push_back(a[i]), y.push_back(b[i]);
    }
    return median_of_differences ? statistic(std::move(x))
                                 : statistic(std::move(x)) - statistic(std::move(y));
  };
  std::vector<std::size_t> index(n);
  std::iota(index.begin(), index.end(), 0);
  c.difference = value(index);
  core::Rng rng(seed);
  std::vector<double> boot;
  boot.reserve(static_cast<std::size_t>(resamples));
  for (int r = 0; r < resamples; ++r) {
    for (auto& i : index)
      i = std::min(n - 1, static_cast<std::size_t>(rng.uniform() * static_cast<double>(n)));
    boot.push_back(value(index));
  }
  std::sort(boot.begin(), boot.end());
  // Percentile interval: the order statistics at (1 ∓ confidence)/2, linearly interpolated.
  c.low = core::quantile_sorted(boot, 0.5 * (1 - confidence));
  c.high = core::quantile_sorted(boot, 0.5 * (1 + confidence));
  return c;
}

namespace {
bool ties(double a, double b, double rel) {
  return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b));
}
}  // namespace

std::vector<std::string> ordering_reversals(const std::vector<std::string>& names,
                                            const std::vector<double>& thesis,
                                            const std::vector<double>& ours, double tie_rel) {
  if (names.size() != thesis.size() || names.size() != ours.size())
    throw std::invalid_argument("ordering_reversals: names, thesis and ours differ in size");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = 0; j < names.size(); ++j)
      if (thesis[i] < thesis[j] && !ties(thesis[i], thesis[j], tie_rel) && ours[i] > ours[j] &&
          !ties(ours[i], ours[j], tie_rel))
        out.push_back(fmt::format("{} > {}", names[i], names[j]));
  return out;
}

std::string ordering_text(const std::vector<std::string>& names, const std::vector<double>& values) {
  std::vector<std::size_t> idx(names.size());
  std::iota(idx.begin(), idx.end(), 0);
  // Ascending values, equal values in the order given (std::sort with the index as tie-break:
  // std::stable_sort on size_t trips clang-19's deprecation of libstdc++ 12's get_temporary_buffer under
  // -Werror).
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
    return values[a] != values[b] ? values[a] < values[b] : a < b;
  });
  std::string out;
  for (std::size_t k = 0; k < idx.size(); ++k) {
    if (k > 0) out += ties(values[idx[k - 1]], values[idx[k]], 1e-9) ? " = " : " < ";
    out += names[idx[k]];
  }
  return out;
}

}  // namespace keel::repro
