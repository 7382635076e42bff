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
#include "study/ch3/alignment_comparison.hpp"
#include "study/ch3/comparison.hpp"

namespace keel::study::ch3 {

// Beyond the thesis, a second Table 3.1 on real terrain (a substitute for §3.8's field data): Table 3.1's
// comparison and certificate on survey pairs cut from a real elevation grid (sim/terrain.hpp: elevation,
// slope and curvature standardised over the reference), with the errors also read against the terrain's local
// roughness under the query.
struct TerrainComparison {
  struct Options {
    AlignmentComparison::Options table;  // table.study.world: the survey geometry (m) and noises on the grid
    std::string dataset, grid_file;      // the grid: a file of datasets/manifest.toml
    std::size_t roughness_bins = 3;      // the worlds split at the roughness quantiles into this many groups
    double length_unit = 1.0;            // m: positions are aligned and scored in this unit (errors in it)
    double block_size = 0;               // m: the side of the square tiles that group worlds into blocks
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    AlignmentComparison::Outcome table;
    std::vector<double> roughness, centre_x, centre_y;  // [world]: TerrainWorld's
    sim::TerrainGrid grid;                              // the grid (for the figure)
    sim::TerrainWorld world0;                           // world 0 (for the figure)
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch3
