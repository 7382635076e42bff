#include "core/report.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "core/config.hpp"
#include "core/experiment.hpp"
#include "core/results.hpp"

namespace keel::core {

using json = nlohmann::json;

std::vector<std::string> list_experiments(const std::filesystem::path& dir) {
  std::vector<std::string> ids;
  if (!std::filesystem::is_directory(dir)) throw std::runtime_error(dir.string() + ": not a directory");
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.is_directory() && std::filesystem::exists(e.path() / "experiment.toml")) {
      ids.push_back(e.path().filename().string());
    }
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

namespace {

std::string fmt(double v) {
  if (std::isnan(v)) return "nan";
  char buf[32];
  const double a = std::fabs(v);
  if (a != 0 && (a < 1e-3 || a >= 1e6)) {
    std::snprintf(buf, sizeof buf, "%.3e", v);
  } else {
    std::snprintf(buf, sizeof buf, "%.6g", v);
  }
  return buf;
}

double json_number(const json& v) {
  if (v.is_number()) return v.get<double>();
  return std::nan("");
}

std::string escape_cell(std::string s) {
  for (std::size_t i = 0; (i = s.find('|', i)) != std::string::npos; i += 2) s.replace(i, 1, "\\|");
  for (auto& c : s)
    if (c == '\n') c = ' ';
  return s;
}

struct Section {
  std::string id, reproduces, title, verdict, body;
  double wall = 0;
};

Section render(const ExperimentConfig& cfg, const std::filesystem::path& results_dir) {
  Section s{cfg.id, cfg.reproduces, cfg.title, "", "", 0};
  std::ostringstream os;
  os << "<a id=\"" << cfg.id << "\"></a>\n\n## " << cfg.reproduces << ": " << cfg.title << "\n\n";
  os << "Experiment `" << cfg.id << "` ([config](../experiments/" << cfg.id << "/experiment.toml), [notes](../experiments/"
     << cfg.id << "/README.md)).";
  if (!cfg.description.empty()) os << " " << cfg.description;
  os << "\n\n";

  const auto latest_file = results_dir / cfg.id / "latest.json";
  std::ifstream in(latest_file);
  if (!in) {
    s.verdict = "not run";
    os << "**Not run**: `" << latest_file.string() << "` is missing. Run `scripts/reproduce " << cfg.id << "`.\n\n";
    s.body = os.str();
    return s;
  }
  const json r = json::parse(in);
  const std::string run_profile = r.value("profile", "?");
  s.wall = r["provenance"].value("wall_time_s", 0.0);
  // A result from other code or another config cannot carry a verdict about the current code.
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(cfg.hash));
  const std::string run_sha = r["provenance"].value("git_sha", "unknown");
  std::string stale;
  if (run_profile != cfg.profile) {
    stale = "the latest run used the `" + run_profile + "` profile";
  } else if (r["provenance"].value("config_hash", "") != hash) {
    stale = "experiment.toml changed since this result was produced";
  } else if (code_changed_since(run_sha, cfg.id)) {
    stale = "the result was produced from code (" + run_sha + ") that differs from the working tree";
  }

  const ConfigTable& th = cfg.thesis;
  std::string source = th.has("source") ? th.string("source") : cfg.reproduces;
  if (th.has("claim")) os << "**Thesis (" << source << ") claims:** " << th.string("claim") << "\n\n";

  int agree = 0, disagree = 0;
  // Published numbers next to ours.
  if (th.has("values")) {
    ConfigTable values = th.table("values");
    ConfigTable agreement = th.has("agreement") ? th.table("agreement") : ConfigTable();
    os << "| quantity | thesis | ours | agreement rule | verdict |\n|---|---|---|---|---|\n";
    for (const auto& key : values.keys()) {
      const ConfigValue& tv = values.value(key);
      std::string thesis_text;
      std::optional<double> thesis_num;
      if (auto d = std::get_if<double>(&tv.data)) {
        thesis_num = *d;
        thesis_text = fmt(*d);
      } else if (auto i = std::get_if<std::int64_t>(&tv.data)) {
        thesis_num = static_cast<double>(*i);
        thesis_text = fmt(static_cast<double>(*i));
      } else if (auto str = std::get_if<std::string>(&tv.data)) {
        thesis_text = *str;
      } else {
        throw ConfigError(values.where(key) + ": thesis value must be a number or a string");
      }
      std::optional<double> ours;
      if (r["metrics"].contains(key)) ours = json_number(r["metrics"][key]);
      Tolerance rule;
      bool has_rule = false;
      for (const std::string k : {key, std::string("default")}) {
        if (agreement.has(k)) {
          ConfigTable t = agreement.table(k);
          if (t.has("abs")) rule.abs = t.number("abs");
          if (t.has("rel")) rule.rel = t.number("rel");
          has_rule = true;
          break;
        }
      }
      std::string verdict = "—";
      if (ours && thesis_num && has_rule) {
        const bool ok = rule.accepts(*ours, *thesis_num);
        (ok ? agree : disagree)++;
        const double ratio = *thesis_num != 0 ? *ours / *thesis_num : std::nan("");
        verdict = ok ? "reproduces" : "differs (ours/thesis = " + fmt(ratio) + ")";
      } else if (!ours) {
        verdict = "not measured";
        disagree++;
      }
      os << "| `" << key << "` | " << escape_cell(thesis_text) << " | " << (ours ? fmt(*ours) : "—") << " | "
         << (has_rule ? rule.describe() : "—") << " | " << verdict << " |\n";
    }
    for (const auto& k : agreement.keys()) (void)agreement.value(k);
    os << "\n";
  }
  // Claim checks computed by the driver from the measured numbers.
  if (r.contains("checks") && !r["checks"].empty()) {
    os << "| claim checked on our numbers | holds? | measured |\n|---|---|---|\n";
    for (const auto& c : r["checks"]) {
      const bool passed = c.value("passed", false);
      (passed ? agree : disagree)++;
      os << "| " << escape_cell(c.value("name", "")) << " | " << (passed ? "yes" : "**no**") << " | "
         << escape_cell(c.value("detail", "")) << " |\n";
    }
    os << "\n";
  }
  if (!stale.empty()) {
    s.verdict = "stale: rerun";
  } else if (agree + disagree == 0) {
    s.verdict = "no comparison";
  } else if (disagree == 0) {
    s.verdict = "reproduces";
  } else if (agree == 0) {
    s.verdict = "differs";
  } else {
    s.verdict = "partly reproduces (" + std::to_string(agree) + " of " + std::to_string(agree + disagree) + ")";
  }
  os << "**Verdict: " << s.verdict << ".**";
  if (!stale.empty()) os << " " << stale << "; run `scripts/reproduce " << cfg.id << "`.";
  os << "\n\n";
  if (!cfg.discussion.empty()) os << cfg.discussion << "\n\n";

  // Key metrics not covered above.
  if (r.contains("metrics") && !r["metrics"].empty()) {
    os << "<details><summary>All metrics of this run</summary>\n\n| metric | value |\n|---|---|\n";
    for (auto it = r["metrics"].begin(); it != r["metrics"].end(); ++it) {
      os << "| `" << it.key() << "` | " << fmt(json_number(it.value())) << " |\n";
    }
    os << "\n</details>\n\n";
  }
  if (r.contains("timings_s") && !r["timings_s"].empty()) {
    os << "Timings of this run (s):";
    for (auto it = r["timings_s"].begin(); it != r["timings_s"].end(); ++it) {
      os << " " << it.key() << " " << fmt(json_number(it.value())) << ";";
    }
    os << "\n\n";
  }
  if (r.contains("figures")) {
    for (const auto& f : r["figures"]) {
      const std::string file = f.value("file", "");
      os << "![" << escape_cell(f.value("title", file)) << "](figures/" << file << ")\n\n";
    }
  }
  const json& p = r["provenance"];
  os << "<sub>profile `" << run_profile << "`, seed " << p.value("seed", 0) << ", git " << p.value("git_sha", "?")
     << ", config " << p.value("config_hash", "?") << ", " << p.value("compiler", "?") << ", " << p.value("threads", 0)
     << " threads, wall " << fmt(s.wall) << " s</sub>\n\n";
  s.body = os.str();
  return s;
}

}  // namespace

std::filesystem::path write_report(const ReportOptions& o) {
  std::vector<std::string> ids = o.ids.empty() ? list_experiments(o.experiments_dir) : o.ids;
  std::vector<Section> sections;
  for (const auto& id : ids) {
    const auto cfg = ExperimentConfig::load(o.experiments_dir / id / "experiment.toml", o.profile);
    sections.push_back(render(cfg, o.results_dir));
  }
  std::ostringstream md;
  md << "# Reproduction report\n\n"
     << "Generated by `scripts/reproduce` from `results/*/latest.json` and each experiment's `experiment.toml`; "
        "do not edit by hand. Thesis: J. G. Mangelson, *Toward Robust Multi-Agent Autonomous Underwater Inspection "
        "with Consistency and Global Optimality Guarantees*, PhD thesis, University of Michigan, 2019.\n\n"
     << "A verdict of *reproduces* means every published number we compare lies within the agreement rule stated "
        "beside it and every claim we check on our own numbers holds; anything else is reported as it is.\n\n"
     << "| thesis item | experiment | verdict | wall time |\n|---|---|---|---|\n";
  for (const auto& s : sections) {
    md << "| " << s.reproduces << " | [`" << s.id << "`](#" << s.id << ") | " << s.verdict << " | " << fmt(s.wall)
       << " s |\n";
  }
  md << "\n";
  for (const auto& s : sections) md << s.body;
  std::filesystem::create_directories(o.paper_dir);
  const auto out = o.paper_dir / "REPRODUCTION.md";
  write_file_atomic(out, md.str());
  return out;
}

}  // namespace keel::core
