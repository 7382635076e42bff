#include "core/bound.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "core/names.hpp"

namespace keel::core {

namespace {
constexpr NameTable<SearchStatus, 4> kSearchStatusNames{"core::SearchStatus",
                                                        {{
                                                            {SearchStatus::optimal, "optimal"},
                                                            {SearchStatus::unproven, "unproven"},
                                                            {SearchStatus::node_limit, "node_limit"},
                                                            {SearchStatus::time_limit, "time_limit"},
                                                        }}};
}  // namespace

std::string_view to_string(SearchStatus s) { return kSearchStatusNames.name(s); }
SearchStatus search_status_from_string(std::string_view s) { return kSearchStatusNames.parse(s); }

double Bound::relative_gap_up_of(double lower, double upper) {
  if (!std::isfinite(lower) || !std::isfinite(upper)) return std::numeric_limits<double>::infinity();
  if (lower >= upper) return 0.0;
  return round_up(round_up(upper - lower) / std::max(1.0, std::abs(upper)));
}

namespace {

// x's significant digits rounded to `significant` of them, toward +∞ (up) or −∞, then printed as %.Ng.
std::string format_directed(double x, int significant, bool up) {
  if (significant < 1 || significant > 15)
    throw std::invalid_argument(fmt::format("core::format_{}: significant digits must be in [1, 15] (got {})",
                                            up ? "upper" : "lower", significant));
  if (!std::isfinite(x) || x == 0.0) return fmt::format("{:.{}g}", x, significant);
  // The exact decimal expansion: a double has at most 767 significant decimal digits, and glibc's printf
  // prints every digit exactly at any precision.
  char buf[1024];
  std::snprintf(buf, sizeof buf, "%.*e", 800, x);
  const bool negative = buf[0] == '-';
  const char* s = buf + (negative ? 1 : 0);
  std::string digits(1, s[0]);
  const char* p = s + 2;  // after "d."
  while (*p != 'e') digits += *p++;
  int exponent = std::atoi(p + 1);
  std::string kept = digits.substr(0, static_cast<std::size_t>(significant));
  bool rest = false;
  for (std::size_t k = static_cast<std::size_t>(significant); k < digits.size(); ++k)
    rest |= digits[k] != '0';
  // Truncation moves the magnitude toward zero: right for an upper bound of a negative x and a lower bound of
  // a positive one; otherwise the last kept digit goes up by one when anything was cut.
  if (rest && up != negative) {
    int k = significant - 1;
    while (k >= 0 && kept[static_cast<std::size_t>(k)] == '9') kept[static_cast<std::size_t>(k--)] = '0';
    if (k >= 0) {
      ++kept[static_cast<std::size_t>(k)];
    } else {
      kept.insert(kept.begin(), '1');
      kept.pop_back();
      ++exponent;
    }
  }
  const std::string decimal =
      fmt::format("{}{}.{}e{}", negative ? "-" : "", kept[0], kept.substr(1), exponent);
  // A decimal of at most 15 significant digits survives the round trip through the nearest double, so %.Ng
  // of that double prints exactly these digits.
  return fmt::format("{:.{}g}", std::strtod(decimal.c_str(), nullptr), significant);
}

}  // namespace

std::string format_lower(double x, int significant) { return format_directed(x, significant, false); }
std::string format_upper(double x, int significant) { return format_directed(x, significant, true); }

}  // namespace keel::core
