// Unit tests of engine/repro: experiment configs, tolerances, results, baselines (they include the headers;
// no module import).
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "repro/baseline.hpp"
#include "repro/experiment.hpp"
#include "repro/experiment_config.hpp"
#include "repro/machine.hpp"
#include "repro/report.hpp"
#include "repro/results.hpp"
#include "kit/scratch.hpp"

using namespace keel::repro;
namespace fs = std::filesystem;

namespace {

using keel::testkit::Scratch;

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

TEST_CASE("results keys: levels from under(), fields at the call") {
  Results r;
  const auto m = r.under("manhattan");
  m.metric("cost", 1.5);
  m.under("odometry").metric("rot_se.median", 2.0);  // a field may hold dots
  m.series("gap", {1, 2});
  m.timing("time_s", 0.25);
  r.under("range1.5").metric("rate", 3.0);  // a dot inside a number is not a level
  r.at(path("paired").under("rot_se").under("sift")).metric("p", 0.01);
  CHECK(r.metrics().at("manhattan.cost") == 1.5);
  CHECK(r.metrics().at("manhattan.odometry.rot_se.median") == 2.0);
  CHECK(r.all_series().at("manhattan.gap") == std::vector<double>{1, 2});
  CHECK(r.metrics().at("range1.5.rate") == 3.0);
  CHECK(r.metrics().at("paired.rot_se.sift.p") == 0.01);
  const KeyPath k = path("cov_error").under("joint");
  CHECK(k.name() == "cov_error.joint");
  CHECK(k.key("mean") == "cov_error.joint.mean");
  CHECK(path("offset3").under(k).key("std") == "offset3.cov_error.joint.std");
  CHECK(KeyPath().name().empty());

  // A segment that joins two names hides a level; an empty one or an empty field is no key.
  for (const char* bad : {"dataset.cov_extraction", ".x", "x.", "a1.b", "1.", ""})
    CHECK_THROWS_AS(r.under(bad), std::invalid_argument);
  CHECK_THROWS_WITH_AS(path("a").under("no_gate.proposed"),
                       doctest::Contains("holds a dot between names; give each level to under()"),
                       std::invalid_argument);
  CHECK_THROWS_AS(m.metric("", 1.0), std::invalid_argument);
  CHECK(r.metrics().size() == 4);  // nothing written by the refused calls
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

TEST_CASE("tolerance in flips: wildcard names, one profile, flips / D, clear errors") {
  Scratch s("flips");
  const std::string text = fmt::format(
      "{}\"*.tpr\" = {{ flips = 1, of = \"datasets\", profile = \"full\" }}\n\"*.chi2\" = {{ rel = 0.05 }}\n",
      kGood);
  const auto file = s.write("experiments/demo/experiment.toml", text);
  const auto quick = ExperimentConfig::load(file, "quick");
  const auto full = ExperimentConfig::load(file, "full");
  CHECK(tolerance_group("dataset.pcm_exact.tpr") == "*.tpr");
  CHECK(tolerance_group("dcs.tpr@0.11") == "*.tpr");
  CHECK(tolerance_group("tpr") == "*.tpr");
  // The profile = "full" entry exists for the full profile only; the quick profile falls back to the default.
  CHECK(quick.tolerance_for("dcs.tpr")->rel == 1e-6);
  CHECK(quick.tolerance_for("dcs.tpr")->flips < 0);
  REQUIRE(full.tolerance_for("dcs.tpr@0.11").has_value());
  const Tolerance t = *full.tolerance_for("dcs.tpr@0.11");
  CHECK(t.flips == 1);
  CHECK(t.describe() == "1 flip(s) of datasets");
  const Tolerance r = t.resolve_flips(81);
  CHECK(r.abs == doctest::Approx(1.0 / 81));
  CHECK(r.accepts(0.969547 - 0.0123, 0.969547));
  CHECK_FALSE(r.accepts(0.969547 - 0.0124, 0.969547));
  CHECK(quick.tolerance_for("x.chi2")->rel == 0.05);
  CHECK(quick.tolerance_for("a.b")->abs == 0.01);  // an exact name wins over a wildcard
  for (const auto& [bad, message] :
       {std::pair<std::string, std::string>{"\"*.tpr\" = { flips = 1 }", "'flips' needs 'of'"},
        {"\"*.tpr\" = { of = \"datasets\" }", "'flips' needs 'of'"},
        {"\"*.tpr\" = { flips = -1, of = \"datasets\" }", "must be >= 0"},
        {"\"*.tpr\" = { profile = \"full\" }", "needs 'abs', 'rel' and/or 'flips'"}}) {
    CAPTURE(bad);
    const std::string e = error_of([&] {
      (void)ExperimentConfig::load(s.write("experiments/demo/experiment.toml", kGood + bad + "\n"), "quick");
    });
    CHECK(e.find(message) != std::string::npos);
  }
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

TEST_CASE("a diagnostic is shown in the diff and never fails it; it stands alone and says why") {
  Scratch s("diagnostic");
  const std::string text = fmt::format(
      "{}\"loose.max_gap\" = {{ diagnostic = \"a solver's stopping point short of convergence\" }}\n", kGood);
  auto c = ExperimentConfig::load(s.write("experiments/demo/experiment.toml", text), "quick");
  const Tolerance t = *c.tolerance_for("loose.max_gap");
  CHECK(t.describe() == "diagnostic (shown, not diffed)");
  CHECK(t.accepts(0.0128026, 0.0156922));
  const fs::path results = s.root / "results";
  Results r;
  r.metric("a.b", 0.5);
  r.metric("loose.max_gap", 0.0156922);
  Results::Provenance p;
  p.id = "demo";
  p.profile = "quick";
  p.git_sha = "0123456789ab";
  r.write(latest_path(results, "demo"), p);
  bless(c, results);
  r.metric("loose.max_gap", 0.0128026);  // what a second machine measured
  r.write(latest_path(results, "demo"), p);
  const auto d = diff_against_baseline(c, results);
  CHECK(d.ok());
  CHECK(format_diff(d).find("diagnostic") != std::string::npos);
  for (const auto& [bad, message] :
       {std::pair<std::string, std::string>{"\"x\" = { diagnostic = \"why\", abs = 1 }", "stands alone"},
        {"\"x\" = { diagnostic = \"  \" }", "must say why"}}) {
    CAPTURE(bad);
    const std::string e = error_of([&] {
      (void)ExperimentConfig::load(s.write("experiments/demo/experiment.toml", kGood + bad + "\n"), "quick");
    });
    CHECK(e.find(message) != std::string::npos);
  }
}

TEST_CASE("a report of some experiments shows the others from their baselines and says so") {
  Scratch s("partial");
  auto toml = [](const std::string& id, const std::string& discussion) {
    return fmt::format(
        "id = \"{0}\"\ntitle = \"T {0}\"\nreproduces = \"Fig. {0}\"\nseed = 1\ndiscussion = \"\"\"{1}\"\"\"\n"
        "[params]\nn = 2\n[profiles.quick]\n[profiles.full]\n[tolerance]\ndefault = {{ rel = 1e-6 }}\n",
        id, discussion);
  };
  s.write("experiments/a/experiment.toml", toml("a", "B says {b/metric:x|.3g}; C says {c/metric:y}."));
  s.write("experiments/b/experiment.toml", toml("b", "x is {metric:x|.3g}."));
  s.write("experiments/c/experiment.toml", toml("c", ""));
  const fs::path results = s.root / "results";
  auto write = [&](const std::string& id, double v, const fs::path& file) {
    Results r;
    r.metric("x", v);
    Results::Provenance p;
    p.id = id;
    p.profile = "full";
    p.git_sha = "0123456789ab";
    p.config_hash = ExperimentConfig::load(s.root / "experiments" / id / "experiment.toml", "full").hash;
    r.write(file, p);
  };
  write("a", 1.0, latest_path(results, "a"));              // run here
  write("b", 0.125, baseline_path(results, "b", "full"));  // not run here at this profile, blessed
  {
    Results quick;  // b's quick run, which lacks what the full discussion quotes
    Results::Provenance p;
    p.id = "b";
    p.profile = "quick";
    quick.write(latest_path(results, "b"), p);
  }
  // c: neither run nor blessed.
  ReportOptions o;
  o.experiments_dir = s.root / "experiments";
  o.results_dir = results;
  o.paper_dir = s.root / "paper";
  o.profile = "full";
  std::ifstream in(write_report(o));
  const std::string md((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(md.find("B says 0.125; C says n/a (`c` was not run and has no baseline).") != std::string::npos);
  CHECK(md.find("Numbers quoted above from b come from the committed `baseline.full.json`") !=
        std::string::npos);
  CHECK(md.find("**Not run here**") != std::string::npos);
  CHECK(md.find("x is 0.125.") != std::string::npos);
  CHECK(md.find("(committed baseline; not run here)") != std::string::npos);
  // A key missing from results that exist is still a typo, and an error.
  s.write("experiments/a/experiment.toml", toml("a", "B says {b/metric:xx}."));
  CHECK(error_of([&] { (void)write_report(o); }).find("no metric 'xx' in b") != std::string::npos);
}

TEST_CASE(
    "a committed side-by-side measurement is rendered under its provenance; a malformed one is refused") {
  Scratch s("side_by_side");
  s.write("experiments/a/experiment.toml",
          "id = \"a\"\ntitle = \"T a\"\nreproduces = \"Fig. a\"\nseed = 1\n[params]\nn = 2\n"
          "[profiles.quick]\n[profiles.full]\n[tolerance]\ndefault = { rel = 1e-6 }\n");
  const fs::path results = s.root / "results";
  {
    Results r;
    r.metric("x", 1.0);
    Results::Provenance p;
    p.id = "a";
    p.profile = "full";
    p.git_sha = "0123456789ab";
    p.config_hash = ExperimentConfig::load(s.root / "experiments/a/experiment.toml", "full").hash;
    r.write(latest_path(results, "a"), p);
  }
  ReportOptions o;
  o.experiments_dir = s.root / "experiments";
  o.results_dir = results;
  o.paper_dir = s.root / "paper";
  auto report = [&] {
    std::ifstream in(write_report(o));
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  CHECK(report().find("Side by side") == std::string::npos);  // no file: nothing shown
  const std::string good =
      R"({"title": "A and B", "what": "one run each.", "provenance": {"keel_commit": "abc1234", "peers": "B 1.0"},
          "tables": [{"caption": "Totals", "header": ["tool", "s"], "rows": [["A", "1.5"], ["B|x", "2.0"]]}]})";
  s.write("results/a/side_by_side.json", good);
  const std::string md = report();
  CHECK(md.find("**Side by side, measured outside this run: A and B.** one run each.") != std::string::npos);
  CHECK(md.find("<sub>keel_commit: abc1234; peers: B 1.0</sub>") != std::string::npos);
  CHECK(md.find("Totals:\n\n| tool | s |\n|---|---|\n| A | 1.5 |\n| B\\|x | 2.0 |\n") != std::string::npos);
  for (const auto& [bad, message] : std::vector<std::pair<std::string, std::string>>{
           {"{", "not JSON"},
           {R"({"title": "t", "tables": []})", "non-empty array \"tables\""},
           {R"({"title": "t", "tables": [{"header": ["a", "b"], "rows": [["1"]]}]})",
            "tables[0].rows[0] must be an array of 2 strings"},
           {R"({"title": "t", "tables": [{"header": ["a"], "rows": [[1]]}]})",
            "tables[0].rows[0] must be a string"},
           {R"({"title": "t", "provenance": {"k": 2}, "tables": [{"header": ["a"], "rows": []}]})",
            "provenance.k must be a string"}}) {
    CAPTURE(bad);
    s.write("results/a/side_by_side.json", bad);
    const std::string e = error_of([&] { (void)report(); });
    CHECK(e.find("side_by_side.json") != std::string::npos);
    CHECK(e.find(message) != std::string::npos);
  }
}

TEST_CASE("a figure's x tick labels must match its ticks one to one") {
  Scratch s("ticks");
  Results r;
  Figure f;
  f.file = "ticks.png";
  Panel p;
  p.xticks = {0.0, 1.0};
  p.xticklabels = {"only one"};
  f.panels = {p};
  r.figure(f);
  Results::Provenance prov;
  prov.id = "ticks";
  CHECK(error_of([&] { r.write(s.root / "latest.json", prov); }).find("1 x tick labels for 2 ticks") !=
        std::string::npos);
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
  p.git_sha = "0123456789ab";
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

TEST_CASE("bless refuses a result of uncommitted code unless allowed, and marks it") {
  Scratch s("bless_dirty");
  auto c = ExperimentConfig::load(s.write("experiments/demo/experiment.toml", kGood), "quick");
  const fs::path results = s.root / "results";
  Results r;
  r.metric("a.b", 0.5);
  r.metric("c", 2.0);
  r.series("s", {1.0, 2.0, 3.0});
  Results::Provenance p;
  p.id = "demo";
  p.profile = "quick";
  auto baseline = [&] {
    std::ifstream in(baseline_path(results, "demo", "quick"));
    return nlohmann::json::parse(in);
  };
  for (const std::string sha : {"0123456789ab-dirty", "unknown", "", "not a sha"}) {
    CAPTURE(sha);
    CHECK_FALSE(clean_commit(sha));
    p.git_sha = sha;
    r.write(latest_path(results, "demo"), p);
    fs::remove(baseline_path(results, "demo", "quick"));
    const std::string e = error_of([&] { (void)bless(c, results); });
    CHECK(e.find("uncommitted changes") != std::string::npos);
    CHECK(e.find("--allow-dirty") != std::string::npos);
    CHECK_FALSE(fs::exists(baseline_path(results, "demo", "quick")));
    CHECK(bless(c, results, true));
    CHECK(baseline()["provenance"]["blessed_dirty"] == true);
  }
  p.git_sha = "0123456789ab";
  CHECK(clean_commit(p.git_sha));
  r.write(latest_path(results, "demo"), p);
  CHECK_FALSE(bless(c, results));
  CHECK_FALSE(baseline()["provenance"].contains("blessed_dirty"));
}

TEST_CASE("provenance names the machine: CPU, its features, glibc, BLAS, packages") {
  const Machine& m = this_machine();
  CHECK_FALSE(m.cpu_model.empty());
  CHECK_FALSE(m.glibc.empty());
  CHECK(m.glibc.find('.') != std::string::npos);  // "2.36"
  // Each recorded feature is one of those libm and the BLAS dispatch on.
  std::istringstream features(m.cpu_features);
  for (std::string f; features >> f;) {
    CHECK((f == "sse4_2" || f == "avx" || f == "avx2" || f == "fma" || f == "avx512f"));
  }
  Scratch s("machine");
  Results r;
  r.metric("x", 1.0);
  Results::Provenance p;
  p.id = "demo";
  p.profile = "quick";
  p.machine = m;
  const fs::path file = s.root / "latest.json";
  r.write(file, p);
  std::ifstream in(file);
  const auto doc = nlohmann::json::parse(in);
  REQUIRE(doc["provenance"].contains("machine"));
  CHECK(doc["provenance"]["machine"]["cpu_model"] == m.cpu_model);
  CHECK(doc["provenance"]["machine"]["glibc"] == m.glibc);
  if (!m.packages.empty()) CHECK(doc["provenance"]["machine"]["packages"].size() == m.packages.size());
}

// The figure contract from the writer's side: one result with every layer type and every optional key,
// written to $KEEL_FIGURE_SAMPLE when set; CTest repro.figure_contract then validates it against
// scripts/figure_schema.json with scripts/figure_spec.py, so the writer and the renderer cannot drift apart.
TEST_CASE("figure contract: a result using every layer type and key") {
  Results r;
  r.timing("solve", 0.25);
  r.timing("certify", 0.5);
  Figure f;
  f.file = "contract.png";
  f.title = "every layer";
  f.rows = 2;
  f.cols = 2;
  f.width = 8;
  f.height = 6;
  Panel a;
  a.title = "lines";
  a.xlabel = "x";
  a.ylabel = "y";
  a.xscale = "log";
  a.yscale = "logit";
  a.legend = "upper left";
  a.xlim = std::pair{0.1, 10.0};
  a.ylim = std::pair{0.01, 0.99};
  Layer line = line_layer({0.1, 1.0, 10.0}, {0.1, 0.5, 0.9}, "line", "C0", "o", "--");
  line.linewidth = 1.5;
  line.alpha = 0.8;
  a.layers.push_back(line);
  Layer timed = line_layer({1.0, 2.0}, {}, "timings", "C1");
  timed.y_timings = {"solve", "certify"};
  a.layers.push_back(timed);
  a.layers.push_back(hline_layer(0.5, "half", "k"));
  Layer v;
  v.type = "vline";
  v.value = 1.0;
  v.label = "one";
  v.color = "r";
  v.linestyle = ":";
  v.linewidth = 2;
  v.alpha = 0.5;
  a.layers.push_back(v);
  a.layers.push_back(histogram_layer({1, 2, 3}, {0.2, 0.5, 0.3}, "histogram", "C2"));
  a.layers.push_back(ecdf_layer({3, 1, 2}, "ecdf", "C3", 0.5, "-."));
  Panel b;
  b.aspect = "equal";
  b.colorbar = "value";
  b.legend = "none";
  Layer sc = scatter_layer({0, 1, 2}, {0, 1, std::numeric_limits<double>::quiet_NaN()}, "scatter", "C4", 9,
                           0.5, "x");
  sc.c = {0.0, 0.5, 1.0};
  sc.cmap = "viridis";
  sc.vmin = 0;
  sc.vmax = 1;
  b.layers.push_back(sc);
  Layer seg;
  seg.type = "segments";
  seg.x0 = {0, 1};
  seg.y0 = {0, 1};
  seg.x1 = {1, 2};
  seg.y1 = {1, std::numeric_limits<double>::infinity()};
  seg.c = {0.2, 0.8};
  seg.cmap = "plasma";
  seg.vmin = 0;
  seg.vmax = 1;
  seg.color = "k";
  seg.linewidth = 0.5;
  seg.alpha = 0.9;
  seg.label = "segments";
  b.layers.push_back(seg);
  f.panels = {a, b, Panel{}};
  f.panels[2].layers.push_back(line_layer({0, 1}, {1, 0}, "", ""));
  r.figure(f);
  Figure plain;
  plain.file = "plain.png";
  Panel only;
  only.layers.push_back(line_layer({0, 1}, {0, 1}, "", ""));
  plain.panels = {only};
  r.figure(plain);
  Results::Provenance p;
  p.id = "contract";
  p.profile = "quick";
  Scratch s("contract");
  fs::path out = s.root / "contract.json";
  if (const char* env = std::getenv("KEEL_FIGURE_SAMPLE")) out = env;
  r.write(out, p);
  std::ifstream in(out);
  const auto doc = nlohmann::json::parse(in);
  REQUIRE(doc["figures"].size() == 2);
  CHECK(doc["figures"][0]["panels"].size() == 3);
  CHECK(doc["figures"][0]["layout"] == nlohmann::json{2, 2});
  CHECK(doc["figures"][0]["panels"][1]["layers"][0]["y"][2] == "nan");
  CHECK(doc["figures"][0]["panels"][1]["layers"][1]["y1"][1] == "inf");
  CHECK(doc["figures"][0]["panels"][0]["layers"][1]["y_timings"] == nlohmann::json{"solve", "certify"});
}

TEST_CASE("histogram_layer outlines unit-width bins; mismatched sizes are an error") {
  const auto l = keel::repro::histogram_layer({0.0, 1.0}, {0.25, 0.75}, "h", "k");
  CHECK(l.x == std::vector<double>{-0.5, -0.5, 0.5, 0.5, 0.5, 0.5, 1.5, 1.5});
  CHECK(l.y == std::vector<double>{0.0, 0.25, 0.25, 0.0, 0.0, 0.75, 0.75, 0.0});
  CHECK_THROWS_WITH_AS(keel::repro::histogram_layer({0.0, 1.0}, {1.0}, "", "k"),
                       "histogram_layer: 1 frequencies for 2 bins", std::invalid_argument);
}
