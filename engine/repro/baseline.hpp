// Comparing a run (results/<id>/latest.json) with its committed baseline
// (results/<id>/baseline.<profile>.json) under the per-metric tolerances of experiment.toml, and blessing a
// run into a new baseline on purpose.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "repro/experiment_config.hpp"

namespace keel::repro {

struct DiffRow {
  std::string name;       // metric name, "series[i]" for a series element, "check: ..." for a claim check
  std::string baseline;   // formatted
  std::string latest;     // formatted
  std::string tolerance;  // "abs 0.01", "exact", ...
  bool ok = true;
  std::string note;  // why not ok
};

struct DiffResult {
  std::string id, profile;
  std::vector<DiffRow> rows;          // one per metric and per series (its worst element), plus problems
  std::vector<std::string> warnings;  // e.g. the config changed since the baseline was blessed
  bool ok() const;
  int failures() const;
};

// Paths of an experiment's results. `root` is the repository root.
std::filesystem::path latest_path(const std::filesystem::path& results_dir, const std::string& id);
std::filesystem::path baseline_path(const std::filesystem::path& results_dir, const std::string& id,
                                    const std::string& profile);

// Throws std::runtime_error with a message naming the missing file (and the command that creates it).
[[nodiscard]] DiffResult diff_against_baseline(const ExperimentConfig& config,
                                               const std::filesystem::path& results_dir);

// Copies latest.json to baseline.<profile>.json without the figure data (baselines hold numbers only).
// Refuses a result whose provenance names no commit (git_sha "-dirty" or unknown: see clean_commit) unless
// allow_dirty, which marks the baseline ("blessed_dirty": true, shown by the report). Returns whether it
// blessed such a result.
bool bless(const ExperimentConfig& config, const std::filesystem::path& results_dir,
           bool allow_dirty = false);

// True when the two result files agree in everything but provenance and timings (wall time, threads). `why`
// gets the first difference. Used by the determinism test (1 thread vs 2 threads).
[[nodiscard]] bool same_results(const std::filesystem::path& a, const std::filesystem::path& b,
                                std::string* why);

// Renders a DiffResult as an aligned text table.
[[nodiscard]] std::string format_diff(const DiffResult& d);

}  // namespace keel::repro
