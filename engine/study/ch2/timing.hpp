#pragma once

#include "study/ch2/world1d_study_common.hpp"

namespace keel::study::ch2 {

// Fig. 2.3 (§2.7.1.2): the median selection time of every selector against the number of measurements m.
struct Timing {
  struct Options {
    TimingSweepOptions sweep;
    std::vector<double> sizes;  // as given (the series of the sweep)
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    TimingSweep sweep;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch2
