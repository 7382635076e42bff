#include "core/config.hpp"

#include <fmt/format.h>

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <iterator>

namespace keel::core {

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

std::string config_type_name(const ConfigValue& v) {
  switch (v.data.index()) {
    case 0:
      return "nothing";
    case 1:
      return "integer";
    case 2:
      return "float";
    case 3:
      return "boolean";
    case 4:
      return "string";
    case 5:
      return "array";
    default:
      return "table";
  }
}

namespace {

std::string join_name(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : fmt::format("{}.{}", parent, key);
}

ConfigValue convert(const toml::node& node, const std::string& table_name, const std::string& file);

std::shared_ptr<ConfigTableData> convert_table(const toml::table& t, const std::string& name,
                                               const std::string& file) {
  auto out = std::make_shared<ConfigTableData>();
  for (const auto& [k, v] : t) {
    const std::string key(k.str());
    ConfigValue cv = convert(v, v.is_table() ? join_name(name, key) : name, file);
    cv.table = name;
    cv.line = static_cast<int>(v.source().begin.line);
    out->emplace(key, std::move(cv));
  }
  return out;
}

ConfigValue convert(const toml::node& node, const std::string& table_name, const std::string& file) {
  ConfigValue cv;
  cv.table = table_name;
  cv.line = static_cast<int>(node.source().begin.line);
  if (auto i = node.as_integer()) {
    cv.data = i->get();
  } else if (auto f = node.as_floating_point()) {
    cv.data = f->get();
  } else if (auto b = node.as_boolean()) {
    cv.data = b->get();
  } else if (auto s = node.as_string()) {
    cv.data = s->get();
  } else if (auto a = node.as_array()) {
    std::vector<ConfigValue> items;
    for (const auto& e : *a) items.push_back(convert(e, table_name, file));
    cv.data = std::move(items);
  } else if (auto t = node.as_table()) {
    cv.data = convert_table(*t, table_name, file);
  } else {
    throw ConfigError(fmt::format("{}:{}: unsupported TOML value type (dates are not used)", file, cv.line));
  }
  return cv;
}

}  // namespace

ConfigTable::ConfigTable(std::string file, std::string name, std::shared_ptr<const ConfigTableData> data)
    : file_(std::move(file)), name_(std::move(name)), data_(std::move(data)) {}

std::string ConfigTable::where(std::string_view key) const {
  std::string s =
      fmt::format("{}: [{}] key '{}'", file_, name_.empty() ? std::string_view("top level") : name_, key);
  if (data_) {
    if (auto it = data_->find(key); it != data_->end()) {
      if (it->second.table != name_) s = fmt::format("{}: [{}] key '{}'", file_, it->second.table, key);
      if (it->second.line > 0) s += fmt::format(" (line {})", it->second.line);
    }
  }
  return s;
}

bool ConfigTable::has(std::string_view key) const { return data_ && data_->find(key) != data_->end(); }

std::vector<std::string> ConfigTable::keys() const {
  std::vector<std::string> out;
  if (data_)
    for (const auto& [k, v] : *data_) out.push_back(k);
  return out;
}

const ConfigValue& ConfigTable::get(std::string_view key, std::string_view expected) const {
  if (!data_ || data_->find(key) == data_->end()) {
    throw ConfigError(fmt::format("{}: missing (expected {})", where(key), expected));
  }
  used_->insert(std::string(key));
  return data_->find(key)->second;
}

const ConfigValue& ConfigTable::value(std::string_view key) const { return get(key, "a value"); }

void ConfigTable::parse_error(std::string_view key, std::string_view what) const {
  throw ConfigError(fmt::format("{}: {}", where(key), what));
}

void ConfigTable::table_error(std::string_view what) const {
  throw ConfigError(fmt::format("{}: [{}]: {}", file(), name(), what));
}

void ConfigTable::type_error(std::string_view key, std::string_view expected, const ConfigValue& v) const {
  throw ConfigError(fmt::format("{}: expected {}, got {}", where(key), expected, config_type_name(v)));
}

double ConfigTable::number(std::string_view key) const {
  const auto& v = get(key, "a number");
  if (auto i = std::get_if<std::int64_t>(&v.data)) return static_cast<double>(*i);
  if (auto d = std::get_if<double>(&v.data)) return *d;
  type_error(key, "a number", v);
}

std::int64_t ConfigTable::integer(std::string_view key) const {
  const auto& v = get(key, "an integer");
  if (auto i = std::get_if<std::int64_t>(&v.data)) return *i;
  type_error(key, "an integer", v);
}

bool ConfigTable::boolean(std::string_view key) const {
  const auto& v = get(key, "a boolean");
  if (auto b = std::get_if<bool>(&v.data)) return *b;
  type_error(key, "a boolean", v);
}

std::string ConfigTable::string(std::string_view key) const {
  const auto& v = get(key, "a string");
  if (auto s = std::get_if<std::string>(&v.data)) return *s;
  type_error(key, "a string", v);
}

std::vector<double> ConfigTable::numbers(std::string_view key) const {
  const auto& v = get(key, "an array of numbers");
  auto a = std::get_if<std::vector<ConfigValue>>(&v.data);
  if (!a) type_error(key, "an array of numbers", v);
  std::vector<double> out;
  for (std::size_t i = 0; i < a->size(); ++i) {
    const auto& e = (*a)[i];
    if (auto x = std::get_if<std::int64_t>(&e.data)) {
      out.push_back(static_cast<double>(*x));
    } else if (auto d = std::get_if<double>(&e.data)) {
      out.push_back(*d);
    } else {
      throw ConfigError(
          fmt::format("{}: element {} must be a number, got {}", where(key), i, config_type_name(e)));
    }
  }
  return out;
}

std::vector<std::string> ConfigTable::strings(std::string_view key) const {
  const auto& v = get(key, "an array of strings");
  auto a = std::get_if<std::vector<ConfigValue>>(&v.data);
  if (!a) type_error(key, "an array of strings", v);
  std::vector<std::string> out;
  for (std::size_t i = 0; i < a->size(); ++i) {
    auto s = std::get_if<std::string>(&(*a)[i].data);
    if (!s) {
      throw ConfigError(
          fmt::format("{}: element {} must be a string, got {}", where(key), i, config_type_name((*a)[i])));
    }
    out.push_back(*s);
  }
  return out;
}

ConfigTable ConfigTable::table(std::string_view key) const {
  const auto& v = get(key, "a table");
  auto t = std::get_if<std::shared_ptr<ConfigTableData>>(&v.data);
  if (!t) type_error(key, "a table", v);
  ConfigTable child(file_, join_name(name_, std::string(key)), *t);
  children_->push_back(child);
  return child;
}

std::size_t ConfigTable::count(std::string_view key) const {
  const std::int64_t v = integer(key);
  if (v < 1) throw ConfigError(fmt::format("{}: must be a positive integer, got {}", where(key), v));
  return static_cast<std::size_t>(v);
}

double ConfigTable::number_or(std::string_view key, double fallback) const {
  return has(key) ? number(key) : fallback;
}
std::int64_t ConfigTable::integer_or(std::string_view key, std::int64_t fallback) const {
  return has(key) ? integer(key) : fallback;
}
std::string ConfigTable::string_or(std::string_view key, std::string fallback) const {
  return has(key) ? string(key) : fallback;
}

void ConfigTable::finish() const {
  if (data_) {
    std::vector<std::string> unknown;
    for (const auto& [k, v] : *data_)
      if (!used_->count(k)) unknown.push_back(k);
    if (!unknown.empty()) {
      std::string msg = fmt::format("{}: unknown key", where(unknown.front()));
      if (unknown.size() > 1) {
        msg += " (also unknown:";
        for (std::size_t i = 1; i < unknown.size(); ++i)
          fmt::format_to(std::back_inserter(msg), " '{}'", unknown[i]);
        msg += ")";
      }
      std::vector<std::string_view> names;
      for (const auto& [k, v] : *data_)
        if (used_->count(k)) names.push_back(k);
      if (!names.empty())
        fmt::format_to(std::back_inserter(msg), "; known keys here: {}", fmt::join(names, ", "));
      throw ConfigError(msg);
    }
  }
  for (const auto& c : *children_) c.finish();
}

ConfigTable load_toml(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open file", file.string()));
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  toml::table root;
  try {
    root = toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format("{}:{}:{}: TOML syntax error: {}", file.string(), e.source().begin.line,
                                  e.source().begin.column, e.description()));
  }
  return ConfigTable(file.string(), "", convert_table(root, "", file.string()));
}

bool Tolerance::accepts(double ours, double base) const {
  if (std::isnan(ours) || std::isnan(base)) return std::isnan(ours) && std::isnan(base);
  if (std::isinf(ours) || std::isinf(base)) return ours == base;
  const double d = std::fabs(ours - base);
  if (abs >= 0 && d <= abs) return true;
  if (rel >= 0 && d <= rel * std::fabs(base)) return true;
  return abs < 0 && rel < 0 && d == 0.0;
}

std::string Tolerance::describe() const {
  if (abs >= 0 && rel >= 0) return fmt::format("abs {:g} or rel {:g}", abs, rel);
  if (abs >= 0) return fmt::format("abs {:g}", abs);
  if (rel >= 0) return fmt::format("rel {:g}", rel);
  return "exact";
}

std::optional<Tolerance> ExperimentConfig::tolerance_for(std::string_view metric) const {
  if (auto it = tolerances.find(metric); it != tolerances.end()) return it->second;
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

Tolerance parse_tolerance(const ConfigTable& t) {
  Tolerance tol;
  if (t.has("abs")) tol.abs = t.number("abs");
  if (t.has("rel")) tol.rel = t.number("rel");
  t.finish();
  if ((t.has("abs") && !(tol.abs >= 0)) || (t.has("rel") && !(tol.rel >= 0))) {
    throw ConfigError(fmt::format("{}: [{}] tolerances must be >= 0", t.file(), t.name()));
  }
  if (!t.has("abs") && !t.has("rel")) {
    throw ConfigError(fmt::format("{}: [{}] needs 'abs' and/or 'rel'", t.file(), t.name()));
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
    for (const auto& k : tol.keys()) c.tolerances[k] = parse_tolerance(tol.table(k));
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

}  // namespace keel::core
