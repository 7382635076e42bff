// Table 5.2 and Figs. 5.10–5.14 (f–g), §5.9.2: normalized relative-pose covariance error on Manhattan3500,
// proposed vs SSC tail-to-tail — thin driver over keel.graph / keel.pgo / keel.cov / keel.lie.
import keel.core;
import keel.repro;
import keel.lie;
import keel.graph;
import keel.pgo;
import keel.cov;
import keel.datasets;

#include <fmt/format.h>

#include <string>

#include "common/solved_pairs.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace lie = keel::lie;
using keel::experiments::pair_panel;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto s = keel::experiments::run_solved_pairs(ex);
    auto& r = ex.results();
    const auto lie_st = keel::experiments::record_statistics(r, s, &lie::PairRecord::normalized_error_lie,
                                                             "norm_cov_error.lie");
    const auto ssc_st = keel::experiments::record_statistics(r, s, &lie::PairRecord::normalized_error_ssc,
                                                             "norm_cov_error.ssc");

    const auto raw = keel::experiments::record_statistics(
        r, s, &lie::PairRecord::normalized_error_ssc_raw_angles, "norm_cov_error.ssc_raw_angles");
    const auto floor = keel::experiments::record_statistics(r, s, &lie::PairRecord::normalized_mc_floor,
                                                            "norm_cov_error.mc_floor");
    (void)raw;
    r.check(
        "the proposed relative pose is within 1.5× of the Monte-Carlo sampling floor (first order is "
        "adequate)",
        lie_st.mean < 1.5 * floor.mean,
        fmt::format("mean normalized ε: proposed {:.4g}, SSC {:.4g}, sampling floor {:.4g}", lie_st.mean,
                    ssc_st.mean, floor.mean));
    std::size_t lie_lower = 0;
    for (const auto& rec : s.records)
      lie_lower += rec.normalized_error_lie < rec.normalized_error_ssc ? 1 : 0;
    r.check("the proposed relative pose has a several-fold lower normalized covariance error than SSC (≥ 3×)",
            ssc_st.mean > 3.0 * lie_st.mean,
            fmt::format("mean normalized ε: proposed {:.4g}, SSC {:.4g} (ratio {:.2f}; thesis 5.8)",
                        lie_st.mean, ssc_st.mean, ssc_st.mean / lie_st.mean));
    r.check("the proposed method is better than SSC for most pairs (> 50 %)",
            2 * lie_lower > s.records.size(), fmt::format("{} of {} pairs", lie_lower, s.records.size()));

    for (int k : s.figure_offsets) {
      const auto sk = lie::pair_statistics(s.records, &lie::PairRecord::normalized_error_ssc, k);
      if (sk.count == 0) continue;
      const double vmax = sk.mean + 2.0 * sk.std;  // thesis: dark orange = 2 std above the mean (SSC)
      repro::Figure f;
      f.file = fmt::format("{}_offset{}.png", ex.id(), k);
      f.title = fmt::format("Manhattan3500, pose pairs at offset {} (cf. Figs. 5.10–5.14 f–g)", k);
      f.width = 12.0;
      f.height = 5.5;
      f.panels.push_back(pair_panel(s, k, &lie::PairRecord::normalized_error_lie,
                                    "(f) normalized ε, proposed", "Oranges", vmax));
      f.panels.push_back(
          pair_panel(s, k, &lie::PairRecord::normalized_error_ssc, "(g) normalized ε, SSC", "Oranges", vmax));
      r.figure(f);
    }
  });
}
