// One experiment's experiment.toml resolved for one profile, and the per-metric tolerances of its baselines.
// The strict reader (core::ConfigTable) is the foundation's; what an experiment file holds is the
// reproduction framework's.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/config.hpp"

namespace keel::repro {

using core::ConfigError;
using core::ConfigTable;

// Per-metric tolerance against a committed baseline: passes if |ours - base| <= abs or <= rel * |base|.
struct Tolerance {
  double abs = -1.0;  // < 0: not set
  double rel = -1.0;  // < 0: not set
  bool accepts(double ours, double base) const;
  std::string describe() const;
};

// One experiment's experiment.toml, resolved for one profile.
struct ExperimentConfig {
  std::filesystem::path file;
  std::string id;           // = folder name = results/<id> = report section
  std::string title;        // one line
  std::string reproduces;   // "Fig. 5.4 (§5.5.2)"
  std::string description;  // what the experiment does and how
  std::string discussion;   // our reading of the results against the thesis (report text)
  std::string
      params_from;  // a variant's base experiment (docs/DESIGN.md), whose driver it may run; else empty
  // Why the experiment cannot be sharded (core/shard.hpp): its work is not a set of independent trials (one
  // solve, one worked example). Empty for a Monte-Carlo experiment, which --slice/--merge can split.
  std::string runs_whole;
  std::string profile;
  std::vector<std::string> profiles;  // every profile the file defines
  std::uint64_t seed = 0;
  std::uint64_t hash = 0;  // FNV-1a of the file bytes and the profile name
  ConfigTable params;      // [params] with [profiles.<profile>] laid over it
  ConfigTable thesis;      // [thesis]: source, claim, values, agreement
  std::map<std::string, Tolerance, std::less<>> tolerances;  // [tolerance]; key "default" applies to the rest
  std::optional<Tolerance> tolerance_for(std::string_view metric) const;

  // Loads and validates: unknown top-level keys, a missing profile, an id that differs from the folder name,
  // and malformed tolerances are errors naming the file and key.
  static ExperimentConfig load(const std::filesystem::path& file, const std::string& profile);
};

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = 0xcbf29ce484222325ull);

}  // namespace keel::repro
