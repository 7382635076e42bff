// The chapter-3 studies (§3.7, §3.8), one per experiment: AlignmentComparison (Table 3.1, and beyond the
// thesis the certified optimum over SO(2) of round 0 and the SDP check of SOConvHull), Sensitivity
// (Table 3.1's methods against feature noise and query size), Example (Fig. 3.4) and HullSubstitute (Fig. 3.5
// on synthetic hull surveys). Each has the study shape of repro/run.hpp; the machinery is comparison.hpp's.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "sim/alignment_world.hpp"
#include "sim/hull_world.hpp"
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
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Beyond Table 3.1: the methods against feature noise and query size, one comparison per sweep point on the
// same worlds (streams from base 0 at every point).
struct Sensitivity {
  struct Options {
    AlignmentStudyOptions study;  // certify off
    std::vector<double> noises, sizes;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    // One comparison per distinct (feature noise, query size); the point the two sweeps share runs once.
    std::map<std::pair<double, double>, AlignmentStudyOutcome> points;
    [[nodiscard]] const AlignmentStudyOutcome& at(double noise, double size) const;
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
