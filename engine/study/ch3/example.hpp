#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "sim/alignment_world.hpp"
#include "sim/hull_world.hpp"
#include "sim/terrain.hpp"
#include "study/ch3/comparison.hpp"

namespace keel::study::ch3 {

// Fig. 3.4 (§3.7): one simulated world of Table 3.1 (world `world_index` of its seed) and the four methods'
// estimates.
struct Example {
  struct Options {
    AlignmentStudyOptions study;  // one world, certify off
    std::uint64_t world_index = 0;
    double field_grid_spacing = 1.0;  // the grid (m) the noiseless field is drawn on
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    AlignmentStudyOutcome study;
    sim::AlignmentWorld world;  // the same world, regenerated for the figure
    sim::LawnMower shape;       // its query's lawn-mower
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch3
