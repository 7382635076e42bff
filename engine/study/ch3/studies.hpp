// The chapter-3 studies (§3.7, §3.8), one per experiment: AlignmentComparison (Table 3.1, and beyond the
// thesis the certified optimum over SO(2) of round 0 and the SDP check of SOConvHull), Sensitivity
// (Table 3.1's methods against feature noise, query size and length scale, one axis at a time), RegimeGrid
// (every combination of the three), TerrainComparison (Table 3.1 on real terrain), Example (Fig. 3.4) and
// HullSubstitute (Fig. 3.5 on synthetic hull surveys). Each has the study shape of repro/run.hpp; the
// machinery is comparison.hpp's.
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

// Table 3.1 (§3.7): the four convex alignment methods on simulated worlds, errors summarised as the thesis
// does (median; std after 1.5·IQR fences); beyond the thesis, the certificate of round 0 on every world.
struct AlignmentComparison {
  struct Options {
    AlignmentStudyOptions study;
    double near_gap = 1e-3;  // certificate.within_<gap>_rate: round 0's answer this close to the optimum
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    AlignmentStudyOutcome study;
    // [world] its spatial block, for worlds that share data (overlapping terrain windows: the paired
    // comparisons then take one value per block); empty when the worlds are independent draws.
    std::vector<std::size_t> blocks;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Beyond Table 3.1: the methods against feature noise, query size and the feature field's length scale, one
// comparison per sweep point on the same worlds (streams from base 0 at every point).
struct Sensitivity {
  // One sweep point: feature noise, the query square's side, and the field's length scale (bump σ range, m).
  struct Point {
    double noise = 0, size = 0, sigma_min = 0, sigma_max = 0;
    [[nodiscard]] auto key() const { return std::tuple(noise, size, sigma_min, sigma_max); }
    bool operator<(const Point& o) const { return key() < o.key(); }
  };
  struct Options {
    AlignmentStudyOptions study;  // certify off; its world is the base point of every sweep
    std::vector<double> noises, sizes;
    std::vector<std::pair<double, double>> scales;  // bump σ ranges (m); may be empty
    static Options read(const core::ConfigTable& p);
    // The sweeps: axis 0 the noises, 1 the sizes, 2 the scales, each at the base values of the other two.
    [[nodiscard]] std::vector<Point> axis(int which) const;
    // The world options of a point. The bump count is scaled by E[σ²] of the base range over that of the
    // point's (E[σ²] = (a² + ab + b²)/3 for σ ~ U[a, b]), so every length scale covers the area alike.
    [[nodiscard]] sim::AlignmentWorldOptions world_at(const Point& p) const;
  };
  struct Outcome {
    Options options;
    // One comparison per distinct point; the base point the sweeps share runs once.
    std::map<Point, AlignmentStudyOutcome> points;
    [[nodiscard]] const AlignmentStudyOutcome& at(const Point& p) const;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

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

// Fig. 3.5 (§3.8) on a SUBSTITUTE: synthetic hull surveys aligned by standardised DVL curvature features in
// the known-depth case, with the depth gate and (optionally) without it.
struct HullSubstitute {
  struct Options {
    HullStudyOptions study;
    bool compare_without_gate = false;
    double relocalised_within = 1.0;  // m: a query counts as re-localised within this translation error
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    HullStudyOutcome gated;
    std::optional<HullStudyOutcome> ungated;
    sim::HullWorld world0;  // world 0, regenerated for the figure
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch3
