#include "repro/baseline.hpp"
#include "repro/experiment.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "repro/results.hpp"

namespace keel::repro {

using json = nlohmann::json;

namespace {

json read_json(const std::filesystem::path& p, const std::string& hint) {
  std::ifstream in(p);
  if (!in) {
    throw std::runtime_error(hint.empty() ? fmt::format("{}: not found", p.string())
                                          : fmt::format("{}: not found ({})", p.string(), hint));
  }
  try {
    return json::parse(in);
  } catch (const json::parse_error& e) {
    throw std::runtime_error(fmt::format("{}: invalid JSON: {}", p.string(), e.what()));
  }
}

double as_number(const json& v) {
  if (v.is_number()) return v.get<double>();
  if (v.is_string()) {
    const auto s = v.get<std::string>();
    if (s == "nan") return std::nan("");
    if (s == "inf") return INFINITY;
    if (s == "-inf") return -INFINITY;
  }
  throw std::runtime_error(fmt::format("not a number: {}", v.dump()));
}

// A number in a diff table: 6 significant digits.
std::string number_text(double v) { return fmt::format("{:.6g}", v); }

}  // namespace

bool DiffResult::ok() const { return failures() == 0; }
int DiffResult::failures() const {
  return static_cast<int>(std::count_if(rows.begin(), rows.end(), [](const DiffRow& r) { return !r.ok; }));
}

std::filesystem::path latest_path(const std::filesystem::path& results_dir, const std::string& id) {
  return results_dir / id / "latest.json";
}
std::filesystem::path baseline_path(const std::filesystem::path& results_dir, const std::string& id,
                                    const std::string& profile) {
  return results_dir / id / fmt::format("baseline.{}.json", profile);
}

DiffResult diff_against_baseline(const ExperimentConfig& config, const std::filesystem::path& results_dir) {
  const auto lp = latest_path(results_dir, config.id);
  const auto bp = baseline_path(results_dir, config.id, config.profile);
  const json latest = read_json(lp, fmt::format("run the experiment first: scripts/reproduce --profile {} {}",
                                                config.profile, config.id));
  const json base = read_json(
      bp, fmt::format(
              "no committed baseline; create one on purpose with scripts/reproduce --profile {} --bless {}",
              config.profile, config.id));
  DiffResult d;
  d.id = config.id;
  d.profile = config.profile;
  if (latest.value("profile", "") != config.profile) {
    d.rows.push_back({"profile", config.profile, latest.value("profile", "?"), "", false,
                      "latest.json was produced with another profile"});
  }
  const auto lh = latest["provenance"].value("config_hash", "");
  const auto bh = base["provenance"].value("config_hash", "");
  if (lh != bh) {
    d.warnings.push_back(
        fmt::format("experiment.toml changed since the baseline was blessed (hash {} -> {})", bh, lh));
  }

  const json& bm = base.at("metrics");
  const json& lm = latest.at("metrics");
  // A tolerance in flips (docs/GRADING.md) allows flips / D, D the baseline's count of the decisions' units.
  auto tol_of = [&](const std::string& name) {
    const Tolerance t = config.tolerance_for(name).value_or(Tolerance{});
    if (t.flips < 0) return t;
    if (!bm.contains(t.of)) {
      throw std::runtime_error(
          fmt::format("{}: the tolerance of '{}' counts flips of '{}', which is no metric of the "
                      "baseline",
                      config.file.string(), name, t.of));
    }
    return t.resolve_flips(as_number(bm.at(t.of)));
  };
  for (auto it = bm.begin(); it != bm.end(); ++it) {
    DiffRow r{it.key(), number_text(as_number(it.value())), "-", tol_of(it.key()).describe(), true, ""};
    if (!lm.contains(it.key())) {
      r.ok = false;
      r.note = "missing from latest";
    } else {
      const double b = as_number(it.value()), l = as_number(lm.at(it.key()));
      r.latest = number_text(l);
      if (!tol_of(it.key()).accepts(l, b)) {
        r.ok = false;
        r.note = fmt::format("|delta| = {}", number_text(std::fabs(l - b)));
      }
    }
    d.rows.push_back(r);
  }
  for (auto it = lm.begin(); it != lm.end(); ++it) {
    if (!bm.contains(it.key())) {
      d.rows.push_back(
          {it.key(), "-", number_text(as_number(it.value())), "", false, "new metric: bless to accept"});
    }
  }
  const json& bs = base.at("series");
  const json& ls = latest.at("series");
  for (auto it = bs.begin(); it != bs.end(); ++it) {
    const std::string name = it.key();
    DiffRow r{fmt::format("{}[]", name), "", "", tol_of(name).describe(), true, ""};
    if (!ls.contains(name)) {
      r.ok = false;
      r.note = "series missing from latest";
    } else if (ls.at(name).size() != it.value().size()) {
      r.ok = false;
      r.note = fmt::format("length {} -> {}", it.value().size(), ls.at(name).size());
    } else {
      // Report the worst element (largest |delta| relative to what the tolerance allows).
      double worst = -1;
      for (std::size_t i = 0; i < it.value().size(); ++i) {
        const double b = as_number(it.value()[i]), l = as_number(ls.at(name)[i]);
        const double delta = std::isnan(b) && std::isnan(l) ? 0.0 : std::fabs(l - b);
        const bool ok = tol_of(name).accepts(l, b);
        const double score = ok ? delta : 1e300;
        if (score > worst || (!ok && r.ok)) {
          worst = score;
          r.name = fmt::format("{}[{}]", name, i);
          r.baseline = number_text(b);
          r.latest = number_text(l);
        }
        if (!ok && r.ok) {
          r.ok = false;
          r.note = fmt::format("|delta| = {}", number_text(delta));
        }
      }
    }
    d.rows.push_back(r);
  }
  for (auto it = ls.begin(); it != ls.end(); ++it) {
    if (!bs.contains(it.key()))
      d.rows.push_back({fmt::format("{}[]", it.key()), "-", "new", "", false, "new series: bless to accept"});
  }
  // A tolerance key that names nothing is a typo that would silently fall back to the default.
  for (const auto& [key, tol] : config.tolerances) {
    if (key == "default") continue;
    bool names_something = bm.contains(key) || lm.contains(key) || bs.contains(key) || ls.contains(key);
    if (key.rfind("*.", 0) == 0) {
      for (const json* names : {&bm, &lm, &bs, &ls}) {
        for (auto it = names->begin(); it != names->end() && !names_something; ++it) {
          names_something = tolerance_group(it.key()) == key;
        }
      }
    }
    if (!names_something) {
      d.rows.push_back({fmt::format("tolerance '{}'", key), "-", "-", tol.describe(), false,
                        "[tolerance] key names no metric or series of this experiment"});
    }
  }
  // Claim checks: a claim that held in the baseline and fails now (or the reverse) is a change worth a look.
  if (base.contains("checks") && latest.contains("checks")) {
    for (const auto& bc : base.at("checks")) {
      const std::string name = bc.value("name", "");
      const auto lc = std::find_if(latest.at("checks").begin(), latest.at("checks").end(),
                                   [&](const json& c) { return c.value("name", "") == name; });
      const std::string bstate = bc.value("passed", false) ? "holds" : "fails";
      if (lc == latest.at("checks").end()) {
        d.rows.push_back(
            {fmt::format("check: {}", name), bstate, "-", "", false, "claim check missing from latest"});
        continue;
      }
      const std::string lstate = lc->value("passed", false) ? "holds" : "fails";
      d.rows.push_back({fmt::format("check: {}", name), bstate, lstate, "same", bstate == lstate,
                        bstate == lstate ? "" : "claim verdict changed"});
    }
    for (const auto& lc : latest.at("checks")) {
      const std::string name = lc.value("name", "");
      const bool known = std::any_of(base.at("checks").begin(), base.at("checks").end(),
                                     [&](const json& c) { return c.value("name", "") == name; });
      if (!known)
        d.rows.push_back({fmt::format("check: {}", name), "-", lc.value("passed", false) ? "holds" : "fails",
                          "", false, "new claim check: bless to accept"});
    }
  }
  return d;
}

bool bless(const ExperimentConfig& config, const std::filesystem::path& results_dir, bool allow_dirty) {
  const auto lp = latest_path(results_dir, config.id);
  json latest = read_json(lp, "run the experiment before blessing it");
  if (latest.value("profile", "") != config.profile) {
    throw std::runtime_error(fmt::format("{}: was produced with profile '{}', not '{}'", lp.string(),
                                         latest.value("profile", "?"), config.profile));
  }
  // A baseline names the commit that made it; a result of uncommitted code names none (docs/GRADING.md).
  const std::string sha =
      latest.contains("provenance") ? latest["provenance"].value("git_sha", "unknown") : "unknown";
  const bool dirty = !clean_commit(sha);
  if (dirty && !allow_dirty) {
    throw std::runtime_error(fmt::format(
        "{}: produced by git {}, a tree with uncommitted changes under engine/, experiments/ or the CMake "
        "files, so "
        "no commit made these numbers; commit, rerun (scripts/reproduce --profile {} --bless {}), or pass "
        "--allow-dirty to bless anyway (the baseline and the report then say so)",
        lp.string(), sha, config.profile, config.id));
  }
  if (dirty) latest["provenance"]["blessed_dirty"] = true;
  // The figure data stay out of the baseline (megabytes of samples); an index of the figures (file and
  // title) stays, so a report rendered from the baseline links the PNGs drawn from the same run.
  if (latest.contains("figures")) {
    json index = json::array();
    for (const auto& f : latest["figures"])
      index.push_back({{"file", f.value("file", "")}, {"title", f.value("title", "")}});
    latest["figures"] = index;
  }
  write_file_atomic(baseline_path(results_dir, config.id, config.profile), latest.dump(1) + "\n");
  return dirty;
}

bool same_results(const std::filesystem::path& a, const std::filesystem::path& b, std::string* why) {
  json ja = read_json(a, ""), jb = read_json(b, "");
  for (const char* k : {"provenance", "timings_s"}) {
    ja.erase(k);
    jb.erase(k);
  }
  if (ja == jb) return true;
  if (why) {
    const json patch = json::diff(ja, jb);
    *why = patch.empty() ? "differ" : patch.front().dump();
  }
  return false;
}

std::string format_diff(const DiffResult& d) {
  std::size_t w = 6;
  for (const auto& r : d.rows) w = std::max(w, r.name.size());
  w = std::min<std::size_t>(w, 60);
  std::string text;
  auto out = std::back_inserter(text);
  if (d.ok()) {
    fmt::format_to(out, "{} [{}]: within tolerance\n", d.id, d.profile);
  } else {
    fmt::format_to(out, "{} [{}]: {} out of tolerance\n", d.id, d.profile, d.failures());
  }
  for (const auto& warn : d.warnings) fmt::format_to(out, "  warning: {}\n", warn);
  fmt::format_to(out, "  {:<{}} {:>14} {:>14}  {:<16} \n", "metric", w, "baseline", "latest", "tolerance");
  for (const auto& r : d.rows) {
    fmt::format_to(out, "  {:<{}} {:>14} {:>14}  {:<16} {}{}{}\n", r.name.substr(0, 60), w, r.baseline,
                   r.latest, r.tolerance, r.ok ? "ok" : "FAIL", r.note.empty() ? "" : "  ", r.note);
  }
  return text;
}

}  // namespace keel::repro
