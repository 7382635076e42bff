// Figs. 4.2–4.3 (§4.6): SBSOS-SLAM against Levenberg–Marquardt on 100-pose segments of CityTrees10000
// (landmark SLAM, eq. 4.12) — thin driver over keel::sos::run_segment_study; metrics, checks and figures from
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
        keel::experiments::run_segments(ex, "CityTrees10000 segments").outcome;
    auto& r = ex.results();
    keel::experiments::record_segment_study(r, out, true);
    r.figure(keel::experiments::segment_error_figure("ch4_fig4_3_citytrees_errors.png",
                                                     "Fig. 4.3: pose error on CityTrees10000 segments", out));
    r.figure(keel::experiments::segment_example_figure(
        "ch4_fig4_2_citytrees_example.png", "Fig. 4.2: SBSOS-SLAM vs LM on a CityTrees10000 segment", out,
        r));
  });
}
