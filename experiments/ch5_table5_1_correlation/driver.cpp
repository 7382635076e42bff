// Table 5.1 and Figs. 5.10–5.14 (a–e), §5.9.2: relative-pose covariance error on Manhattan3500 with and
// without the cross-covariance of the two poses — thin driver over keel.graph / keel.pgo / keel.cov /
// keel.lie.
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
    const auto joint =
        keel::experiments::record_statistics(r, s, &lie::PairRecord::error_joint, "cov_error.joint");
    const auto ind = keel::experiments::record_statistics(r, s, &lie::PairRecord::error_independent,
                                                          "cov_error.independent");

    std::size_t joint_lower = 0;
    for (const auto& rec : s.records) joint_lower += rec.error_joint < rec.error_independent ? 1 : 0;
    r.metric("cov_error.ratio", ind.mean / joint.mean);  // mean ε ignoring correlation / mean ε with it
    r.metric("joint_better_rate",
             static_cast<double>(joint_lower) /
                 static_cast<double>(s.records.size()));  // pairs where joint ε is lower
    r.check("ignoring correlation raises the mean covariance error by more than two orders of magnitude",
            ind.mean > 100.0 * joint.mean,
            fmt::format("mean ε: joint {:.4g}, ignoring correlation {:.4g} (ratio {:.0f}; thesis 305)",
                        joint.mean, ind.mean, ind.mean / joint.mean));
    r.check("the joint prediction has the lower error for (almost) every pair (≥ 99 %)",
            joint_lower >= 0.99 * static_cast<double>(s.records.size()),
            fmt::format("{} of {} pairs", joint_lower, s.records.size()));

    for (int k : s.figure_offsets) {
      const auto ik = lie::pair_statistics(s.records, &lie::PairRecord::error_independent, k);
      if (ik.count == 0) continue;
      const double vmax =
          ik.mean + 2.0 * ik.std;  // thesis: dark red = 2 std above the mean (correlation ignored)
      repro::Figure f;
      f.file = fmt::format("{}_offset{}.png", ex.id(), k);
      f.title = fmt::format("Manhattan3500, pose pairs at offset {} (cf. Figs. 5.10–5.14 a–e)", k);
      f.rows = 2;
      f.cols = 3;
      f.width = 16.0;
      f.height = 10.0;
      f.panels.push_back(pair_panel(s, k, &lie::PairRecord::corr_x, "(a) correlation x", "Greys", 1.0));
      f.panels.push_back(pair_panel(s, k, &lie::PairRecord::corr_y, "(b) correlation y", "Greys", 1.0));
      f.panels.push_back(pair_panel(s, k, &lie::PairRecord::corr_theta, "(c) correlation θ", "Greys", 1.0));
      f.panels.push_back(pair_panel(s, k, &lie::PairRecord::error_joint, "(d) ε, joint", "Reds", vmax));
      f.panels.push_back(
          pair_panel(s, k, &lie::PairRecord::error_independent, "(e) ε, correlation ignored", "Reds", vmax));
      r.figure(f);
    }
  });
}
