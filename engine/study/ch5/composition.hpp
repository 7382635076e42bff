#pragma once

#include "study/ch5/composition_setup.hpp"

namespace keel::study::ch5 {

// Fig. 5.4 (§5.5.2): N correlated steps composed end to end; the fraction of Monte-Carlo end poses inside
// each predicted ellipsoid, and the regions' planar shadows.
struct Composition {
  struct Options {
    CompositionSetup setup;  // keep_samples is set by run (the figure draws the samples)
    int region_points = 1500;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    CompositionOutcome composition;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch5
