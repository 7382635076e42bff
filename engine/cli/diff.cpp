// keel diff --profile P [ids...] — results/<id>/latest.json against the committed baseline.<P>.json, under
// the tolerances of experiment.toml (exit 1 when a metric leaves its tolerance, 3 when a file cannot be
// read).
import keel.core;
import keel.repro;

#include <fmt/format.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "repro_common.hpp"

namespace keel::cli {

void add_diff_command(CLI::App& app) {
  auto a = std::make_shared<ReproArgs>();
  repro_command(app, "diff", "compare results/<id>/latest.json with its committed baseline", *a, true)
      ->callback([a] {
        int failed_count = 0, unread = 0;
        for (const auto& id : resolve_ids(*a)) {
          try {
            const auto d = repro::diff_against_baseline(load(*a, id), a->results);
            fmt::print("{}\n", repro::format_diff(d));
            failed_count += d.ok() ? 0 : 1;
          } catch (const core::ConfigError&) {
            throw;
          } catch (const std::exception& e) {
            fmt::print("{} [{}]: cannot compare: {}\n\n", id, a->profile, e.what());
            unread += 1;
          }
        }
        // A result or baseline that cannot be read is bad input (exit 3), a metric out of tolerance exit 1.
        if (unread) {
          throw std::invalid_argument(fmt::format(
              "{} experiment(s) could not be compared{}", unread,
              failed_count ? fmt::format(" and {} left their baseline tolerance", failed_count) : ""));
        }
        if (failed_count) {
          throw CommandFailed(fmt::format("{} experiment(s) left their baseline tolerance", failed_count));
        }
      });
}

}  // namespace keel::cli
