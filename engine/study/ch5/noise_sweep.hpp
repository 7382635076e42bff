#pragma once

#include "study/ch5/composition_setup.hpp"

namespace keel::study::ch5 {

// Fig. 5.9 (§5.9.1): the inside fractions against rotation noise (σt fixed) and against translation noise (σr
// fixed); each sweep on its own streams, common within it.
struct NoiseSweep {
  struct Options {
    CompositionSetup setup;  // sigma_t and sigma_r are set per sweep point
    double fixed_sigma = 3.0;
    std::vector<double> sigmas;
    static Options read(const core::ConfigTable& p);
  };
  struct Sweep {
    std::vector<double> ssc, ssc_independent, lie_independent, lie_joint, lie_fourth_order,
        lie_joint_fourth_order;  // one per σ
  };
  struct Outcome {
    Options options;
    Sweep rotation, translation;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch5
