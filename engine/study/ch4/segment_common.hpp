// What the segment studies (Segments, FirstSegment) share: the methods compared on each segment, the test of
// a method above SBSOS, the worst segment and the run over a data set's segments. Internal to
// engine/study/ch4.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "pgo/optimize.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "study/ch4/segments.hpp"

namespace keel::study::ch4 {

struct SegmentMethod {
  const char* key;
  const char* label;
  const char* color;
  MethodOutcome SegmentOutcome::* member;
};

const std::vector<SegmentMethod>& segment_methods();

// A local minimum: the method's cost above the certified SBSOS cost by more than 1e-4 relative (χ² units, at
// least 1e-4 absolute).
bool above_sbsos(const SegmentOutcome& s, const MethodOutcome& m);

// The segment where LM from a random initialization ends farthest above the certified cost.
std::size_t worst_segment(const SegmentStudyOutcome& out);

// The segments a study runs, in one thread with a progress bar: DSDP calls are serialised, so a second
// thread would only wait for the lock and the per-segment times (the thesis's comparison) would include that
// wait.
SegmentStudyOutcome run_segments(const PlanarDataset& data, const SegmentStudyOptions& o,
                                 const repro::RunContext& context);

}  // namespace keel::study::ch4
