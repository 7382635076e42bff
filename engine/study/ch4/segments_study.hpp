#pragma once

#include "study/ch4/segment_common.hpp"

namespace keel::study::ch4 {

// Figs. 4.2–4.5 (§4.6): every segment of a planar data set by SBSOS with its certificate and by LM from a
// random and from an odometry start; errors against ground truth, costs on the thesis's cost.
struct Segments {
  struct Options {
    PlanarDatasetFiles data;
    SegmentStudyOptions study;
    std::string errors_figure, errors_title;    // the error CDFs (Fig. 4.3 / 4.4): file name and title
    std::string example_figure, example_title;  // the worst segment drawn (Fig. 4.2 / 4.5)
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    bool landmarks = false;  // the data set has landmarks (their errors are recorded)
    SegmentStudyOutcome study;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch4
