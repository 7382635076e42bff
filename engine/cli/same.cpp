// keel same A.json B.json — exit 0 when two result files agree except for provenance and timings.
import keel.core;
import keel.repro;

#include <fmt/format.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "repro_common.hpp"

namespace keel::cli {

void add_same_command(CLI::App& app) {
  auto* same = app.add_subcommand("same", "exit 0 when two result files agree except for provenance");
  same->group("Reproduction");
  auto files = std::make_shared<std::vector<std::string>>();
  same->add_option("files", *files, "two result files")->required()->expected(2);
  same->callback([files] {
    std::string why;
    const bool same = [&] {
      try {
        return repro::same_results((*files)[0], (*files)[1], &why);
      } catch (const std::runtime_error& e) {  // a file missing or not JSON: bad input, not a difference
        throw std::invalid_argument(e.what());
      }
    }();
    if (same) {
      fmt::print("identical (provenance aside)\n");
      return;
    }
    fmt::print("results differ: {}\n", why);
    throw CommandFailed("the result files differ");
  });
}

}  // namespace keel::cli
