#include "repro/report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <set>
#include <vector>

#include "core/config.hpp"
#include "repro/experiment.hpp"
#include "repro/grading.hpp"
#include "repro/prose.hpp"
#include "repro/results.hpp"
#include "core/statistics.hpp"

namespace keel::repro {

using core::ConfigError;
using core::ConfigTable;
using core::ConfigTableData;
using core::ConfigValue;
using core::median;

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

// results/<id>/side_by_side.json (report.hpp): a measurement beside other tools, made outside the run by a
// bench script and committed; rendered as its tables under its provenance. Empty when the file does not
// exist; a malformed file is an error naming the file and the field.
std::string side_by_side_text(const std::filesystem::path& results_dir, const std::string& id) {
  const std::filesystem::path file = results_dir / id / "side_by_side.json";
  std::ifstream in(file);
  if (!in) return {};
  const std::string where = file.string();
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::exception& e) {
    throw std::runtime_error(fmt::format("{}: not JSON: {}", where, e.what()));
  }
  auto text_of = [&](const json& v, const std::string& what) {
    if (!v.is_string()) throw std::runtime_error(fmt::format("{}: {} must be a string", where, what));
    return v.get<std::string>();
  };
  if (!doc.is_object() || !doc.contains("title") || !doc.contains("tables") || !doc["tables"].is_array() ||
      doc["tables"].empty())
    throw std::runtime_error(
        fmt::format("{}: needs an object with \"title\" and a non-empty array \"tables\"", where));
  std::string out =
      fmt::format("**Side by side, measured outside this run: {}.**", text_of(doc["title"], "title"));
  if (doc.contains("what")) out += " " + text_of(doc["what"], "what");
  out += "\n\n";
  if (doc.contains("provenance")) {
    if (!doc["provenance"].is_object())
      throw std::runtime_error(fmt::format("{}: provenance must be an object of strings", where));
    std::vector<std::string> parts;
    for (auto it = doc["provenance"].begin(); it != doc["provenance"].end(); ++it)
      parts.push_back(fmt::format("{}: {}", it.key(), text_of(it.value(), "provenance." + it.key())));
    if (!parts.empty())
      out += fmt::format("<sub>{}</sub>\n\n", escape_cell(fmt::format("{}", fmt::join(parts, "; "))));
  }
  for (std::size_t t = 0; t < doc["tables"].size(); ++t) {
    const json& table = doc["tables"][t];
    const std::string name = fmt::format("tables[{}]", t);
    if (!table.is_object() || !table.contains("header") || !table["header"].is_array() ||
        table["header"].empty() || !table.contains("rows") || !table["rows"].is_array())
      throw std::runtime_error(
          fmt::format("{}: {} needs a non-empty array \"header\" and an array \"rows\"", where, name));
    if (table.contains("caption")) out += text_of(table["caption"], name + ".caption") + ":\n\n";
    std::vector<std::string> header;
    for (const json& h : table["header"]) header.push_back(escape_cell(text_of(h, name + ".header")));
    std::string rule;
    for (std::size_t k = 0; k < header.size(); ++k) rule += "---|";
    out += fmt::format("| {} |\n|{}\n", fmt::join(header, " | "), rule);
    for (std::size_t r = 0; r < table["rows"].size(); ++r) {
      const json& row = table["rows"][r];
      const std::string rname = fmt::format("{}.rows[{}]", name, r);
      if (!row.is_array() || row.size() != header.size())
        throw std::runtime_error(fmt::format("{}: {} must be an array of {} strings (the header's width)",
                                             where, rname, header.size()));
      std::vector<std::string> cells;
      for (const json& c : row) cells.push_back(escape_cell(text_of(c, rname)));
      out += fmt::format("| {} |\n", fmt::join(cells, " | "));
    }
    out += "\n";
  }
  return out;
}

// The results of experiment `id` a report section reads: `file_name` (latest.json, or a baseline) and, for a
// report of this machine's runs, the committed baseline of the profile standing in where the experiment was
// not run here at that profile (`stand_in` set). Null (json()) where neither exists.
json read_results(const std::filesystem::path& results_dir, const std::string& id,
                  const std::string& file_name, const std::string& profile, bool* stand_in) {
  if (stand_in) *stand_in = false;
  const std::string baseline = fmt::format("baseline.{}.json", profile);
  if (std::ifstream in(results_dir / id / file_name); in) {
    json r = json::parse(in);
    // A latest.json of another profile (a quick run before a full report) was not run at this profile here.
    if (file_name == baseline || r.value("profile", profile) == profile) return r;
  }
  if (file_name == baseline) return json();
  std::ifstream in(results_dir / id / baseline);
  if (!in) return json();
  if (stand_in) *stand_in = true;
  return json::parse(in);
}

// Placeholders of the discussion (core/prose.hpp): this run's metrics, timings and series, the toml's
// [thesis.values], and other experiments' results read from the same results folder — their committed
// baselines where they were not run (named in `stand_ins`), and "n/a (… not run)" where they have none.
ProseLookup prose_lookup(const ExperimentConfig& cfg, const json& r, const std::filesystem::path& results_dir,
                         const std::string& file_name, std::shared_ptr<std::set<std::string>> stand_ins) {
  auto others = std::make_shared<std::map<std::string, json>>();
  auto doc_of = [&r, &cfg, others, results_dir, file_name, stand_ins](const std::string& id) -> const json* {
    if (id.empty()) return &r;
    auto it = others->find(id);
    if (it == others->end()) {
      bool stand_in = false;
      it = others->emplace(id, read_results(results_dir, id, file_name, cfg.profile, &stand_in)).first;
      if (stand_in) stand_ins->insert(id);
    }
    return it->second.is_null() ? nullptr : &it->second;
  };
  ProseLookup l;
  l.unavailable = [doc_of](const ProseRef& ref) -> std::string {
    if (ref.experiment.empty() || ref.kind == "thesis" || doc_of(ref.experiment)) return "";
    return fmt::format("n/a (`{}` was not run and has no baseline)", ref.experiment);
  };
  l.value = [&cfg, doc_of](const ProseRef& ref) -> std::optional<double> {
    if (ref.kind == "thesis") {
      if (!cfg.thesis.has("values")) return std::nullopt;
      const ConfigTable values = cfg.thesis.table("values");
      if (!values.has(ref.key)) return std::nullopt;
      const ConfigValue& v = values.value(ref.key);
      if (auto d = std::get_if<double>(&v.data)) return *d;
      if (auto i = std::get_if<std::int64_t>(&v.data)) return static_cast<double>(*i);
      return std::nullopt;
    }
    const json* doc = doc_of(ref.experiment);
    if (!doc) return std::nullopt;
    const char* section = ref.kind == "metric" ? "metrics" : ref.kind == "timing" ? "timings_s" : "series";
    if (!doc->contains(section) || !(*doc)[section].contains(ref.key)) return std::nullopt;
    const json& v = (*doc)[section][ref.key];
    if (ref.kind != "series") return json_number(v);
    std::vector<double> xs;
    for (const auto& x : v) xs.push_back(json_number(x));
    if (ref.selector == "size") return static_cast<double>(xs.size());
    if (xs.empty()) return std::nullopt;
    if (ref.selector == "min") return *std::min_element(xs.begin(), xs.end());
    if (ref.selector == "max") return *std::max_element(xs.begin(), xs.end());
    if (ref.selector == "mean")
      return std::accumulate(xs.begin(), xs.end(), 0.0) / static_cast<double>(xs.size());
    if (ref.selector == "median") {
      std::sort(xs.begin(), xs.end());
      const std::size_t m = xs.size() / 2;
      return xs.size() % 2 ? xs[m] : 0.5 * (xs[m - 1] + xs[m]);
    }
    const std::size_t k = std::stoul(ref.selector);
    if (k >= xs.size()) return std::nullopt;
    return xs[k];
  };
  l.keys = [&cfg, doc_of](const std::string& id, const std::string& kind) {
    std::vector<std::string> keys;
    if (kind == "thesis") {
      if (cfg.thesis.has("values")) keys = cfg.thesis.table("values").keys();
      return keys;
    }
    const json* doc = doc_of(id);
    const char* section = kind == "metric" ? "metrics" : kind == "timing" ? "timings_s" : "series";
    if (doc && doc->contains(section))
      for (auto it = (*doc)[section].begin(); it != (*doc)[section].end(); ++it) keys.push_back(it.key());
    return keys;
  };
  // A quick-profile report: the discussion is written for the full profile's results.
  if (cfg.profile != "full") l.missing_text = "n/a (full profile)";
  return l;
}

// Renders one section from results/<id>/<file_name>: latest.json (this machine's last run) or a committed
// baseline, baseline.<profile>.json (from_baseline).
Section render(const ExperimentConfig& cfg, const std::filesystem::path& results_dir, bool from_baseline) {
  const std::string file_name = from_baseline ? fmt::format("baseline.{}.json", cfg.profile) : "latest.json";
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

  const auto latest_file = results_dir / cfg.id / file_name;
  // A run of some experiments only: the others are shown from their committed baselines, and say so.
  bool stand_in = false;
  const json r = read_results(results_dir, cfg.id, file_name, cfg.profile, &stand_in);
  if (r.is_null()) {
    s.verdict = "not run";
    fmt::format_to(os, "**Not run**: `{}` is missing. Run `scripts/reproduce {}`.\n\n", latest_file.string(),
                   cfg.id);
    s.body = std::move(text);
    return s;
  }
  if (stand_in)
    fmt::format_to(
        os,
        "**Not run here**: `{}` is missing, so this section shows the committed baseline "
        "`baseline.{}.json` in its place. Run `scripts/reproduce {}` for this machine's numbers.\n\n",
        latest_file.string(), cfg.profile, cfg.id);
  auto stand_ins = std::make_shared<std::set<std::string>>();
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
  } else if (!from_baseline && !stand_in && code_changed_since(run_sha, cfg.id, cfg.params_from)) {
    // A baseline is checked against the code by CI (every quick baseline is diffed against a fresh run), so a
    // report from baselines is stale only where the configuration moved.
    stale = fmt::format("the result was produced from code ({}) that differs from the working tree", run_sha);
  }

  const ConfigTable& th = cfg.thesis;
  std::string source = th.has("source") ? th.string("source") : cfg.reproduces;
  if (th.has("claim")) fmt::format_to(os, "**Thesis ({}) claims:** {}\n\n", source, th.string("claim"));

  // Grading (docs/GRADING.md): each counted row agrees or disagrees; rows true by construction, circular, on
  // another scale or not claimed by the thesis are shown with their reason and not counted.
  int agree = 0, disagree = 0;
  std::vector<std::string> central = th.has("central") ? th.strings("central") : std::vector<std::string>{};
  std::vector<std::string> central_failed;
  auto tally = [&](const std::string& row, bool ok) {
    (ok ? agree : disagree)++;
    if (!ok && std::find(central.begin(), central.end(), row) != central.end()) central_failed.push_back(row);
  };
  auto ours_value = [&r](const std::string& key) -> std::optional<double> {
    if (r["metrics"].contains(key)) return json_number(r["metrics"][key]);
    // A published time is set beside this run's timing of the same name (shown; timings are never diffed).
    if (r.contains("timings_s") && r["timings_s"].contains(key)) return json_number(r["timings_s"][key]);
    return std::nullopt;
  };
  auto thesis_number = [](const ConfigValue& tv) -> std::optional<double> {
    if (auto d = std::get_if<double>(&tv.data)) return *d;
    if (auto i = std::get_if<std::int64_t>(&tv.data)) return static_cast<double>(*i);
    return std::nullopt;
  };
  ConfigTable values = th.has("values") ? th.table("values") : ConfigTable();
  // Published numbers next to ours.
  if (th.has("values")) {
    ConfigTable agreement = th.has("agreement") ? th.table("agreement") : ConfigTable();
    text += "| quantity | thesis | ours | agreement rule | verdict |\n|---|---|---|---|---|\n";
    for (const auto& key : values.keys()) {
      const ConfigValue& tv = values.value(key);
      std::string thesis_text;
      const std::optional<double> thesis_num = thesis_number(tv);
      if (thesis_num) {
        thesis_text = number_text(*thesis_num);
      } else if (auto str = std::get_if<std::string>(&tv.data)) {
        thesis_text = *str;
      } else {
        throw ConfigError(fmt::format("{}: thesis value must be a number or a string", values.where(key)));
      }
      const std::optional<double> ours = ours_value(key);
      Tolerance rule;
      bool has_rule = false;
      std::string not_counted;  // why the row is shown but not counted
      std::optional<ConfigTable> binomial;
      for (const std::string& k : {key, std::string("default")}) {
        if (agreement.has(k)) {
          ConfigTable t = agreement.table(k);
          if (t.has("abs")) rule.abs = t.number("abs");
          if (t.has("rel")) rule.rel = t.number("rel");
          // by_construction = true: our method or setup guarantees the value.
          if (t.has("by_construction") && t.boolean("by_construction")) not_counted = "true by construction";
          // circular = "why": the value was used to set up the run that reproduces it.
          if (t.has("circular")) not_counted = "circular: " + t.string("circular");
          // scale = "why": the magnitudes are not comparable; [thesis.orderings] compares the order instead.
          if (t.has("scale")) not_counted = "scale differs: " + t.string("scale");
          if (t.has("binomial")) binomial = t.table("binomial");
          has_rule = true;
          break;
        }
      }
      std::string verdict = "—", rule_text = has_rule ? rule.describe() : "—";
      if (ours && thesis_num && has_rule) {
        bool ok = false;
        if (binomial) {
          // binomial = { n = <trials, or a metric that counts them>, per = <trials per counted unit>,
          //              n_thesis = <trials>, z = 2 }.
          double n = 0;
          if (const ConfigValue& nv = binomial->value("n"); std::holds_alternative<std::string>(nv.data)) {
            const auto nk = std::get<std::string>(nv.data);
            const auto m = ours_value(nk);
            if (!m)
              throw ConfigError(fmt::format("{}: binomial n names metric '{}', which the results lack",
                                            agreement.where(key), nk));
            // per = k: the metric counts units (data sets) of k trials each.
            n = *m * binomial->number_or("per", 1.0);
          } else {
            n = binomial->number("n");
          }
          const double z = binomial->number_or("z", 2.0);
          // printed = the unit of the thesis's last printed digit (0.001 for "0.997"): half of it is
          // rounding.
          const auto c = compare_rates(*ours, n, *thesis_num, binomial->number("n_thesis"), z,
                                       0.5 * binomial->number_or("printed", 0.0));
          ok = c.agrees;
          rule_text = fmt::format("binomial, {:g} SE (n {:g} / {:g}): ±{}", z, n,
                                  binomial->number("n_thesis"), number_text(c.allowed));
        } else {
          ok = rule.accepts(*ours, *thesis_num);
        }
        if (not_counted.empty()) tally(key, ok);
        const double ratio = *thesis_num != 0 ? *ours / *thesis_num : std::nan("");
        verdict = ok                 ? std::string("reproduces")
                  : *thesis_num != 0 ? fmt::format("differs (ours/thesis = {})", number_text(ratio))
                                     : std::string("differs");
        if (!not_counted.empty()) verdict += fmt::format(" ({}; not counted)", not_counted);
      } else if (!ours) {
        verdict = "not measured";
        tally(key, false);
      }
      fmt::format_to(os, "| `{}` | {} | {} | {} | {} |\n", key, escape_cell(thesis_text),
                     ours ? number_text(*ours) : "—", escape_cell(rule_text), escape_cell(verdict));
    }
    for (const auto& k : agreement.keys()) (void)agreement.value(k);
    text += "\n";
  }
  // Quantities the thesis and we measure on different scales: compared by the order they put the methods in.
  if (th.has("orderings")) {
    const ConfigTable orderings = th.table("orderings");
    text += "| ordering of | thesis | ours | verdict |\n|---|---|---|---|\n";
    for (const auto& name : orderings.keys()) {
      const auto keys = orderings.strings(name);
      std::vector<double> t, o;
      std::vector<std::string> labels;
      for (const auto& k : keys) {
        const auto tn = values.has(k) ? thesis_number(values.value(k)) : std::nullopt;
        if (!tn)
          throw ConfigError(fmt::format("{}: '{}' has no numeric [thesis.values] entry to order",
                                        orderings.where(name), k));
        const auto on = ours_value(k);
        if (!on) throw ConfigError(fmt::format("{}: the results lack '{}'", orderings.where(name), k));
        t.push_back(*tn), o.push_back(*on), labels.push_back(k.substr(0, k.find('.')));
      }
      const auto reversed = ordering_reversals(labels, t, o);
      tally(name, reversed.empty());
      fmt::format_to(os, "| {} | {} | {} | {} |\n", escape_cell(name), escape_cell(ordering_text(labels, t)),
                     escape_cell(ordering_text(labels, o)),
                     reversed.empty() ? std::string("same order")
                                      : fmt::format("**reversed**: {}", fmt::join(reversed, ", ")));
    }
    text += "\n";
  }
  // Claim checks computed by the driver from the measured numbers. [thesis.checks] names those that are not a
  // claim of the thesis (or repeat another row), with the reason; the driver marks the ones true by
  // construction.
  if (r.contains("checks") && !r["checks"].empty()) {
    const ConfigTable reasons = th.has("checks") ? th.table("checks") : ConfigTable();
    std::vector<std::string> unknown = reasons.keys();
    text += "| claim checked on our numbers | holds? | measured |\n|---|---|---|\n";
    for (const auto& c : r["checks"]) {
      const std::string name = c.value("name", "");
      const bool passed = c.value("passed", false);
      std::string why = c.value("counted", true) ? "" : "true by construction";
      if (reasons.has(name)) {
        why = reasons.string(name);
        unknown.erase(std::remove(unknown.begin(), unknown.end(), name), unknown.end());
      }
      if (why.empty()) tally(name, passed);
      fmt::format_to(os, "| {} | {}{} | {} |\n", escape_cell(name), passed ? "yes" : "**no**",
                     why.empty() ? "" : fmt::format(" ({}; not counted)", why),
                     escape_cell(c.value("detail", "")));
    }
    if (!unknown.empty())
      throw ConfigError(fmt::format("{}: [thesis.checks] names no check of the results: '{}'",
                                    cfg.file.string(), fmt::join(unknown, "', '")));
    text += "\n";
  }
  for (const auto& row : central) {
    bool found = values.has(row) || (th.has("orderings") && th.table("orderings").has(row));
    if (r.contains("checks"))
      for (const auto& c : r["checks"]) found = found || c.value("name", "") == row;
    if (!found)
      throw ConfigError(
          fmt::format("{}: [thesis] central names no row of the report: '{}'", cfg.file.string(), row));
  }
  if (!stale.empty()) {
    s.verdict = "stale: rerun";
  } else if (!central_failed.empty()) {
    // The thesis's central claim fails: the section does not reproduce, however many side rows agree.
    s.verdict = th.has("explained") ? "does not reproduce (explained)" : "does not reproduce";
  } else if (agree + disagree == 0) {
    s.verdict = "no comparison";
  } else if (disagree == 0) {
    s.verdict = "reproduces";
  } else if (agree == 0) {
    s.verdict = "differs";
  } else {
    s.verdict = fmt::format("partly reproduces ({} of {})", agree, agree + disagree);
  }
  // scope = "beyond the thesis" / "substitute data": what kind of comparison the counts are.
  if (stale.empty() && th.has("scope")) s.verdict = fmt::format("{}: {}", th.string("scope"), s.verdict);
  if (stand_in) s.verdict += " (committed baseline; not run here)";
  fmt::format_to(os, "**Verdict: {}.**", s.verdict);
  if (!stale.empty()) fmt::format_to(os, " {}; run `scripts/reproduce {}`.", stale, cfg.id);
  if (!central_failed.empty())
    fmt::format_to(os, " The thesis's central claim ({}) fails on our numbers.",
                   fmt::join(central_failed, "; "));
  if (th.has("explained"))
    fmt::format_to(
        os, " **Why:** {}",
        expand_prose(th.string("explained"), prose_lookup(cfg, r, results_dir, file_name, stand_ins),
                     fmt::format("{} [thesis] explained", cfg.file.string())));
  text += "\n\n";
  if (!cfg.discussion.empty())
    fmt::format_to(os, "{}\n\n",
                   expand_prose(cfg.discussion, prose_lookup(cfg, r, results_dir, file_name, stand_ins),
                                fmt::format("{} [discussion]", cfg.file.string())));
  if (!stand_ins->empty())
    fmt::format_to(os,
                   "<sub>Numbers quoted above from {} come from the committed `baseline.{}.json`: not run "
                   "here.</sub>\n\n",
                   fmt::join(*stand_ins, ", "), cfg.profile);
  text += side_by_side_text(results_dir, cfg.id);

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
  // The machine (docs/GRADING.md "Results on another machine"): CPU, the features libm and the BLAS dispatch
  // on, glibc, and the BLAS kernel family.
  std::string machine;
  if (p.contains("machine")) {
    const json& m = p["machine"];
    machine =
        fmt::format(", {} ({}), glibc {}, BLAS {}{}", m.value("cpu_model", "?"), m.value("cpu_features", "?"),
                    m.value("glibc", "?"), std::filesystem::path(m.value("blas", "?")).filename().string(),
                    m.contains("blas_core") ? fmt::format(" ({})", m.value("blas_core", "")) : "");
    if (m.contains("overrides")) machine += fmt::format(", run with {}", m.value("overrides", ""));
  }
  const std::string sha = p.value("git_sha", "?");
  const std::string dirty = p.value("blessed_dirty", false) || (from_baseline && !clean_commit(sha))
                                ? " — **blessed from uncommitted code: no commit made these numbers**"
                                : "";
  fmt::format_to(os,
                 "<sub>{}profile `{}`, seed {}, git {}, config {}, {}, {} threads, wall {} s{}{}</sub>\n\n",
                 from_baseline || stand_in ? fmt::format("baseline.{}.json: ", cfg.profile) : "", run_profile,
                 p.value("seed", 0), sha, p.value("config_hash", "?"), p.value("compiler", "?"),
                 p.value("threads", 0), number_text(s.wall), machine, dirty);
  s.body = std::move(text);
  return s;
}

}  // namespace

namespace {
void collect_numbers(const ConfigValue& v, std::vector<double>& out) {
  if (auto d = std::get_if<double>(&v.data)) out.push_back(*d);
  if (auto i = std::get_if<std::int64_t>(&v.data)) out.push_back(static_cast<double>(*i));
  if (auto a = std::get_if<std::vector<ConfigValue>>(&v.data))
    for (const auto& x : *a) collect_numbers(x, out);
  if (auto t = std::get_if<std::shared_ptr<ConfigTableData>>(&v.data))
    if (*t)
      for (const auto& [k, x] : **t) collect_numbers(x, out);
}
}  // namespace

std::vector<std::string> prose_number_problems(const ExperimentConfig& cfg) {
  std::vector<double> allowed;
  const ConfigTable& th = cfg.thesis;
  if (th.has("values")) collect_numbers(th.value("values"), allowed);
  for (const char* k : {"claim", "source"})
    if (th.has(k))
      for (const auto& n : literal_numbers(th.string(k))) allowed.push_back(n.value);
  for (const auto& k : cfg.params.keys()) collect_numbers(cfg.params.value(k), allowed);
  std::vector<std::string> problems;
  // The discussion and the [thesis] explanation of a verdict are both report prose.
  const std::string explained = th.has("explained") ? th.string("explained") : std::string();
  for (const auto& [label, prose] :
       {std::pair<const char*, const std::string*>{"[discussion]", &cfg.discussion},
        {"[thesis] explained", &explained}}) {
    for (const auto& n : literal_numbers(*prose)) {
      if (std::any_of(allowed.begin(), allowed.end(), [&](double a) { return literal_matches(n, a); }))
        continue;
      const std::size_t from = n.offset > 40 ? n.offset - 40 : 0;
      std::string context = prose->substr(from, n.offset - from + n.text.size() + 20);
      std::replace(context.begin(), context.end(), '\n', ' ');
      problems.push_back(
          fmt::format("{} {}: '{}' in \"…{}…\" is neither a thesis number nor a setting: "
                      "write a placeholder such as {{metric:KEY}}",
                      cfg.file.string(), label, n.text, context));
    }
  }
  return problems;
}

std::filesystem::path write_report(const ReportOptions& o) {
  std::vector<std::string> ids = o.ids.empty() ? list_experiments(o.experiments_dir) : o.ids;
  std::vector<Section> sections;
  for (const auto& id : ids) {
    const auto cfg = ExperimentConfig::load(o.experiments_dir / id / "experiment.toml", o.profile);
    sections.push_back(render(cfg, o.results_dir, o.from_baseline));
  }
  std::string md =
      "# Reproduction report\n\n" +
      std::string(
          o.from_baseline
              ? fmt::format("Generated by `keel report --profile {0} --from baseline` from the committed "
                            "baselines `results/*/baseline.{0}.json` (each section names the commit its "
                            "results were blessed at) and each experiment's `experiment.toml`, so it can "
                            "be regenerated from a clone alone;",
                            o.profile)
              : fmt::format("Generated by `keel report --profile {}` from this machine's last runs, "
                            "`results/*/latest.json` (not committed), and each experiment's "
                            "`experiment.toml`;",
                            o.profile)) +
      " do not edit by hand. Thesis: J. G. Mangelson, *Toward Robust Multi-Agent Autonomous Underwater "
      "Inspection "
      "with Consistency and Global Optimality Guarantees*, PhD thesis, University of Michigan, 2019.\n\n"
      "A verdict of *reproduces* means every counted row agrees: each published number we compare lies "
      "within "
      "the agreement rule stated beside it, each ordering of methods is the thesis's, and each claim we "
      "check on "
      "our own numbers holds. *Partly reproduces (k of n)* counts the rows that agree; *does not reproduce* "
      "means the thesis's central claim fails, *(explained)* when the section names the cause and the metric "
      "that shows it. Rows true by construction, circular rows, rows on scales the thesis and we do not "
      "share, "
      "and checks of what the thesis does not claim are shown with the reason and not counted; rates are "
      "compared within binomial sampling error. The rules are in "
      "[docs/GRADING.md](../docs/GRADING.md).\n\n"
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

}  // namespace keel::repro
