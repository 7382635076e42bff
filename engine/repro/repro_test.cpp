// Unit tests of engine/repro: experiment configs, tolerances, results, baselines (they include the headers;
// no module import).
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "repro/baseline.hpp"
#include "repro/experiment_config.hpp"
#include "repro/results.hpp"

using namespace keel::repro;
namespace fs = std::filesystem;

namespace {

// A scratch experiment folder experiments/<id>/experiment.toml under a fresh temporary root.
struct Scratch {
  fs::path root;
  explicit Scratch(const std::string& tag) {
    root = fs::temp_directory_path() / fmt::format("keel_repro_test_{}_{}", tag, ::getpid());
    fs::remove_all(root);
    fs::create_directories(root);
  }
  ~Scratch() { fs::remove_all(root); }
  fs::path write(const std::string& rel, const std::string& text) const {
    const fs::path p = root / rel;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p;
  }
};

const char* kGood = R"(id = "demo"
title = "Demo"
reproduces = "Fig. 0"
seed = 7
[params]
steps = 10
sigma = 0.5
name = "x"
[profiles.quick]
trials = 100
[profiles.full]
trials = 10000
[tolerance]
"a.b" = { abs = 0.01 }
default = { rel = 1e-6 }
)";

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("config: profile overlay, typed reads, unknown keys") {
  Scratch s("cfg");
  const auto file = s.write("demo/experiment.toml", kGood);
  auto c = ExperimentConfig::load(file, "quick");
  CHECK(c.id == "demo");
  CHECK(c.seed == 7);
  CHECK(c.params.integer("steps") == 10);
  CHECK(c.params.number("steps") == 10.0);  // integers widen to numbers
  CHECK(c.params.number("sigma") == 0.5);
  CHECK(c.params.integer("trials") == 100);
  // 'name' was never read: finish() must name it, with file and table.
  const std::string e = error_of([&] { c.params.finish(); });
  CHECK(e.find("experiment.toml") != std::string::npos);
  CHECK(e.find("[params]") != std::string::npos);
  CHECK(e.find("'name'") != std::string::npos);
  CHECK(e.find("unknown key") != std::string::npos);
  CHECK(ExperimentConfig::load(file, "full").params.integer("trials") == 10000);
  CHECK(c.tolerance_for("a.b")->abs == 0.01);
  CHECK(c.tolerance_for("other")->rel == 1e-6);
}

TEST_CASE("config: wrong type names file, table, key and line") {
  Scratch s("type");
  const auto file = s.write("demo/experiment.toml", kGood);
  auto c = ExperimentConfig::load(file, "quick");
  const std::string e = error_of([&] { (void)c.params.integer("sigma"); });
  CHECK(e.find("[params] key 'sigma'") != std::string::npos);
  CHECK(e.find("expected an integer, got float") != std::string::npos);
  CHECK(e.find("line 7") != std::string::npos);
  const std::string e2 = error_of([&] { (void)c.params.integer("trials_missing"); });
  CHECK(e2.find("'trials_missing': missing") != std::string::npos);
  // A key set by the profile is reported in the profile's table.
  const std::string e3 = error_of([&] { (void)c.params.string("trials"); });
  CHECK(e3.find("[profiles.quick] key 'trials'") != std::string::npos);
}

TEST_CASE("config: bad files give clear errors") {
  Scratch s("bad");
  std::string text = kGood;
  CHECK(error_of([&] {
          ExperimentConfig::load(s.write("demo/experiment.toml", text), "nope");
        }).find("no profile 'nope'") != std::string::npos);
  CHECK(error_of([&] {
          ExperimentConfig::load(s.write("other/experiment.toml", text), "quick");
        }).find("must equal the experiment folder name 'other'") != std::string::npos);
  CHECK(error_of([&] {
          ExperimentConfig::load(s.write("demo/experiment.toml", fmt::format("colour = 3\n{}", text)),
                                 "quick");
        }).find("[top level] key 'colour'") != std::string::npos);
  CHECK(error_of([&] {
          ExperimentConfig::load(s.write("demo/experiment.toml", "id = \n"), "quick");
        }).find("TOML syntax error") != std::string::npos);
  CHECK(error_of([&] {
          ExperimentConfig::load(s.root / "missing/experiment.toml", "quick");
        }).find("cannot open") != std::string::npos);
  std::string bad_tol = kGood;
  bad_tol += "\"x\" = { absolute = 1 }\n";
  CHECK(error_of([&] {
          ExperimentConfig::load(s.write("demo/experiment.toml", bad_tol), "quick");
        }).find("'absolute'") != std::string::npos);
}

TEST_CASE("config: a key set by one profile only is a typo") {
  Scratch s("prof");
  std::string text = kGood;
  const auto pos = text.find("trials = 10000");
  text.replace(pos, 14, "trails = 10000");
  const std::string e =
      error_of([&] { ExperimentConfig::load(s.write("demo/experiment.toml", text), "quick"); });
  CHECK(e.find("[profiles.full] key 'trails'") != std::string::npos);
  CHECK(e.find("every profile must set the same keys") != std::string::npos);
}

TEST_CASE("level tags") {
  CHECK(level_tag(0.95) == "95");
  CHECK(level_tag(0.999) == "999");
  CHECK(level_tag(0.5) == "5");
  CHECK_THROWS(level_tag(1.0));
}

TEST_CASE("tolerance semantics") {
  Tolerance t;
  CHECK(t.accepts(1.0, 1.0));
  CHECK_FALSE(t.accepts(1.0, 1.0 + 1e-15));
  t.abs = 0.1;
  CHECK(t.accepts(1.05, 1.0));
  CHECK_FALSE(t.accepts(1.2, 1.0));
  Tolerance r;
  r.rel = 0.1;
  CHECK(r.accepts(105, 100));
  CHECK_FALSE(r.accepts(120, 100));
  CHECK(r.accepts(std::nan(""), std::nan("")));
  CHECK_FALSE(r.accepts(1.0, std::nan("")));
}

TEST_CASE("tolerance descriptions") {
  Tolerance t;
  CHECK(t.describe() == "exact");
  t.abs = 0.01;
  CHECK(t.describe() == "abs 0.01");
  t.rel = 1e-6;
  CHECK(t.describe() == "abs 0.01 or rel 1e-06");
  t.abs = -1;
  CHECK(t.describe() == "rel 1e-06");
}

TEST_CASE("rounding of result values") {
  CHECK(round_significant(0.1 + 0.2) == 0.3);
  CHECK(round_significant(123456.789, 4) == 123500.0);
  CHECK(round_significant(-0.000123456, 2) == -0.00012);
}

TEST_CASE("a variant takes its base's parameters and profiles (params_from)") {
  Scratch s("variant");
  s.write("experiments/demo/experiment.toml", kGood);
  const auto file = s.write("experiments/demo_b/experiment.toml", R"(id = "demo_b"
title = "Demo B"
reproduces = "Fig. 0"
params_from = "demo"
seed = 7
[params]
sigma = 2.5
extra = 1
)");
  const auto base = ExperimentConfig::load(s.root / "experiments/demo/experiment.toml", "full");
  const auto c = ExperimentConfig::load(file, "full");
  CHECK(c.params.number("sigma") == 2.5);      // overridden
  CHECK(c.params.integer("steps") == 10);      // inherited
  CHECK(c.params.integer("trials") == 10000);  // the base's full profile
  CHECK(c.params.integer("extra") == 1);       // its own
  CHECK(c.profiles == std::vector<std::string>{"full", "quick"});
  CHECK(c.hash != base.hash);
  // Its own [profiles] replace the base's.
  const auto own = ExperimentConfig::load(
      s.write("experiments/demo_c/experiment.toml",
              "id = \"demo_c\"\ntitle = \"C\"\nreproduces = \"Fig. 0\"\nparams_from = \"demo\"\nseed = 7\n"
              "[params]\n[profiles.quick]\ntrials = 3\n"),
      "quick");
  CHECK(own.params.integer("trials") == 3);
  CHECK(error_of([&] {
          (void)ExperimentConfig::load(s.root / "experiments/demo_c/experiment.toml", "full");
        }).find("no profile 'full'") != std::string::npos);
  // A missing base and a chain of variants are refused with the file and key.
  CHECK(error_of([&] {
          (void)ExperimentConfig::load(
              s.write("experiments/demo_d/experiment.toml",
                      "id = \"demo_d\"\ntitle = \"D\"\nreproduces = \"Fig. 0\"\nparams_from = \"nope\"\n"
                      "seed = 7\n[params]\n"),
              "full");
        }).find("no experiment 'nope'") != std::string::npos);
  CHECK(error_of([&] {
          (void)ExperimentConfig::load(
              s.write("experiments/demo_e/experiment.toml",
                      "id = \"demo_e\"\ntitle = \"E\"\nreproduces = \"Fig. 0\"\nparams_from = \"demo_b\"\n"
                      "seed = 7\n[params]\n"),
              "full");
        }).find("is itself a variant") != std::string::npos);
}

TEST_CASE("results round trip through baseline diff and bless") {
  Scratch s("diff");
  const auto file = s.write("experiments/demo/experiment.toml", kGood);
  auto c = ExperimentConfig::load(file, "quick");
  const fs::path results = s.root / "results";
  Results r;
  r.metric("a.b", 0.5);
  r.metric("c", 2.0);
  r.series("s", {1.0, 2.0, 3.0});
  r.check("claim", true, "detail");
  Figure f;
  f.file = "demo.png";
  r.figure(f);
  Results::Provenance p;
  p.id = "demo";
  p.profile = "quick";
  r.write(latest_path(results, "demo"), p);
  // No baseline yet: a clear error that says how to create one.
  CHECK(error_of([&] { (void)diff_against_baseline(c, results); }).find("--bless demo") != std::string::npos);
  bless(c, results);
  auto d = diff_against_baseline(c, results);
  CHECK(d.ok());
  // Move a metric beyond its tolerance, and one within.
  Results r2 = r;
  r2.metric("a.b", 0.505);  // within abs 0.01
  r2.metric("c", 2.1);      // default rel 1e-6: out
  r2.series("s", {1.0, 2.0, 3.5});
  r2.write(latest_path(results, "demo"), p);
  d = diff_against_baseline(c, results);
  CHECK(d.failures() == 2);
  const std::string table = format_diff(d);
  CHECK(table.find("s[2]") != std::string::npos);
  // Baselines carry no figure data, only the index a report from baselines links: file and title.
  {
    std::ifstream in(baseline_path(results, "demo", "quick"));
    const auto base = nlohmann::json::parse(in);
    REQUIRE(base["figures"].size() == 1);
    CHECK(base["figures"][0] == nlohmann::json{{"file", "demo.png"}, {"title", ""}});
  }
  // A tolerance key that names no metric or series is reported (a typo would silently fall back to the
  // default).
  auto c2 = ExperimentConfig::load(
      s.write("experiments/demo/experiment.toml", fmt::format("{}\"a.bb\" = {{ abs = 1 }}\n", kGood)),
      "quick");
  r.write(latest_path(results, "demo"), p);
  d = diff_against_baseline(c2, results);
  CHECK(d.failures() == 1);
  CHECK(format_diff(d).find("tolerance 'a.bb'") != std::string::npos);
  std::string why;
  CHECK_FALSE(same_results(latest_path(results, "demo"), baseline_path(results, "demo", "quick"), &why));
}

TEST_CASE("histogram_layer outlines unit-width bins; mismatched sizes are an error") {
  const auto l = keel::repro::histogram_layer({0.0, 1.0}, {0.25, 0.75}, "h", "k");
  CHECK(l.x == std::vector<double>{-0.5, -0.5, 0.5, 0.5, 0.5, 0.5, 1.5, 1.5});
  CHECK(l.y == std::vector<double>{0.0, 0.25, 0.25, 0.0, 0.0, 0.75, 0.75, 0.0});
  CHECK_THROWS_WITH_AS(keel::repro::histogram_layer({0.0, 1.0}, {1.0}, "", "k"),
                       "histogram_layer: 1 frequencies for 2 bins", std::invalid_argument);
}
