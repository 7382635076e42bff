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
#include "study/ch3/sensitivity.hpp"

namespace keel::study::ch3 {

// Beyond Table 3.1: a grid of regimes fixed in the config before the run, every combination of the feature
// field's length scale (bump σ range), the feature noise and the query's size. Each cell is one comparison on
// the same worlds (streams from base 0), so cells differ by their parameters, not by their random worlds.
struct RegimeGrid {
  using Point = Sensitivity::Point;
  struct Options {
    AlignmentStudyOptions study;  // certify off; its world is the base of every cell (bump count scaling)
    std::vector<std::pair<double, double>> scales;  // bump σ ranges (m)
    std::vector<double> noises, sizes;
    static Options read(const core::ConfigTable& p);
    // The cells, query size outermost, then noise, then σ range (fastest).
    [[nodiscard]] std::vector<Point> cells() const;
    // As Sensitivity::Options::world_at: the bump count scaled so every length scale covers the area alike.
    [[nodiscard]] sim::AlignmentWorldOptions world_at(const Point& p) const;
  };
  struct Outcome {
    Options options;
    std::vector<AlignmentStudyOutcome> cells;  // [cell], in Options::cells() order
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch3
