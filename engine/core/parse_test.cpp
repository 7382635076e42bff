// Unit tests of the one number parser (core/parse.hpp): integers with overflow, sign and trailing-junk
// checks, reals with subnormals accepted and inf/nan/overflow refused, id ranges checked before they are
// expanded, and whole files read in one pass.
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include "core/config.hpp"
#include "core/parse.hpp"

using namespace keel::core;

namespace {

std::string int_error(std::string_view t, std::int64_t lo = 0, std::int64_t hi = 2147483646) {
  std::int64_t v = -7;
  auto why = parse_integer(t, lo, hi, v, "a pose id");
  if (!why.empty()) CHECK(v == -7);  // untouched on failure
  return why;
}

std::string real_error(std::string_view t) {
  double v = -7.0;
  auto why = parse_real(t, v);
  if (!why.empty()) CHECK(v == -7.0);
  return why;
}

}  // namespace

TEST_CASE("parse_integer: sign, overflow, trailing junk, bounds") {
  std::int64_t v = 0;
  CHECK(parse_integer("42", 0, 100, v).empty());
  CHECK(v == 42);
  CHECK(parse_integer("+7", 0, 100, v).empty());
  CHECK(v == 7);
  CHECK(parse_integer("-3", -5, 5, v).empty());
  CHECK(v == -3);
  CHECK(parse_integer("9223372036854775807", 0, std::numeric_limits<std::int64_t>::max(), v).empty());
  // 2^32 + 1 and 99999999999 wrapped through a 32-bit sscanf; here they are out of range.
  CHECK(int_error("4294967297") == "'4294967297' is too large: expected a pose id in 0 … 2147483646");
  CHECK(int_error("4294967296") == "'4294967296' is too large: expected a pose id in 0 … 2147483646");
  CHECK(int_error("99999999999") == "'99999999999' is too large: expected a pose id in 0 … 2147483646");
  CHECK(int_error("99999999999999999999999") ==
        "'99999999999999999999999' is too large: expected a pose id in 0 … 2147483646");
  CHECK(int_error("-1") == "'-1' is negative: expected a pose id in 0 … 2147483646");
  CHECK(int_error("-9", -5, 5) == "'-9' is too small: expected a pose id in -5 … 5");
  CHECK(int_error("2", 3, 5) == "'2' is too small: expected a pose id in 3 … 5");
  CHECK(int_error("-99999999999999999999", -5, 5) ==
        "'-99999999999999999999' is too small: expected a pose id in -5 … 5");
  for (const char* junk : {"1x", "1O", " 1", "1 ", "", "+", "-", "+-1", "++1", "0x10", "1e3", "1.0", "٣"}) {
    INFO(junk);
    CHECK(int_error(junk).find("is not a pose id (expected a decimal integer in 0 … 2147483646)") !=
          std::string::npos);
  }
  CHECK_THROWS_WITH_AS((void)to_integer("12a", 0, 9, "--threads"),
                       "--threads: '12a' is not an integer (expected a decimal integer in 0 … 9)",
                       std::invalid_argument);
}

TEST_CASE("parse_real: subnormals accepted; inf, nan, overflow, junk refused") {
  double v = 0;
  CHECK(parse_real("1e-310", v).empty());
  CHECK(v == 1e-310);
  CHECK(std::fpclassify(v) == FP_SUBNORMAL);
  CHECK(parse_real("4.9406564584124654e-324", v).empty());
  CHECK(v == std::numeric_limits<double>::denorm_min());
  CHECK(parse_real("-1e-400", v).empty());  // below the smallest subnormal: the correctly rounded value, -0
  CHECK(v == 0.0);
  CHECK(std::signbit(v));
  CHECK(parse_real("1.7976931348623157e308", v).empty());
  CHECK(v == std::numeric_limits<double>::max());
  CHECK(parse_real("+.5", v).empty());
  CHECK(v == 0.5);
  CHECK(parse_real("-2.5E-3", v).empty());
  CHECK(v == -2.5e-3);
  CHECK(real_error("1e309") ==
        "'1e309' is out of the range of a double (a finite real of magnitude at most 1.797e308)");
  CHECK(real_error("-1e999").find("out of the range of a double") != std::string::npos);
  for (const char* t : {"nan", "NaN", "-nan", "inf", "-inf", "+infinity"}) {
    INFO(t);
    CHECK(real_error(t).find("is not a finite number (NaN and infinities are refused)") != std::string::npos);
  }
  for (const char* t : {"1O", "0x1p3", "1,5", " 1", "1 ", "", "e5", "1e", "--1", "+-1", "1.2.3"}) {
    INFO(t);
    CHECK(real_error(t).find("is not a number (expected a finite decimal real") != std::string::npos);
  }
  CHECK(real_error(std::string_view("\x01\x7f", 2)) ==
        "'\\x01\\x7f' is not a number (expected a finite decimal real such as -2.5e-3)");
}

TEST_CASE("id ranges and lists are checked against the limit before they are expanded") {
  IdRange r;
  CHECK(parse_id_range("3-7", 10, r).empty());
  CHECK((r.first == 3 && r.last == 7 && r.count() == 5));
  CHECK(parse_id_range("4", 10, r).empty());
  CHECK((r.first == 4 && r.last == 4));
  CHECK(parse_id_range("0-2147483647", 10, r, "a pose id") ==
        "range '0-2147483647': '2147483647' is too large: expected a pose id in 0 … 9");
  CHECK(parse_id_range("7-3", 10, r) == "range '7-3': the end 3 is below the start 7");
  CHECK(parse_id_range("-3", 10, r).find("'-3' is") != std::string::npos);
  CHECK(parse_id_range("1-", 10, r).find("is not an id") != std::string::npos);
  CHECK(parse_id_range("0", 0, r).find("none exists") != std::string::npos);
  const auto ids = parse_id_list("0,2-4,9", 10, 10, "--poses");
  CHECK(ids == std::vector<int>{0, 2, 3, 4, 9});
  CHECK_THROWS_WITH_AS(
      (void)parse_id_list("0-9,0-9", 10, 10, "--poses"),
      "--poses: '0-9,0-9' names more than 10 ids (the list is checked before it is expanded)",
      std::invalid_argument);
  CHECK_THROWS_WITH_AS(
      (void)parse_id_list("0-2147483647", 100, 100, "--poses", "a pose id"),
      "--poses: range '0-2147483647': '2147483647' is too large: expected a pose id in 0 … 99",
      std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)parse_id_list("1,,2", 10, 10, "--poses"),
                       "--poses: '' is not an id (expected a decimal integer in 0 … 9)",
                       std::invalid_argument);
}

TEST_CASE("read_whole_file: one pass (a FIFO works); a directory or a missing file says why") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / fmt::format("keel_core_parse_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path fifo = dir / "pipe";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  std::thread writer([&] { std::ofstream(fifo) << "hello\nworld\n"; });
  std::string text;
  CHECK(read_whole_file(fifo, text).empty());
  writer.join();
  CHECK(text == "hello\nworld\n");
  CHECK(read_whole_file(dir, text) == "cannot read: is a directory, not a file");
  CHECK(read_whole_file(dir / "missing", text) == "cannot open file (No such file or directory)");
  CHECK_THROWS_WITH_AS((void)read_text_file(dir),
                       fmt::format("{}: cannot read: is a directory, not a file", dir.string()).c_str(),
                       std::invalid_argument);
  fs::remove_all(dir);
}

TEST_CASE("load_toml: a directory or a missing file is 'file: reason', not a stream error") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / fmt::format("keel_core_toml_dir_{}", ::getpid());
  fs::create_directories(dir);
  CHECK_THROWS_WITH_AS((void)load_toml(dir),
                       fmt::format("{}: cannot read: is a directory, not a file", dir.string()).c_str(),
                       ConfigError);
  CHECK_THROWS_WITH_AS(
      (void)load_toml(dir / "missing.toml"),
      fmt::format("{}: cannot open file (No such file or directory)", (dir / "missing.toml").string())
          .c_str(),
      ConfigError);
  fs::remove_all(dir);
}
