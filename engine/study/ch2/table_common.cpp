#include "study/ch2/table_common.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "core/parallel.hpp"
#include "core/statistics.hpp"
#include "core/timing.hpp"

namespace keel::study::ch2 {

std::size_t claimed_method(const std::vector<StudyMethod>& methods, const core::ConfigTable& claims,
                           const std::string& name, std::optional<merge::MergeMethodKind> kind) {
  std::size_t k = 0;
  try {
    k = method_index(methods, name, "[params.claims]");
  } catch (const std::invalid_argument& e) {
    throw core::ConfigError(fmt::format("{}: {}", claims.file(), e.what()));
  }
  if (kind && methods[k].method.kind() != *kind)
    throw core::ConfigError(fmt::format("{}: [params.claims] names '{}' where a {} method is needed",
                                        claims.file(), name, merge::to_string(*kind)));
  return k;
}

std::vector<std::size_t> claimed_methods(const std::vector<StudyMethod>& methods,
                                         const core::ConfigTable& claims,
                                         const std::vector<std::string>& names,
                                         std::optional<merge::MergeMethodKind> kind) {
  std::vector<std::size_t> out;
  for (const auto& n : names) out.push_back(claimed_method(methods, claims, n, kind));
  return out;
}

std::string tag_of(double v) {
  std::string s = fmt::format("{:g}", v);
  std::replace(s.begin(), s.end(), '.', '_');
  return s;
}

std::string join(const std::vector<double>& v) {
  std::string out;
  for (double x : v) out += fmt::format("{}{:.4f}", out.empty() ? "" : ", ", x);
  return out;
}

}  // namespace keel::study::ch2
