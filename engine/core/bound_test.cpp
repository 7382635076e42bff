// Outward rounding of bounds (core/bound.hpp): printed lower bounds at or below the value, upper bounds at or
// above it, and the one-ulp steps of round_down / round_up.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/bound.hpp"
#include "core/random.hpp"

using keel::core::Bound;
using keel::core::format_lower;
using keel::core::format_upper;
using keel::core::round_down;
using keel::core::round_up;

TEST_CASE("format_lower / format_upper: the printed decimal is on the bound's side of the value") {
  // 638.624599974 printed to nearest at 7 digits is 638.6246, above the value.
  CHECK(format_lower(638.624599974, 7) == "638.6245");
  CHECK(format_upper(638.624599974, 7) == "638.6246");
  CHECK(format_lower(-638.624599974, 7) == "-638.6246");
  CHECK(format_upper(-638.624599974, 7) == "-638.6245");
  // 0.1 is stored as 0.1000000000000000055…: its lower bound at 3 digits is 0.1, its upper bound 0.101.
  CHECK(format_lower(0.1, 3) == "0.1");
  CHECK(format_upper(0.1, 3) == "0.101");
  // 0.3 is stored as 0.2999999999999999888…: the other way round.
  CHECK(format_lower(0.3, 3) == "0.299");
  CHECK(format_upper(0.3, 3) == "0.3");
  // Exact values print as they are; a carry moves the exponent.
  CHECK(format_lower(2.5, 3) == "2.5");
  CHECK(format_upper(2.5, 3) == "2.5");
  CHECK(format_upper(9.9999, 3) == "10");
  CHECK(format_upper(-9.9999, 3) == "-9.99");
  CHECK(format_lower(-9.9999, 3) == "-10");
  CHECK(format_upper(9.99951e-7, 3) == "1e-06");
  CHECK(format_lower(9.99951e-7, 3) == "9.99e-07");
  CHECK(format_lower(0.0, 10) == "0");
  CHECK(format_lower(std::numeric_limits<double>::infinity(), 5) == "inf");
  CHECK(format_upper(-std::numeric_limits<double>::infinity(), 5) == "-inf");
  CHECK_THROWS_AS((void)format_lower(1.0, 0), std::invalid_argument);
  CHECK_THROWS_AS((void)format_upper(1.0, 16), std::invalid_argument);
}

TEST_CASE("format_lower / format_upper: bracket the value on random doubles and are the closest decimals") {
  // keel's generator (std's distributions are implementation-defined).
  keel::core::Rng rng(20190101);
  const auto mantissa = [](keel::core::Rng& r) { return r.uniform(-1.0, 1.0); };
  const auto exponent = [](keel::core::Rng& r) {
    return std::min(40, static_cast<int>(81 * r.uniform()) - 40);
  };
  const auto digits = [](keel::core::Rng& r) { return std::min(15, 1 + static_cast<int>(15 * r.uniform())); };
  for (int k = 0; k < 20000; ++k) {
    double x = std::ldexp(mantissa(rng), exponent(rng));
    if (k % 7 == 0) x = std::round(x * 1e4) / 1e4;  // values near short decimals
    const int p = digits(rng);
    const std::string lo = format_lower(x, p), hi = format_upper(x, p);
    // strtod rounds to nearest and is monotone, and x is a double: a decimal ≤ x converts to ≤ x.
    const double l = std::strtod(lo.c_str(), nullptr), h = std::strtod(hi.c_str(), nullptr);
    INFO("x = " << x << ", p = " << p << ", lower " << lo << ", upper " << hi);
    CHECK(l <= x);
    CHECK(h >= x);
    // The directed decimals are the two neighbours of x at p digits: the nearest one is one of them.
    char nearest[64];
    std::snprintf(nearest, sizeof nearest, "%.*g", p, x);
    CHECK((lo == nearest || hi == nearest));
  }
}

TEST_CASE("round_down / round_up: one ulp outward, non-finite unchanged, and the upward gap") {
  CHECK(round_down(1.0) < 1.0);
  CHECK(round_up(1.0) > 1.0);
  CHECK(round_up(1.0) == std::nextafter(1.0, 2.0));
  CHECK(round_down(0.0) < 0.0);
  CHECK(std::isinf(round_down(-std::numeric_limits<double>::infinity())));
  CHECK(std::isinf(round_up(std::numeric_limits<double>::infinity())));
  const Bound b{638.6, 638.7};
  CHECK(b.relative_gap_up() >= b.relative_gap());
  CHECK(b.relative_gap_up() <= b.relative_gap() * (1.0 + 1e-15));
  CHECK(Bound{2.0, 1.0}.relative_gap_up() == 0.0);
  CHECK(std::isinf(Bound{}.relative_gap_up()));
}
