#include "repro/grading.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
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

namespace {

// log C(n, i), by lgamma (n reaches thousands).
double log_choose(int n, int i) {
  return std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0);
}

// log P(X = i) for X ~ Binomial(n, 1/2).
double log_binomial_half(int n, int i) { return log_choose(n, i) - n * std::log(2.0); }

// P(X ≤ k) for X ~ Binomial(n, 1/2).
double binomial_half_cdf(int n, int k) {
  double tail = 0;
  for (int i = 0; i <= std::min(k, n); ++i) tail += std::exp(log_binomial_half(n, i));
  return tail;
}

double median_sorted(const std::vector<double>& v) {
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return median_sorted(v);
}

bool tie(double a, double b) { return std::fabs(a - b) <= 1e-12 * std::max(std::fabs(a), std::fabs(b)); }

void check_paired(const std::vector<double>& a, const std::vector<double>& b, const PairedOptions& o) {
  if (a.size() != b.size() || a.empty())
    throw std::invalid_argument(fmt::format(
        "paired comparison: {} and {} values: need the same, non-zero count", a.size(), b.size()));
  if (!o.blocks.empty() && o.blocks.size() != a.size())
    throw std::invalid_argument(fmt::format("paired comparison: {} blocks for {} trials: need one per trial",
                                            o.blocks.size(), a.size()));
  if (o.resamples < 100)
    throw std::invalid_argument(fmt::format("paired comparison: resamples = {}: need >= 100", o.resamples));
  if (!(o.alpha > 0 && o.alpha < 1))
    throw std::invalid_argument(fmt::format("paired comparison: alpha = {}: must be in (0, 1)", o.alpha));
}

// The median of `values` (ties already set to exactly 0) with the order-statistic interval and the sign test
// it inverts (grading.hpp).
void order_statistic(std::vector<double> values, double alpha, PairedComparison& c) {
  c.below = c.above = c.ties = 0;
  for (double v : values) (v < 0 ? c.below : v > 0 ? c.above : c.ties) += 1;
  const int n = static_cast<int>(values.size());
  c.units = values.size();
  c.p = sign_test_p(c.below, c.above, c.ties);
  std::sort(values.begin(), values.end());
  c.difference = median_sorted(values);
  // k − 1 = the largest j with P(X ≤ j) ≤ alpha/2; none when P(X = 0) = 2^-n exceeds it.
  int k = 0;
  while (k < n && binomial_half_cdf(n, k) <= alpha / 2) ++k;
  if (k == 0) {
    c.low = -std::numeric_limits<double>::infinity(), c.high = std::numeric_limits<double>::infinity();
  } else {
    c.low = values[static_cast<std::size_t>(k - 1)];
    c.high = values[static_cast<std::size_t>(n - k)];
  }
}

// Per block, in order of first appearance: the indices of its trials.
std::vector<std::vector<std::size_t>> group_blocks(const std::vector<std::size_t>& blocks) {
  std::vector<std::vector<std::size_t>> groups;
  std::vector<std::size_t> ids;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const auto it = std::find(ids.begin(), ids.end(), blocks[i]);
    if (it == ids.end()) {
      ids.push_back(blocks[i]), groups.push_back({i});
    } else {
      groups[static_cast<std::size_t>(it - ids.begin())].push_back(i);
    }
  }
  return groups;
}

// The per-trial difference, with a tie set to exactly 0.
double difference(double a, double b) { return tie(a, b) ? 0.0 : a - b; }

}  // namespace

double sign_test_p(int below, int above, int ties) {
  if (below < 0 || above < 0 || ties < 0)
    throw std::invalid_argument(
        fmt::format("sign_test_p: counts {}, {}, {} must be >= 0", below, above, ties));
  const int n = below + above + ties;
  if (n == 0) return 1.0;
  return std::min(1.0, 2.0 * binomial_half_cdf(n, std::min(below, above) + ties));
}

PairedComparison paired_median(const std::vector<double>& a, const std::vector<double>& b,
                               const PairedOptions& o) {
  check_paired(a, b, o);
  PairedComparison c;
  c.alpha = o.alpha;
  c.difference_of_medians = median_of(a) - median_of(b);
  std::vector<double> values;
  if (o.blocks.empty()) {
    for (std::size_t i = 0; i < a.size(); ++i) values.push_back(difference(a[i], b[i]));
  } else {
    for (const auto& g : group_blocks(o.blocks)) {
      std::vector<double> d;
      for (std::size_t i : g) d.push_back(difference(a[i], b[i]));
      values.push_back(median_of(std::move(d)));
    }
  }
  order_statistic(std::move(values), o.alpha, c);
  c.adjusted_p = c.p;
  return c;
}

PairedComparison paired_statistic(const std::vector<double>& a, const std::vector<double>& b,
                                  const std::function<double(std::vector<double>)>& statistic,
                                  const PairedOptions& o) {
  check_paired(a, b, o);
  PairedComparison c;
  c.alpha = o.alpha;
  c.difference_of_medians = median_of(a) - median_of(b);
  if (!o.blocks.empty()) {
    std::vector<double> values;
    for (const auto& g : group_blocks(o.blocks)) {
      std::vector<double> x, y;
      for (std::size_t i : g) x.push_back(a[i]), y.push_back(b[i]);
      const double sx = statistic(x), sy = statistic(y);
      values.push_back(difference(sx, sy));
    }
    order_statistic(std::move(values), o.alpha, c);
    c.adjusted_p = c.p;
    return c;
  }
  const std::size_t n = a.size();
  for (std::size_t i = 0; i < n; ++i) (tie(a[i], b[i]) ? c.ties : a[i] < b[i] ? c.below : c.above) += 1;
  c.units = n;
  const auto value = [&](const std::vector<std::size_t>& index) {
    std::vector<double> x, y;
    x.reserve(n), y.reserve(n);
    for (std::size_t i : index) x.push_back(a[i]), y.push_back(b[i]);
    return statistic(std::move(x)) - statistic(std::move(y));
  };
  std::vector<std::size_t> index(n);
  std::iota(index.begin(), index.end(), 0);
  c.difference = value(index);
  core::Rng rng(o.seed);
  std::vector<double> boot;
  boot.reserve(static_cast<std::size_t>(o.resamples));
  for (int r = 0; r < o.resamples; ++r) {
    for (auto& i : index)
      i = std::min(n - 1, static_cast<std::size_t>(rng.uniform() * static_cast<double>(n)));
    boot.push_back(value(index));
  }
  std::sort(boot.begin(), boot.end());
  // The order statistics j and R + 1 − j of the resampled values, j = floor(alpha/2 · (R + 1)); j = 0 (alpha
  // below 2/(R + 1)) leaves no finite interval.
  const std::size_t R = boot.size();
  const auto j = static_cast<std::size_t>(std::floor(o.alpha / 2 * static_cast<double>(R + 1)));
  if (j == 0) {
    c.low = -std::numeric_limits<double>::infinity(), c.high = std::numeric_limits<double>::infinity();
  } else {
    c.low = boot[j - 1], c.high = boot[R - j];
  }
  // p inverts that interval: high < 0 ⇔ at most j − 1 values ≥ 0 ⇔ 2 (#{≥ 0} + 1) / (R + 1) ≤ alpha.
  const auto at_least = static_cast<double>(boot.end() - std::lower_bound(boot.begin(), boot.end(), 0.0));
  const auto at_most = static_cast<double>(std::upper_bound(boot.begin(), boot.end(), 0.0) - boot.begin());
  c.p = std::min(1.0, 2.0 * (std::min(at_least, at_most) + 1.0) / static_cast<double>(R + 1));
  c.adjusted_p = c.p;
  return c;
}

namespace {
// P(X ≤ k) for X ~ Binomial(n, π), 0 < π < 1, in logs.
double binomial_cdf(int n, int k, double pi) {
  if (k < 0) return 0.0;
  if (k >= n) return 1.0;
  double sum = 0;
  for (int i = 0; i <= k; ++i)
    sum += std::exp(log_choose(n, i) + i * std::log(pi) + (n - i) * std::log1p(-pi));
  return std::min(1.0, sum);
}
// The π in (0, 1) where the decreasing function f(π) equals target, by bisection.
template <class F>
double solve_decreasing(F f, double target) {
  double lo = 0, hi = 1;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}
}  // namespace

PairedComparison paired_rate(const std::vector<double>& a, const std::vector<double>& b,
                             const PairedOptions& o) {
  check_paired(a, b, o);
  if (!o.blocks.empty()) {
    const auto mean = [](std::vector<double> v) {
      return 100.0 * std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
    };
    return paired_statistic(a, b, mean, o);
  }
  PairedComparison c;
  c.alpha = o.alpha;
  const auto n = static_cast<int>(a.size());
  int wins = 0, losses = 0;  // trials where only a succeeds, only b
  double sa = 0, sb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const bool x = a[i] > 0.5, y = b[i] > 0.5;
    sa += x, sb += y;
    wins += x && !y, losses += !x && y;
  }
  c.units = a.size();
  c.above = wins, c.below = losses, c.ties = n - wins - losses;
  c.difference = 100.0 * (sa - sb) / n;
  c.difference_of_medians = 0;
  const int m = wins + losses;
  c.p = sign_test_p(losses, wins);  // McNemar's exact test: the concordant trials say nothing
  if (m == 0) {
    c.low = c.high = 0;  // no discordant trial: the interval is the point 0
  } else {
    // Clopper-Pearson for π = P(a succeeds | discordant): P(X ≥ wins | π_lo) = alpha/2, P(X ≤ wins | π_hi) =
    // alpha/2.
    const double pi_lo =
        wins == 0
            ? 0.0
            : solve_decreasing([&](double pi) { return binomial_cdf(m, wins - 1, pi); }, 1 - o.alpha / 2);
    const double pi_hi =
        wins == m ? 1.0 : solve_decreasing([&](double pi) { return binomial_cdf(m, wins, pi); }, o.alpha / 2);
    const double scale = 100.0 * m / n;
    c.low = (2 * pi_lo - 1) * scale, c.high = (2 * pi_hi - 1) * scale;
  }
  c.adjusted_p = c.p;
  return c;
}

std::vector<double> holm_adjust(const std::vector<double>& p) {
  for (double x : p)
    if (!(x >= 0 && x <= 1))
      throw std::invalid_argument(fmt::format("holm_adjust: p = {} is not in [0, 1]", x));
  const std::size_t m = p.size();
  std::vector<std::size_t> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t x, std::size_t y) { return p[x] != p[y] ? p[x] < p[y] : x < y; });
  std::vector<double> out(m);
  double running = 0;
  for (std::size_t r = 0; r < m; ++r) {
    running = std::max(running, std::min(1.0, static_cast<double>(m - r) * p[order[r]]));
    out[order[r]] = running;
  }
  return out;
}

void PairedFamily::add(const std::string& key, PairedComparison c) {
  if (adjusted_)
    throw std::invalid_argument("PairedFamily: '" + key + "' added after the family was adjusted");
  if (std::find(keys_.begin(), keys_.end(), key) != keys_.end())
    throw std::invalid_argument("PairedFamily: '" + key + "' added twice");
  keys_.push_back(key), items_.push_back(c);
}

void PairedFamily::adjust() {
  std::vector<double> p;
  for (const auto& c : items_) p.push_back(c.p);
  const std::vector<double> q = holm_adjust(p);
  for (std::size_t i = 0; i < items_.size(); ++i) items_[i].adjusted_p = q[i];
  adjusted_ = true;
}

const PairedComparison& PairedFamily::at(const std::string& key) const {
  if (!adjusted_) throw std::logic_error("PairedFamily: '" + key + "' read before the family was adjusted");
  const auto it = std::find(keys_.begin(), keys_.end(), key);
  if (it == keys_.end()) throw std::out_of_range("PairedFamily: no comparison '" + key + "'");
  return items_[static_cast<std::size_t>(it - keys_.begin())];
}

std::size_t PairedFamily::significant() const {
  return static_cast<std::size_t>(
      std::count_if(items_.begin(), items_.end(), [](const auto& c) { return c.lower() || c.higher(); }));
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
