#include "core/report.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>

#include "core/config.hpp"
#include "core/experiment.hpp"
#include "core/results.hpp"

namespace keel::core {

using json = nlohmann::json;

std::vector<std::string> list_experiments(const std::filesystem::path& dir) {
  std::vector<std::string> ids;
  if (!std::filesystem::is_directory(dir))
    throw std::runtime_error(fmt::format("{}: not a directory", dir.string()));
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.is_directory() && std::filesystem::exists(e.path() / "experiment.toml")) {
      ids.push_back(e.path().filename().string());
    }
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

namespace {

// A number for the report: 3 significant decimals in scientific notation outside [1e-3, 1e6), else 6
// significant digits.
std::string number_text(double v) {
  if (std::isnan(v)) return "nan";
  const double a = std::fabs(v);
  if (a != 0 && (a < 1e-3 || a >= 1e6)) return fmt::format("{:.3e}", v);
  return fmt::format("{:.6g}", v);
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
  std::string text;
  auto os = std::back_inserter(text);
  fmt::format_to(os, "<a id=\"{}\"></a>\n\n## {}: {}\n\n", cfg.id, cfg.reproduces, cfg.title);
  fmt::format_to(os,
                 "Experiment `{0}` ([config](../experiments/{0}/experiment.toml), "
                 "[notes](../experiments/{0}/README.md)).",
                 cfg.id);
  if (!cfg.description.empty()) fmt::format_to(os, " {}", cfg.description);
  text += "\n\n";

  const auto latest_file = results_dir / cfg.id / "latest.json";
  std::ifstream in(latest_file);
  if (!in) {
    s.verdict = "not run";
    fmt::format_to(os, "**Not run**: `{}` is missing. Run `scripts/reproduce {}`.\n\n", latest_file.string(),
                   cfg.id);
    s.body = std::move(text);
    return s;
  }
  const json r = json::parse(in);
  const std::string run_profile = r.value("profile", "?");
  s.wall = r["provenance"].value("wall_time_s", 0.0);
  // A result from other code or another config cannot carry a verdict about the current code.
  const std::string hash = fmt::format("{:016x}", cfg.hash);
  const std::string run_sha = r["provenance"].value("git_sha", "unknown");
  std::string stale;
  if (run_profile != cfg.profile) {
    stale = fmt::format("the latest run used the `{}` profile", run_profile);
  } else if (r["provenance"].value("config_hash", "") != hash) {
    stale = "experiment.toml changed since this result was produced";
  } else if (code_changed_since(run_sha, cfg.id)) {
    stale = fmt::format("the result was produced from code ({}) that differs from the working tree", run_sha);
  }

  const ConfigTable& th = cfg.thesis;
  std::string source = th.has("source") ? th.string("source") : cfg.reproduces;
  if (th.has("claim")) fmt::format_to(os, "**Thesis ({}) claims:** {}\n\n", source, th.string("claim"));

  int agree = 0, disagree = 0;
  // Published numbers next to ours.
  if (th.has("values")) {
    ConfigTable values = th.table("values");
    ConfigTable agreement = th.has("agreement") ? th.table("agreement") : ConfigTable();
    text += "| quantity | thesis | ours | agreement rule | verdict |\n|---|---|---|---|---|\n";
    for (const auto& key : values.keys()) {
      const ConfigValue& tv = values.value(key);
      std::string thesis_text;
      std::optional<double> thesis_num;
      if (auto d = std::get_if<double>(&tv.data)) {
        thesis_num = *d;
        thesis_text = number_text(*d);
      } else if (auto i = std::get_if<std::int64_t>(&tv.data)) {
        thesis_num = static_cast<double>(*i);
        thesis_text = number_text(static_cast<double>(*i));
      } else if (auto str = std::get_if<std::string>(&tv.data)) {
        thesis_text = *str;
      } else {
        throw ConfigError(fmt::format("{}: thesis value must be a number or a string", values.where(key)));
      }
      std::optional<double> ours;
      if (r["metrics"].contains(key)) ours = json_number(r["metrics"][key]);
      // A published time is set beside this run's timing of the same name (shown; timings are never diffed).
      else if (r.contains("timings_s") && r["timings_s"].contains(key))
        ours = json_number(r["timings_s"][key]);
      Tolerance rule;
      bool has_rule = false, by_construction = false;
      for (const std::string& k : {key, std::string("default")}) {
        if (agreement.has(k)) {
          ConfigTable t = agreement.table(k);
          if (t.has("abs")) rule.abs = t.number("abs");
          if (t.has("rel")) rule.rel = t.number("rel");
          // by_construction = true: our method or setup guarantees the value; shown, not counted.
          if (t.has("by_construction")) by_construction = t.boolean("by_construction");
          has_rule = true;
          break;
        }
      }
      std::string verdict = "—";
      if (ours && thesis_num && has_rule) {
        const bool ok = rule.accepts(*ours, *thesis_num);
        if (!by_construction) (ok ? agree : disagree)++;
        const double ratio = *thesis_num != 0 ? *ours / *thesis_num : std::nan("");
        verdict = ok ? "reproduces" : fmt::format("differs (ours/thesis = {})", number_text(ratio));
        if (by_construction) verdict += " (true by construction; not counted)";
      } else if (!ours) {
        verdict = "not measured";
        disagree++;
      }
      fmt::format_to(os, "| `{}` | {} | {} | {} | {} |\n", key, escape_cell(thesis_text),
                     ours ? number_text(*ours) : "—", has_rule ? rule.describe() : "—", verdict);
    }
    for (const auto& k : agreement.keys()) (void)agreement.value(k);
    text += "\n";
  }
  // Claim checks computed by the driver from the measured numbers.
  if (r.contains("checks") && !r["checks"].empty()) {
    text += "| claim checked on our numbers | holds? | measured |\n|---|---|---|\n";
    for (const auto& c : r["checks"]) {
      const bool passed = c.value("passed", false), counted = c.value("counted", true);
      if (counted) (passed ? agree : disagree)++;
      fmt::format_to(os, "| {} | {}{} | {} |\n", escape_cell(c.value("name", "")), passed ? "yes" : "**no**",
                     counted ? "" : " (true by construction; not counted)",
                     escape_cell(c.value("detail", "")));
    }
    text += "\n";
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
    s.verdict = fmt::format("partly reproduces ({} of {})", agree, agree + disagree);
  }
  fmt::format_to(os, "**Verdict: {}.**", s.verdict);
  if (!stale.empty()) fmt::format_to(os, " {}; run `scripts/reproduce {}`.", stale, cfg.id);
  text += "\n\n";
  if (!cfg.discussion.empty()) fmt::format_to(os, "{}\n\n", cfg.discussion);

  // Key metrics not covered above.
  if (r.contains("metrics") && !r["metrics"].empty()) {
    text += "<details><summary>All metrics of this run</summary>\n\n| metric | value |\n|---|---|\n";
    for (auto it = r["metrics"].begin(); it != r["metrics"].end(); ++it) {
      fmt::format_to(os, "| `{}` | {} |\n", it.key(), number_text(json_number(it.value())));
    }
    text += "\n</details>\n\n";
  }
  if (r.contains("timings_s") && !r["timings_s"].empty()) {
    text += "Timings of this run (s):";
    for (auto it = r["timings_s"].begin(); it != r["timings_s"].end(); ++it) {
      fmt::format_to(os, " {} {};", it.key(), number_text(json_number(it.value())));
    }
    text += "\n\n";
  }
  if (r.contains("figures")) {
    for (const auto& f : r["figures"]) {
      const std::string file = f.value("file", "");
      fmt::format_to(os, "![{}](figures/{})\n\n", escape_cell(f.value("title", file)), file);
    }
  }
  const json& p = r["provenance"];
  fmt::format_to(os, "<sub>profile `{}`, seed {}, git {}, config {}, {}, {} threads, wall {} s</sub>\n\n",
                 run_profile, p.value("seed", 0), p.value("git_sha", "?"), p.value("config_hash", "?"),
                 p.value("compiler", "?"), p.value("threads", 0), number_text(s.wall));
  s.body = std::move(text);
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
  std::string md =
      "# Reproduction report\n\n"
      "Generated by `scripts/reproduce` from `results/*/latest.json` and each experiment's "
      "`experiment.toml`; "
      "do not edit by hand. Thesis: J. G. Mangelson, *Toward Robust Multi-Agent Autonomous Underwater "
      "Inspection "
      "with Consistency and Global Optimality Guarantees*, PhD thesis, University of Michigan, 2019.\n\n"
      "A verdict of *reproduces* means every published number we compare lies within the agreement rule "
      "stated "
      "beside it and every claim we check on our own numbers holds; anything else is reported as it is. Rows "
      "marked "
      "*true by construction* hold because of how the method or the setup is built: they are shown, not "
      "counted.\n\n"
      "| thesis item | experiment | verdict | wall time |\n|---|---|---|---|\n";
  for (const auto& s : sections) {
    fmt::format_to(std::back_inserter(md), "| {} | [`{}`](#{}) | {} | {} s |\n", s.reproduces, s.id, s.id,
                   s.verdict, number_text(s.wall));
  }
  md += "\n";
  for (const auto& s : sections) md += s.body;
  std::filesystem::create_directories(o.paper_dir);
  const auto out = o.paper_dir / "REPRODUCTION.md";
  write_file_atomic(out, md);
  return out;
}

}  // namespace keel::core
