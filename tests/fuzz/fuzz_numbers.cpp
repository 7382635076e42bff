// libFuzzer target: the one number parser of engine/core (core/parse.hpp) on arbitrary bytes — integers,
// reals, id lists and ranges (as `keel marginals --poses` reads them), pose pairs 'i:j,k:l' (as --pairs
// splits them) and CSV tables of numbers (survey files). A parser may only succeed or throw
// std::invalid_argument (the parse_* forms return a reason instead); what it accepts must hold its promise:
// integers inside their bounds and read back from their decimal text, reals finite and read back from
// "%.17g", id lists inside the limit and no longer than the count they were checked against, CSV tables
// rectangular and finite. A violation aborts.
#include <fmt/format.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/parse.hpp"

using namespace keel::core;

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  fmt::print(stderr, "fuzz_numbers: {}: {}\n", what, detail);
  std::abort();
}

template <class F>
void expect_invalid_argument_only(const char* what, F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    if (std::string_view(e.what()).empty()) fail(what, "an empty message");
  } catch (const std::exception& e) {
    fail(what, fmt::format("unexpected exception: {}", e.what()));
  } catch (...) {
    fail(what, "unexpected non-std exception");
  }
}

void check_integer(std::string_view t, std::int64_t lo, std::int64_t hi) {
  std::int64_t v = 0;
  const std::string why = parse_integer(t, lo, hi, v, "an id");
  if (!why.empty()) {
    if (why.find('\'') == std::string::npos) fail("parse_integer", "the message does not quote the token");
    return;
  }
  if (v < lo || v > hi) fail("parse_integer", fmt::format("{} outside {} … {}", v, lo, hi));
  std::int64_t back = 0;
  if (!parse_integer(std::to_string(v), lo, hi, back).empty() || back != v)
    fail("parse_integer", fmt::format("{} does not read back", v));
}

void check_real(std::string_view t) {
  double v = 0.0;
  if (!parse_real(t, v).empty()) return;
  if (!std::isfinite(v))
    fail("parse_real", fmt::format("accepted a non-finite value from {}", quote_token(t)));
  double back = 0.0;
  const std::string text = fmt::format("{:.17g}", v);
  if (!parse_real(text, back).empty() || back != v)
    fail("parse_real", fmt::format("{} does not read back", text));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  check_integer(text, 0, 2147483646);
  check_integer(text, -5, 5);
  check_integer(text, INT64_MIN, INT64_MAX);
  check_real(text);
  for (const std::string_view field : split_fields(text, ',')) {
    check_real(field);
    check_integer(field, 0, 1000);
  }
  // --poses: ids below 50, at most 60 of them.
  expect_invalid_argument_only("parse_id_list", [&] {
    const auto ids = parse_id_list(text, 50, 60, "--poses", "a pose id");
    if (ids.size() > 60) fail("parse_id_list", fmt::format("{} ids beyond the count 60", ids.size()));
    for (int id : ids)
      if (id < 0 || id >= 50) fail("parse_id_list", fmt::format("id {} outside 0 … 49", id));
  });
  // --pairs: 'i:j' items, each side a pose id below 50 (engine/cli/marginals.cpp splits them the same way).
  for (const std::string_view item : split_fields(text, ',')) {
    const auto colon = item.find(':');
    if (colon == std::string_view::npos) continue;
    check_integer(item.substr(0, colon), 0, 49);
    check_integer(item.substr(colon + 1), 0, 49);
  }
  // Survey CSV: at least 3 columns.
  expect_invalid_argument_only("parse_numeric_csv", [&] {
    const NumericCsv t = parse_numeric_csv(text, "fuzz.csv", 3, "x, y and a feature");
    if (t.values.size() != t.rows() * t.columns) fail("parse_numeric_csv", "not rectangular");
    if (t.rows() > 0 && t.columns < 3) fail("parse_numeric_csv", "fewer columns than asked");
    for (double v : t.values)
      if (!std::isfinite(v)) fail("parse_numeric_csv", "a non-finite value");
  });
  return 0;
}
