// One bound and one status for every search that can stop early and every certificate of global optimality
// (docs/DESIGN.md "Bounds and status"): the maximum-clique search of pcm, the θ certificate of align, the
// Sparse-BSOS relaxations and the whole-data-set certificate of sos.
//
// A Bound brackets the optimum of the problem: lower ≤ optimum ≤ upper. For a minimization the upper end is
// attained (the cost of the answer returned) and the lower end is proven (a relaxation, a dual certificate);
// for a maximization (a clique's size) the lower end is attained and the upper end proven. One gap for all:
//
//     relative_gap = (upper − lower) / max(1, |upper|),    0 when lower ≥ upper, +inf when an end is not
//     finite,
//
// so below a magnitude of one (a χ² of less than one σ², a clique of one vertex) the gap is absolute.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>

namespace keel::core {

// How a search for a global optimum ended.
enum class SearchStatus {
  optimal,     // proven: the bound's gap is within the method's tolerance (for a clique: zero)
  unproven,    // finished without a proof (a heuristic, or a certificate whose gap did not close)
  node_limit,  // a branch and bound stopped at its node limit: the best answer so far and a valid bound
  time_limit,  // a branch and bound stopped at its time limit: likewise
};
std::string_view to_string(SearchStatus s);
SearchStatus search_status_from_string(std::string_view s);  // throws std::invalid_argument

struct Bound {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  // (upper − lower) / max(1, |upper|), clamped at 0 below; +inf when either end is not finite.
  [[nodiscard]] double relative_gap() const { return relative_gap_of(lower, upper); }
  [[nodiscard]] static double relative_gap_of(double lower, double upper) {
    if (!std::isfinite(lower) || !std::isfinite(upper)) return std::numeric_limits<double>::infinity();
    if (lower >= upper) return 0.0;
    return (upper - lower) / std::max(1.0, std::abs(upper));
  }
  // The same gap rounded upward (each operation's result moved one ulp toward +∞, round_up below): what a
  // certificate prints and records, never below the gap of the exact ends.
  [[nodiscard]] double relative_gap_up() const { return relative_gap_up_of(lower, upper); }
  [[nodiscard]] static double relative_gap_up_of(double lower, double upper);
};

// Outward rounding by one-ulp steps. A double operation rounded to nearest errs by at most half an ulp of its
// result, so moving the result one ulp toward −∞ (round_down) after each operation of a lower bound, or
// toward +∞ (round_up) after each operation of an upper bound, keeps the bound on its side of the exact value
// whatever the rounding mode the compiler assumed. Non-finite values are returned as they are.
[[nodiscard]] inline double round_down(double x) {
  return std::isfinite(x) ? std::nextafter(x, -std::numeric_limits<double>::infinity()) : x;
}
[[nodiscard]] inline double round_up(double x) {
  return std::isfinite(x) ? std::nextafter(x, std::numeric_limits<double>::infinity()) : x;
}

// x with `significant` significant digits in the style of printf's %.Ng (1 ≤ N ≤ 15), the decimal rounded
// toward −∞ (format_lower) or toward +∞ (format_upper) instead of to nearest: a printed lower bound is never
// above the value, a printed upper bound never below it ("F* ≥ 638.6245" for 638.624599974, not 638.6246).
// The decision uses x's exact decimal expansion; "inf", "-inf" and "nan" as they are. Throws
// std::invalid_argument for N outside [1, 15].
[[nodiscard]] std::string format_lower(double x, int significant);
[[nodiscard]] std::string format_upper(double x, int significant);

}  // namespace keel::core
