#include "repro/grading.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

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
