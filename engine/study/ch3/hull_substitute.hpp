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
