#pragma once

#include "study/ch2/world1d_study_common.hpp"

namespace keel::study::ch2 {

// Beyond Fig. 2.2: PCM-Heuristic's and PCM-Exact's rate of returning a set of the combinatorial maximum's
// size as the outliers are drawn closer to the true state, every density on the same streams.
struct DensitySweep {
  struct Options {
    World1DStudyOptions study;            // only the combinatorial search and PCM run
    std::vector<double> ranges;           // outlier mean ranges R
    double reference_heuristic_rate = 0;  // Fig. 2.2's PCM-Heuristic rate, drawn as a reference line
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    std::vector<double> heuristic, exact, max_size;  // one per range
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch2
