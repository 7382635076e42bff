#include "core/config.hpp"
#include "core/parse.hpp"

#include <fmt/format.h>

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <iterator>

namespace keel::core {

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
  // Read once through core::read_whole_file: a directory or an unreadable file says why.
  std::string text;
  if (auto why = read_whole_file(file, text); !why.empty())
    throw ConfigError(fmt::format("{}: {}", file.string(), why));
  toml::table root;
  try {
    root = toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format("{}:{}:{}: TOML syntax error: {}", file.string(), e.source().begin.line,
                                  e.source().begin.column, e.description()));
  }
  return ConfigTable(file.string(), "", convert_table(root, "", file.string()));
}

}  // namespace keel::core
