// Strict TOML configuration. A config is read into a small tree that remembers, for every key, the file,
// table and line it came from; every read marks the key, and finish() rejects keys nobody read ("unknown
// key"). Wrong types and missing keys are errors that name file, table and key. toml++ stays inside
// config.cpp.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace keel::core {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ConfigValue;
using ConfigTableData = std::map<std::string, ConfigValue, std::less<>>;

struct ConfigValue {
  std::variant<std::monostate, std::int64_t, double, bool, std::string, std::vector<ConfigValue>,
               std::shared_ptr<ConfigTableData>>
      data;
  std::string table;  // the TOML table this key was written in, e.g. "profiles.quick"
  int line = 0;       // 1-based line in the file (0 if unknown)
};

// Human-readable type name of a value ("integer", "float", "string", ...).
std::string config_type_name(const ConfigValue& v);

// A strict, read-tracking view over one table.
class ConfigTable {
 public:
  ConfigTable() = default;
  ConfigTable(std::string file, std::string name, std::shared_ptr<const ConfigTableData> data);

  bool has(std::string_view key) const;
  std::vector<std::string> keys() const;

  double number(std::string_view key) const;  // integer or float
  std::int64_t integer(std::string_view key) const;
  std::size_t count(std::string_view key) const;  // an integer >= 1 (sizes, sample counts)
  bool boolean(std::string_view key) const;
  std::string string(std::string_view key) const;
  std::vector<double> numbers(std::string_view key) const;
  std::vector<std::string> strings(std::string_view key) const;
  ConfigTable table(std::string_view key) const;

  double number_or(std::string_view key, double fallback) const;
  std::int64_t integer_or(std::string_view key, std::int64_t fallback) const;
  std::string string_or(std::string_view key, std::string fallback) const;

  // The string at `key` turned into an enum by `from_string` (an area's `<e>_from_string`, docs/DESIGN.md
  // "Naming and errors"); its std::invalid_argument comes back as a ConfigError located at the key, e.g.
  // "x/experiment.toml: [params] key 'method' (line 7): unknown pgo::Method 'lm' (valid: levenberg_marquardt,
  // ...)".
  template <class F>
  auto parse(std::string_view key, F&& from_string) const {
    const std::string text = string(key);
    try {
      return from_string(std::string_view(text));
    } catch (const std::invalid_argument& e) {
      parse_error(key, e.what());
    }
  }
  // Runs value.validate() (an options struct read from this table) and turns its std::invalid_argument into a
  // ConfigError located at the table: "x/experiment.toml: [params]: AlignOptions.shrink = 1.5: must be in (0,
  // 1)".
  template <class T>
  void validate(const T& value) const {
    try {
      value.validate();
    } catch (const std::invalid_argument& e) {
      table_error(e.what());
    }
  }
  // The same, or `fallback` when the key is absent.
  template <class T, class F>
  T parse_or(std::string_view key, F&& from_string, T fallback) const {
    return has(key) ? T(parse(key, from_string)) : fallback;
  }

  // Raw access for generic consumers (the report reads thesis values that may be numbers or strings).
  const ConfigValue& value(std::string_view key) const;

  // Throws ConfigError naming every key of this table (and of sub-tables obtained through table()) never
  // read.
  void finish() const;

  const std::string& file() const { return file_; }
  const std::string& name() const { return name_; }
  // "experiments/x/experiment.toml: [params] key 'steps' (line 7)"
  std::string where(std::string_view key) const;

 private:
  const ConfigValue& get(std::string_view key, std::string_view expected) const;
  [[noreturn]] void parse_error(std::string_view key, std::string_view what) const;
  [[noreturn]] void table_error(std::string_view what) const;
  [[noreturn]] void type_error(std::string_view key, std::string_view expected, const ConfigValue& v) const;
  std::string file_;
  std::string name_;
  std::shared_ptr<const ConfigTableData> data_;
  std::shared_ptr<std::set<std::string, std::less<>>> used_ =
      std::make_shared<std::set<std::string, std::less<>>>();
  std::shared_ptr<std::vector<ConfigTable>> children_ = std::make_shared<std::vector<ConfigTable>>();
};

// Parses a TOML file into a read-tracking root table. Syntax errors name file, line and column.
ConfigTable load_toml(const std::filesystem::path& file);

}  // namespace keel::core
