#pragma once

#include "study/ch5/pair_correlation.hpp"

namespace keel::study::ch5 {

// Table 5.2 and Figs. 5.10–5.14 (f–g): the normalized error of the proposed relative pose against SSC
// tail-to-tail. The same run as PairCorrelation.
struct PairsVsSsc {
  using Options = PairCorrelation::Options;
  using Outcome = PairCorrelation::Outcome;
  static Outcome run(const Options& options, const repro::RunContext& context) {
    return PairCorrelation::run(options, context);
  }
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch5
