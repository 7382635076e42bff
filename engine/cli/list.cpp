// keel list — the experiment ids (the folders of experiments/ with an experiment.toml).
import keel.core;
import keel.repro;

#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "repro_common.hpp"

namespace keel::cli {

void add_list_command(CLI::App& app) {
  auto a = std::make_shared<ReproArgs>();
  repro_command(app, "list", "list the experiment ids", *a, false)->callback([a] {
    for (const auto& id : experiment_ids(a->experiments)) fmt::print("{}\n", id);
  });
}

}  // namespace keel::cli
