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
  // Discrete decisions (docs/GRADING.md "Results on another machine"): `flips` decisions of the `of` units (a
  // metric holding their count D, e.g. "datasets") may flip, so a rate averaged over them may move by flips /
  // D. Resolved into `abs` by resolve_flips() against the baseline's count. flips < 0: not set.
  double flips = -1.0;
  std::string of;
  // A diagnostic (docs/GRADING.md "Diagnostics"): a value read at a solver's stopping point short of its own
  // convergence test, which follows the arithmetic path there and may move by any amount within its meaning
  // on another machine. Non-empty: why. Shown in the diff beside the baseline, never a failure.
  std::string diagnostic;
  bool accepts(double ours, double base) const;
  std::string describe() const;
  // This tolerance with abs raised to flips / count (count = the baseline's value of metric `of`).
  Tolerance resolve_flips(double count) const;
};

// The wildcard [tolerance] key that covers `name`: "*." and its last dot-separated part up to an '@'
// ("dataset.pcm_exact.tpr" and "dcs.tpr@0.11" -> "*.tpr").
std::string tolerance_group(std::string_view name);

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
  // [tolerance]: per metric or series name; "*.<last>" for every name whose last dot-separated part (up to an
  // '@') is <last>; "default" for the rest. An entry with profile = "<name>" belongs to that profile only.
  std::map<std::string, Tolerance, std::less<>> tolerances;
  std::optional<Tolerance> tolerance_for(std::string_view metric) const;

  // Loads and validates: unknown top-level keys, a missing profile, an id that differs from the folder name,
  // and malformed tolerances are errors naming the file and key.
  static ExperimentConfig load(const std::filesystem::path& file, const std::string& profile);
};

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = 0xcbf29ce484222325ull);

}  // namespace keel::repro
