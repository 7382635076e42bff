// paper/REPRODUCTION.md: one section per thesis table/figure with the thesis's published values or claim
// (from each experiment.toml's [thesis]), our values (results/<id>/latest.json), a verdict and the figures.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "repro/experiment_config.hpp"

namespace keel::repro {

struct ReportOptions {
  std::filesystem::path experiments_dir = "experiments";
  std::filesystem::path results_dir = "results";
  std::filesystem::path paper_dir = "paper";
  std::string profile = "full";
  std::vector<std::string> ids;  // empty: every experiment folder
  // Read results/<id>/baseline.<profile>.json (committed) instead of latest.json: the report a clone can
  // regenerate. A section is then stale only where its experiment.toml changed since the bless.
  bool from_baseline = false;
};

// A section also shows results/<id>/side_by_side.json where it exists: a measurement beside other tools
// (peers built outside the repository), made by a bench script and committed, e.g.
// bench/side_by_side/robust.py
// --summary-json for ext_robust_backend. Its format, every value a string written by that script:
//   {"title": "...", "what": "how it was measured", "provenance": {"keel_commit": "...", ...},
//    "tables": [{"caption": "...", "header": ["...", ...], "rows": [["...", ...], ...]}, ...]}
// "title" and a non-empty "tables" are required, each row as wide as its header; "what", "provenance" and
// "caption" are optional.
//
// Writes <paper_dir>/REPRODUCTION.md atomically and returns its path. Throws on malformed [thesis] tables and
// on a malformed side_by_side.json, naming the file and the field.
std::filesystem::path write_report(const ReportOptions& options);

// The literal numbers of an experiment's `discussion` that are neither a thesis number ([thesis] values, or a
// number in its claim or source) nor a setting (a number of [params] with the profile laid over it), one
// message each with its context: such a number must come from the results through a placeholder
// (core/prose.hpp).
std::vector<std::string> prose_number_problems(const ExperimentConfig& config);

// Every experiment id (folder with an experiment.toml), sorted.
std::vector<std::string> list_experiments(const std::filesystem::path& experiments_dir);

}  // namespace keel::repro
