// keel prose-check [ids...] — fail on numbers typed by hand in the discussions (thesis numbers and settings
// aside; repro/prose.hpp).
import keel.core;
import keel.repro;

#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "repro_common.hpp"

namespace keel::cli {

void add_prose_check_command(CLI::App& app) {
  auto* prose = app.add_subcommand(
      "prose-check", "fail on numbers typed by hand in the discussions (thesis numbers and settings aside)");
  prose->group("Reproduction");
  auto prose_ids = std::make_shared<std::vector<std::string>>();
  prose->add_option("ids", *prose_ids, "experiments (default: all)");
  prose->callback([prose_ids] {
    const auto ids = prose_ids->empty() ? experiment_ids("experiments") : *prose_ids;
    std::size_t count = 0;
    for (const auto& id : ids) {
      const auto cfg =
          repro::ExperimentConfig::load(fmt::format("experiments/{}/experiment.toml", id), "full");
      for (const auto& p : repro::prose_number_problems(cfg)) fmt::print("{}\n", p), ++count;
    }
    if (count > 0) throw CommandFailed(fmt::format("{} number(s) typed by hand in the discussions", count));
    fmt::print("no number typed by hand in {} discussion(s)\n", ids.size());
  });
}

}  // namespace keel::cli
