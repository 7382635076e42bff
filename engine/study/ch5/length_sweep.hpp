#pragma once

#include "study/ch5/composition_setup.hpp"

namespace keel::study::ch5 {

// Fig. 5.8 (§5.9.1): the inside fractions against the number of composed poses N, every N on the same streams
// (common random numbers).
struct LengthSweep {
  struct Options {
    CompositionSetup setup;  // steps is set per sweep point
    int steps_min = 1, steps_max = 50, steps_stride = 1;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    std::vector<double> steps;                                  // N of each sweep point
    std::vector<double> ssc, ssc_independent, lie_independent;  // inside fractions at levels[0], one per N
    std::vector<double> lie_joint, lie_fourth_order;
    std::vector<double> steps_joint_fourth_order, lie_joint_fourth_order;  // where it was evaluated
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch5
