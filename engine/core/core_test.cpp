// Unit tests of engine/core (the foundation) (they include the headers; no module import).
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/fields.hpp"
#include "core/names.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "core/random.hpp"
#include "core/statistics.hpp"
#include "kit/scratch.hpp"

using namespace keel::core;
namespace fs = std::filesystem;

namespace {

using keel::testkit::Scratch;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("random streams: deterministic, independent, standard normal") {
  Rng a = Rng::stream(42, 3), b = Rng::stream(42, 3), c = Rng::stream(42, 4);
  for (int i = 0; i < 100; ++i) CHECK(a.next() == b.next());
  CHECK(Rng::stream(42, 3).next() != c.next());
  Rng r = Rng::stream(1, 0);
  const int n = 400000;
  double m = 0, v = 0, k = 0;
  for (int i = 0; i < n; ++i) {
    const double x = r.normal();
    m += x;
    v += x * x;
    k += x * x * x * x;
  }
  m /= n;
  v /= n;
  k /= n;
  CHECK(std::fabs(m) < 0.01);
  CHECK(std::fabs(v - 1.0) < 0.01);
  CHECK(std::fabs(k - 3.0) < 0.05);  // fourth moment of N(0,1)
  double u = 0;
  for (int i = 0; i < n; ++i) u += r.uniform();
  CHECK(std::fabs(u / n - 0.5) < 0.005);
}

TEST_CASE("parallel_for: each index once, results independent of threads, exceptions propagate") {
  const std::size_t n = 10007;
  auto run = [&](unsigned threads) {
    std::vector<double> out(n);
    parallel_for(n, [&](std::size_t i) { out[i] = Rng::stream(9, i).normal(); }, threads);
    return out;
  };
  const auto one = run(1), two = run(2), many = run(7);
  CHECK(one == two);
  CHECK(one == many);
  std::atomic<int> count{0};
  parallel_for(n, [&](std::size_t) { count++; }, 3);
  CHECK(count == static_cast<int>(n));
  CHECK_THROWS_WITH(parallel_for(
                        100,
                        [](std::size_t i) {
                          if (i == 57) throw std::runtime_error("trial 57");
                        },
                        2),
                    "trial 57");
}

namespace {
enum class Colour { light_red, dark_blue };
constexpr NameTable<Colour, 2> kColourNames{"test::Colour",
                                            {{
                                                {Colour::light_red, "light_red"},
                                                {Colour::dark_blue, "dark_blue"},
                                            }}};
Colour colour_from_string(std::string_view s) { return kColourNames.parse(s); }
}  // namespace

TEST_CASE("name tables: round trip, exact matches, errors naming the type and every valid name") {
  for (const auto& [value, name] : kColourNames.names) {
    CHECK(kColourNames.name(value) == name);
    CHECK(colour_from_string(name) == value);
  }
  CHECK(error_of([] { (void)colour_from_string("Light_Red"); }) ==
        "unknown test::Colour 'Light_Red' (valid: light_red, dark_blue)");
  CHECK(error_of([] { (void)colour_from_string(""); }) ==
        "unknown test::Colour '' (valid: light_red, dark_blue)");
  CHECK(error_of([] { (void)kColourNames.name(static_cast<Colour>(7)); }) ==
        "test::Colour: value 7 has no name");
  CHECK_THROWS_AS((void)colour_from_string("dark"), std::invalid_argument);

  // A config reader turns the parse error into a ConfigError located at file, table, key and line.
  Scratch s("names");
  const auto file = s.write("colours.toml", "good = \"dark_blue\"\n[style]\nbad = \"green\"\n");
  const ConfigTable root = load_toml(file);
  CHECK(root.parse("good", colour_from_string) == Colour::dark_blue);
  CHECK(root.parse_or("absent", colour_from_string, Colour::light_red) == Colour::light_red);
  const std::string e = error_of([&] { (void)root.table("style").parse("bad", colour_from_string); });
  CHECK(e == fmt::format(
                 "{}: [style] key 'bad' (line 3): unknown test::Colour 'green' (valid: light_red, dark_blue)",
                 file.string()));
}

TEST_CASE("durations") {
  CHECK(format_duration(-1.0) == "0.0s");
  CHECK(format_duration(12.34) == "12.3s");
  CHECK(format_duration(245.0) == "4m05s");
  CHECK(format_duration(3725.0) == "1h02m");
}

TEST_CASE("Wilson score interval: Newcombe's (1998) worked values, edges, and coverage") {
  // Newcombe, "Two-sided confidence intervals for the single proportion", Stat. Med. 17 (1998), Table I.
  const struct {
    double x, n, low, high;
  } cases[] = {
      {81, 263, 0.2553, 0.3662}, {15, 148, 0.0624, 0.1605}, {0, 20, 0.0, 0.1611}, {1, 29, 0.0061, 0.1718}};
  for (const auto& c : cases) {
    const Proportion p = wilson_interval(c.x, c.n);
    CHECK(p.rate == doctest::Approx(c.x / c.n));
    CHECK(std::abs(p.low - c.low) <= 5e-5);  // the table prints four decimals
    CHECK(std::abs(p.high - c.high) <= 5e-5);
  }
  const Proportion all = wilson_interval(300, 300);
  CHECK(all.high == 1.0);
  CHECK(all.low > 0.98);
  CHECK(all.low < 1.0);
  const Proportion none = wilson_interval(0, 0);
  CHECK(none.low == 0.0);
  CHECK(none.high == 1.0);
  // Coverage by simulation: for p = 0.3 and n = 50, the 95 % interval covers p in about 95 % of samples.
  Rng rng(7);
  int covered = 0;
  const int samples = 4000;
  for (int k = 0; k < samples; ++k) {
    int x = 0;
    for (int i = 0; i < 50; ++i) x += rng.uniform() < 0.3;
    const Proportion p = wilson_interval(x, 50);
    covered += p.low <= 0.3 && 0.3 <= p.high;
  }
  CHECK(covered / double(samples) > 0.93);
  CHECK(covered / double(samples) < 0.97);
}

TEST_CASE("spearman: rank correlation against a brute-force definition, with ties") {
  using keel::core::spearman;
  // Ranks by counting (1 + values below + half the other equal values), then Pearson with explicit means.
  const auto brute = [](const std::vector<double>& a, const std::vector<double>& b) {
    const auto rank = [](const std::vector<double>& v) {
      std::vector<double> r;
      for (double x : v) {
        double below = 0, equal = 0;
        for (double y : v) below += y < x, equal += y == x;
        r.push_back(1 + below + 0.5 * (equal - 1));
      }
      return r;
    };
    const std::vector<double> ra = rank(a), rb = rank(b);
    double ma = 0, mb = 0;
    for (std::size_t i = 0; i < ra.size(); ++i) ma += ra[i], mb += rb[i];
    ma /= static_cast<double>(ra.size()), mb /= static_cast<double>(rb.size());
    double sab = 0, saa = 0, sbb = 0;
    for (std::size_t i = 0; i < ra.size(); ++i)
      sab += (ra[i] - ma) * (rb[i] - mb), saa += (ra[i] - ma) * (ra[i] - ma),
          sbb += (rb[i] - mb) * (rb[i] - mb);
    return sab / std::sqrt(saa * sbb);
  };
  keel::core::Rng rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> a, b;
    for (int i = 0; i < 40; ++i) {
      a.push_back(std::floor(rng.uniform(0.0, 8.0)));  // many ties
      b.push_back(a.back() * rng.uniform(0.0, 1.0) + std::floor(rng.uniform(0.0, 3.0)));
    }
    CHECK(spearman(a, b) == doctest::Approx(brute(a, b)).epsilon(1e-12));
  }
  // Invariant to monotone maps: a strictly increasing map gives 1, a decreasing one −1.
  std::vector<double> x, up, down;
  for (int i = 0; i < 30; ++i) x.push_back(rng.uniform(-2.0, 2.0));
  for (double v : x) up.push_back(std::exp(3 * v)), down.push_back(-v * v * v);
  CHECK(spearman(x, up) == doctest::Approx(1.0));
  CHECK(spearman(x, down) == doctest::Approx(-1.0));
  CHECK(spearman(x, std::vector<double>(x.size(), 2.0)) == 0.0);  // a constant sample
  CHECK(spearman({1.0}, {2.0}) == 0.0);
}

namespace {
struct Listed {
  int count = 0;
  std::vector<double> values;
  std::string label_with_underscores;
  KEEL_FIELDS(count, values,
              label_with_underscores)  // a list broken over lines is still one name per member
};
}  // namespace

TEST_CASE("KEEL_FIELDS lists the members once: the tie and the names agree, in order") {
  constexpr auto names = keel::core::field_names<Listed>();
  static_assert(names.size() == 3);
  CHECK(names[0] == "count");
  CHECK(names[1] == "values");
  CHECK(names[2] == "label_with_underscores");
  Listed x;
  std::get<0>(x.fields()) = 4;  // the tie refers to the members
  CHECK(x.count == 4);
  std::vector<std::string> seen;
  keel::core::for_each_field(x, [&](std::string_view name, auto& member) {
    seen.emplace_back(name);
    if constexpr (std::is_same_v<std::decay_t<decltype(member)>, std::string>) member = "set by name";
  });
  CHECK(seen == std::vector<std::string>{"count", "values", "label_with_underscores"});
  CHECK(x.label_with_underscores == "set by name");
  const Listed& c = x;
  int n = 0;
  keel::core::for_each_field(c, [&](std::string_view, const auto&) { ++n; });
  CHECK(n == 3);
}
