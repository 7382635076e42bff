#pragma once

#include "study/ch5/composition.hpp"
#include "study/ch5/composition_setup.hpp"

namespace keel::study::ch5 {

// Fig. 5.7 (§5.8.1, eqs. 5.60–5.62): Fig. 5.4's SSC head-to-tail prediction converted to the Lie algebra by
// the unscented transform, against the true spread of the composed poses.
struct UnscentedSsc {
  using Options = Composition::Options;
  struct Outcome {
    Options options;
    CompositionOutcome composition;
    SscConversion conversion;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch5
