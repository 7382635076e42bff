// Figs. 4.4–4.5 (§4.6): SBSOS-SLAM against Levenberg–Marquardt on 100-pose segments of Manhattan3500 — thin
// driver over keel::sos::run_segment_study; metrics, checks and figures from
// experiments/common/sos_segments.hpp.
import keel.core;
import keel.repro;
import keel.lie;
import keel.sos;

#include <fmt/format.h>

#include <string>
#include <vector>

#include "common/sos_segments.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace sos = keel::sos;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const sos::SegmentStudyOutcome out =
        keel::experiments::run_segments(ex, "Manhattan3500 segments").outcome;
    auto& r = ex.results();
    keel::experiments::record_segment_study(r, out, false);
    r.figure(keel::experiments::segment_error_figure("ch4_fig4_4_m3500_errors.png",
                                                     "Fig. 4.4: pose error on Manhattan3500 segments", out));
    r.figure(keel::experiments::segment_example_figure(
        "ch4_fig4_5_m3500_example.png", "Fig. 4.5: SBSOS-SLAM vs LM on a Manhattan3500 segment", out, r));
  });
}
