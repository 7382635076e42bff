#pragma once

#include "study/ch4/segment_common.hpp"
#include "study/ch4/segments_study.hpp"

namespace keel::study::ch4 {

// Fig. 4.1 (§4.6): the first segment of CityTrees10000 (430 poses, 40 landmarks) by SBSOS and by LM from the
// random start the figure shows.
struct FirstSegment {
  using Options = Segments::Options;
  struct Outcome {
    Options options;
    SegmentOutcome segment;
    pgo::Estimate2D start;  // LM's random start on the segment, in the frame of its pose 0
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch4
