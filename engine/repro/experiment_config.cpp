#include "repro/experiment_config.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

namespace keel::repro {

using core::ConfigError;
using core::ConfigTable;
using core::ConfigTableData;
using core::ConfigValue;
using core::load_toml;

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

bool Tolerance::accepts(double ours, double base) const {
  if (!diagnostic.empty()) return true;
  if (std::isnan(ours) || std::isnan(base)) return std::isnan(ours) && std::isnan(base);
  if (std::isinf(ours) || std::isinf(base)) return ours == base;
  const double d = std::fabs(ours - base);
  if (abs >= 0 && d <= abs) return true;
  if (rel >= 0 && d <= rel * std::fabs(base)) return true;
  return abs < 0 && rel < 0 && d == 0.0;
}

std::string tolerance_group(std::string_view name) {
  name = name.substr(0, name.find('@'));  // "dcs.tpr@0.11": the level tag may hold dots itself
  const auto dot = name.rfind('.');
  return fmt::format("*.{}", dot == std::string_view::npos ? name : name.substr(dot + 1));
}

Tolerance Tolerance::resolve_flips(double count) const {
  Tolerance t = *this;
  if (flips >= 0 && count > 0) t.abs = std::max(abs, flips / count);
  return t;
}

std::string Tolerance::describe() const {
  if (!diagnostic.empty()) return "diagnostic (shown, not diffed)";
  if (flips >= 0) {
    const std::string rest = abs >= 0 && rel >= 0 ? fmt::format(": abs {:g} or rel {:g}", abs, rel)
                             : abs >= 0           ? fmt::format(": abs {:g}", abs)
                             : rel >= 0           ? fmt::format(" or rel {:g}", rel)
                                                  : "";
    return fmt::format("{:g} flip(s) of {}{}", flips, of, rest);
  }
  if (abs >= 0 && rel >= 0) return fmt::format("abs {:g} or rel {:g}", abs, rel);
  if (abs >= 0) return fmt::format("abs {:g}", abs);
  if (rel >= 0) return fmt::format("rel {:g}", rel);
  return "exact";
}

std::optional<Tolerance> ExperimentConfig::tolerance_for(std::string_view metric) const {
  if (auto it = tolerances.find(metric); it != tolerances.end()) return it->second;
  if (auto it = tolerances.find(tolerance_group(metric)); it != tolerances.end()) return it->second;
  if (auto it = tolerances.find(std::string_view("default")); it != tolerances.end()) return it->second;
  return std::nullopt;
}

namespace {

std::string canonical_value(const ConfigValue& v) {
  switch (v.data.index()) {
    case 1:
      return fmt::format("{}", std::get<std::int64_t>(v.data));
    case 2:
      return fmt::format("{:.17g}", std::get<double>(v.data));
    case 3:
      return std::get<bool>(v.data) ? "true" : "false";
    case 4:
      return fmt::format("\"{}\"", std::get<std::string>(v.data));
    case 5: {
      std::string s = "[";
      for (const auto& e : std::get<std::vector<ConfigValue>>(v.data))
        fmt::format_to(std::back_inserter(s), "{},", canonical_value(e));
      return s + "]";
    }
    case 6: {
      std::string s = "{";
      for (const auto& [k, e] : *std::get<std::shared_ptr<ConfigTableData>>(v.data))
        fmt::format_to(std::back_inserter(s), "{}={},", k, canonical_value(e));
      return s + "}";
    }
    default:
      return "";
  }
}

std::shared_ptr<ConfigTableData> overlay(const ConfigTableData& base, const ConfigTableData& top) {
  auto out = std::make_shared<ConfigTableData>(base);
  for (const auto& [k, v] : top) (*out)[k] = v;
  return out;
}

// A [tolerance] entry; `profile` (when given) is returned through `only_profile`.
Tolerance parse_tolerance(const ConfigTable& t, std::string& only_profile) {
  Tolerance tol;
  if (t.has("abs")) tol.abs = t.number("abs");
  if (t.has("rel")) tol.rel = t.number("rel");
  if (t.has("flips")) tol.flips = t.number("flips");
  if (t.has("of")) tol.of = t.string("of");
  if (t.has("diagnostic")) tol.diagnostic = t.string("diagnostic");
  only_profile = t.has("profile") ? t.string("profile") : "";
  t.finish();
  if ((t.has("abs") && !(tol.abs >= 0)) || (t.has("rel") && !(tol.rel >= 0)) ||
      (t.has("flips") && !(tol.flips >= 0))) {
    throw ConfigError(fmt::format("{}: [{}] tolerances must be >= 0", t.file(), t.name()));
  }
  if (t.has("flips") != t.has("of")) {
    throw ConfigError(
        fmt::format("{}: [{}] 'flips' needs 'of' (the metric that counts the decisions' units, e.g. "
                    "of = \"datasets\") and 'of' needs 'flips'",
                    t.file(), t.name()));
  }
  if (t.has("diagnostic")) {
    // A diagnostic is never diffed, so a bound beside it would be read as one that holds.
    if (t.has("abs") || t.has("rel") || t.has("flips"))
      throw ConfigError(fmt::format("{}: [{}] 'diagnostic' stands alone: a diagnostic has no tolerance",
                                    t.file(), t.name()));
    if (tol.diagnostic.find_first_not_of(" \t") == std::string::npos)
      throw ConfigError(
          fmt::format("{}: [{}] 'diagnostic' must say why the value is not diffed", t.file(), t.name()));
    return tol;
  }
  if (!t.has("abs") && !t.has("rel") && !t.has("flips")) {
    throw ConfigError(
        fmt::format("{}: [{}] needs 'abs', 'rel' and/or 'flips', or 'diagnostic'", t.file(), t.name()));
  }
  return tol;
}

}  // namespace

ExperimentConfig ExperimentConfig::load(const std::filesystem::path& file, const std::string& profile) {
  ConfigTable root = load_toml(file);
  ExperimentConfig c;
  c.file = file;
  c.profile = profile;
  c.id = root.string("id");
  const std::string folder = std::filesystem::absolute(file).parent_path().filename().string();
  if (c.id != folder) {
    throw ConfigError(
        fmt::format("{}: '{}' must equal the experiment folder name '{}'", root.where("id"), c.id, folder));
  }
  c.title = root.string("title");
  c.reproduces = root.string("reproduces");
  c.description = root.string_or("description", "");
  c.discussion = root.string_or("discussion", "");
  c.runs_whole = root.string_or("runs_whole", "");
  const std::int64_t seed = root.integer("seed");
  if (seed < 0) throw ConfigError(fmt::format("{}: must be >= 0", root.where("seed")));
  c.seed = static_cast<std::uint64_t>(seed);

  ConfigTable params = root.table("params");
  // params_from = "<id>": a variant of another experiment. Its [params] are the base that this file's
  // [params] override key by key, and its [profiles] apply unless this file has its own. One level only, so a
  // variant's settings are always found in two files at most.
  std::optional<ConfigTable> from;
  if (root.has("params_from")) {
    const std::string from_id = root.string("params_from");
    c.params_from = from_id;
    const auto from_file =
        std::filesystem::absolute(file).parent_path().parent_path() / from_id / "experiment.toml";
    if (!std::filesystem::exists(from_file))
      throw ConfigError(fmt::format("{}: no experiment '{}' ({} is missing)", root.where("params_from"),
                                    from_id, from_file.string()));
    from = load_toml(from_file);
    if (from->has("params_from"))
      throw ConfigError(fmt::format("{}: '{}' is itself a variant (params_from); name its base instead",
                                    root.where("params_from"), from_id));
  }
  ConfigTable profiles = root.has("profiles") || !from ? root.table("profiles") : from->table("profiles");
  c.profiles = profiles.keys();
  if (!profiles.has(profile)) {
    throw ConfigError(fmt::format("{}: [profiles] has no profile '{}' (defined: {})", file.string(), profile,
                                  fmt::join(c.profiles, ", ")));
  }
  // Only the selected profile is laid over [params]; the driver's reads check its keys. The other profiles
  // must not hide typos until their own run: every profile key must either override a [params] key or be set
  // by every profile (then the driver reads it whichever profile runs).
  const auto& pv = root.value("params");
  const auto base = from ? *overlay(*std::get<std::shared_ptr<ConfigTableData>>(from->value("params").data),
                                    *std::get<std::shared_ptr<ConfigTableData>>(pv.data))
                         : *std::get<std::shared_ptr<ConfigTableData>>(pv.data);
  std::shared_ptr<const ConfigTableData> selected;
  std::vector<ConfigTable> profile_tables;
  for (const auto& p : c.profiles) {
    profile_tables.push_back(profiles.table(p));
    if (p == profile) selected = std::get<std::shared_ptr<ConfigTableData>>(profiles.value(p).data);
  }
  for (const auto& pt : profile_tables) {
    for (const auto& k : pt.keys()) {
      (void)pt.value(k);
      if (base.count(k)) continue;
      for (const auto& other : profile_tables) {
        if (!other.has(k)) {
          throw ConfigError(
              fmt::format("{}: set in [{}] but neither in [params] nor in [{}] (a typo? every profile must "
                          "set the same keys)",
                          pt.where(k), pt.name(), other.name()));
        }
      }
    }
  }
  const auto merged = overlay(base, *selected);
  c.params = ConfigTable(file.string(), "params", merged);
  // The overlay copy is what the driver reads; the original [params] view is marked read as a whole.
  for (const auto& k : params.keys()) (void)params.value(k);

  if (root.has("thesis")) c.thesis = root.table("thesis");
  if (root.has("tolerance")) {
    ConfigTable tol = root.table("tolerance");
    for (const auto& k : tol.keys()) {
      std::string only_profile;
      const Tolerance t = parse_tolerance(tol.table(k), only_profile);
      if (only_profile.empty() || only_profile == c.profile) c.tolerances[k] = t;
    }
  }
  // Report-only tables are read by the report; mark them here so finish() only catches typos at the top
  // level.
  if (root.has("thesis")) {
    for (const auto& k : c.thesis.keys()) (void)c.thesis.value(k);
  }
  // finish() on the root checks top-level keys only for unknowns: sub-tables were fully consumed above.
  root.finish();

  // The hash covers what the run depends on — id, seed, profile and the resolved parameters — not the prose
  // (description, discussion, thesis values), so editing the report text does not make results stale.
  std::string canon = fmt::format("{}\n{}\n{}\n", c.id, c.seed, profile);
  for (const auto& [k, v] : *merged)
    fmt::format_to(std::back_inserter(canon), "{}={}\n", k, canonical_value(v));
  c.hash = fnv1a64(canon);
  // A fresh, untracked view of [thesis] for the report (so its reads are checked there, not here).
  if (root.has("thesis")) {
    const auto& tv = root.value("thesis");
    c.thesis = ConfigTable(file.string(), "thesis", std::get<std::shared_ptr<ConfigTableData>>(tv.data));
  }
  return c;
}

}  // namespace keel::repro
