#pragma once

#include "study/ch2/world1d_study_common.hpp"

namespace keel::study::ch2 {

// Fig. 2.2 (§2.7.1.1): PCM-Exact, PCM-Heuristic, SCGP and RANSAC against the combinatorial maximum pairwise
// consistent set (eq. 2.5) on simulated 1D worlds.
struct World1DComparison {
  struct Options {
    World1DStudyOptions study;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    World1DStudy study;
    CombinatorialComparison comparison;  // PCM-Exact, PCM-Heuristic, SCGP, RANSAC, in that order
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch2
