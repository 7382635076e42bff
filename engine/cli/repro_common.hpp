// What the reproduction commands share: the folders and profile they read, the experiment ids they act on.
// Included after `import keel.core; import keel.repro;` (DESIGN rule 4).
#pragma once

#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"

namespace keel::cli {

struct ReproArgs {
  std::string profile = "full";
  std::string experiments = "experiments", results = "results";
  std::vector<std::string> ids;
};

// The experiment ids under `dir`; a missing folder is bad input (exit 3), named with the option that sets it.
inline std::vector<std::string> experiment_ids(const std::string& dir) {
  if (!std::filesystem::is_directory(dir))
    throw std::invalid_argument(fmt::format(
        "{}: not a folder (the experiments folder: run keel from the repository root or give --experiments)",
        dir));
  return repro::list_experiments(dir);
}

// The ids given (each checked against the experiment folders), or every experiment.
inline std::vector<std::string> resolve_ids(const ReproArgs& a) {
  auto all = experiment_ids(a.experiments);
  if (a.ids.empty()) return all;
  for (const auto& id : a.ids) {
    bool found = false;
    for (const auto& x : all) found = found || x == id;
    if (!found) {
      throw std::invalid_argument(
          fmt::format("unknown experiment '{}' (known: {})", id, fmt::join(all, " ")));
    }
  }
  return a.ids;
}

inline repro::ExperimentConfig load(const ReproArgs& a, const std::string& id) {
  return repro::ExperimentConfig::load(std::filesystem::path(a.experiments) / id / "experiment.toml",
                                       a.profile);
}

// A reproduction subcommand with --profile, --experiments, --results and (ids) the experiment ids.
inline CLI::App* repro_command(CLI::App& app, const char* name, const char* help, ReproArgs& a, bool ids) {
  auto* c = app.add_subcommand(name, help);
  c->group("Reproduction");
  c->add_option("--profile", a.profile, "quick or full")->capture_default_str();
  c->add_option("--experiments", a.experiments, "experiment folders")->capture_default_str();
  c->add_option("--results", a.results, "results folder")->capture_default_str();
  if (ids) c->add_option("ids", a.ids, "experiment ids (default: all)");
  return c;
}

}  // namespace keel::cli
