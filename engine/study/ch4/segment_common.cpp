#include "study/ch4/segment_common.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/statistics.hpp"
#include "pgo/options.hpp"

namespace keel::study::ch4 {

using repro::Figure;
using repro::Panel;
using repro::Results;
using repro::RunContext;

const std::vector<SegmentMethod>& segment_methods() {
  static const std::vector<SegmentMethod> m{
      {"sbsos", "SBSOS (certified)", "C0", &SegmentOutcome::sbsos},
      {"lm_random", "LM, random init", "C3", &SegmentOutcome::lm_random},
      {"lm_odometry", "LM, odometry init", "C2", &SegmentOutcome::lm_odometry}};
  return m;
}

bool above_sbsos(const SegmentOutcome& s, const MethodOutcome& m) {
  return m.cost > s.sbsos.cost + 1e-4 * std::max(1.0, s.sbsos.cost);
}

std::size_t worst_segment(const SegmentStudyOutcome& out) {
  std::size_t pick = 0;
  double worst = -1.0;
  for (std::size_t k = 0; k < out.segments.size(); ++k) {
    const auto& s = out.segments[k];
    if (s.failed) continue;
    const double excess = s.lm_random.cost - s.sbsos.cost;
    if (excess > worst) worst = excess, pick = k;
  }
  return pick;
}

SegmentStudyOutcome run_segments(const PlanarDataset& data, const SegmentStudyOptions& o,
                                 const RunContext& context) {
  const int n = static_cast<int>(data.graph.poses.size());
  int count = n >= o.segment_length ? (n - o.segment_length) / o.stride + 1 : 0;
  if (o.max_segments > 0) count = std::min(count, o.max_segments);
  const RunContext one = context.with_threads(1);
  core::Progress progress = one.progress(static_cast<std::size_t>(count));
  SegmentStudyOutcome out =
      run_segment_study(data.graph, data.truth, data.truth_landmarks, o, one, &progress);
  progress.finish();
  return out;
}

}  // namespace keel::study::ch4
