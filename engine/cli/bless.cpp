// keel bless --profile P ids... — latest.json becomes the baseline (numbers only), on purpose.
import keel.core;
import keel.repro;

#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "repro_common.hpp"

namespace keel::cli {

void add_bless_command(CLI::App& app) {
  auto a = std::make_shared<ReproArgs>();
  repro_command(app, "bless", "write latest.json as the baseline (numbers only; on purpose)", *a, true)
      ->callback([a] {
        if (a->ids.empty()) {
          throw CLI::ValidationError(
              "ids", "bless needs explicit experiment ids (baselines change only on purpose)");
        }
        for (const auto& id : resolve_ids(*a)) {
          repro::bless(load(*a, id), a->results);
          fmt::print("blessed {}\n", repro::baseline_path(a->results, id, a->profile).string());
        }
      });
}

}  // namespace keel::cli
