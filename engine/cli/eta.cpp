// keel eta --profile P [ids...] — each experiment's baseline wall time in seconds (progress estimates of
// scripts/reproduce).
import keel.core;
import keel.repro;

#include <fmt/format.h>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "repro_common.hpp"

namespace keel::cli {

namespace {

// Reads provenance.wall_time_s from the baseline without a JSON library: the field is written by keel itself.
double baseline_wall(const ReproArgs& a, const std::string& id) {
  std::ifstream in(repro::baseline_path(a.results, id, a.profile));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto pos = text.find("\"wall_time_s\":");
  if (pos == std::string::npos) return -1;
  return std::strtod(text.c_str() + pos + 14, nullptr);
}

}  // namespace

void add_eta_command(CLI::App& app) {
  auto a = std::make_shared<ReproArgs>();
  repro_command(app, "eta", "baseline wall time per experiment (seconds)", *a, true)->callback([a] {
    for (const auto& id : resolve_ids(*a)) fmt::print("{} {:.3f}\n", id, baseline_wall(*a, id));
  });
}

}  // namespace keel::cli
