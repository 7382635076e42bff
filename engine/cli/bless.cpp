// keel bless --profile P ids... — latest.json becomes the baseline (numbers only), on purpose.
import keel.core;
import keel.repro;
import keel.app;

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "repro_common.hpp"

namespace keel::cli {

void add_bless_command(CLI::App& app) {
  auto a = std::make_shared<ReproArgs>();
  auto allow_dirty = std::make_shared<bool>(false);
  auto* c =
      repro_command(app, "bless", "write latest.json as the baseline (numbers only; on purpose)", *a, true);
  c->add_flag("--allow-dirty", *allow_dirty,
              "bless a result of uncommitted code (the baseline then names no commit; marked, and the report "
              "says so)");
  c->callback([a, allow_dirty] {
    if (a->ids.empty()) {
      throw CLI::ValidationError("ids",
                                 "bless needs explicit experiment ids (baselines change only on purpose)");
    }
    const auto ids = resolve_ids(*a);
    // Before any baseline is written: every result exists (bad input otherwise) and every folder is writable.
    for (const auto& id : ids) {
      const auto latest = repro::latest_path(a->results, id);
      if (!std::filesystem::is_regular_file(latest))
        throw std::invalid_argument(
            fmt::format("{}: not found (run the experiment before blessing it)", latest.string()));
      app::check_folder_writable("--results", repro::baseline_path(a->results, id, a->profile).parent_path());
    }
    for (const auto& id : ids) {
      const bool dirty = repro::bless(load(*a, id), a->results, *allow_dirty);
      fmt::print("blessed {}\n", repro::baseline_path(a->results, id, a->profile).string());
      if (dirty) {
        fmt::print(
            stderr,
            "warning: {} was blessed from uncommitted code (--allow-dirty): its baseline names no commit "
            "and the report marks it\n",
            id);
      }
    }
  });
}

}  // namespace keel::cli
