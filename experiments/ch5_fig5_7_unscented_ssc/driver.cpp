// Fig. 5.7 (§5.8.1): the SSC head-to-tail prediction of Fig. 5.4's composition, converted to the Lie algebra
// by the unscented transform (eqs. 5.60–5.62), against the true spread of the composed poses — thin driver
// over keel::lie::run_composition_study and keel::lie::convert_ssc_prediction.
import keel.core;
import keel.repro;
import keel.lie;

#include <fmt/format.h>

#include <string>
#include <vector>

#include "common/composition.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace lie = keel::lie;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    auto s = keel::experiments::read_composition_setup(p, true);
    const double level = s.levels[0];
    const int region_points = static_cast<int>(p.count("region_points"));
    ex.params_done();
    s.keep_samples = true;
    s.joint_fourth_order_max_steps = 0;  // not used here
    s.seed = ex.seed();
    s.threads = ex.threads();

    core::Progress progress(ex.id(), s.trajectories);
    const auto out = lie::run_composition_study(s, &progress);
    progress.finish();
    const auto c = lie::convert_ssc_prediction(out, s.levels);

    auto& r = ex.results();
    const std::string tag = fmt::format("inside{}", repro::level_tag(level));
    r.metric(tag + ".ssc", out.ssc.inside[0]);
    r.metric(tag + ".ssc_unscented", c.unscented.inside[0]);
    r.metric(tag + ".lie_joint", out.lie_joint.inside[0]);
    r.metric("volume_ratio.unscented_vs_samples", c.volume_vs_samples);
    r.metric("volume_ratio.unscented_vs_joint", c.volume_vs_joint);
    r.metric("volume_ratio.joint_vs_samples", c.joint_volume_vs_samples);
    r.check(
        "the UT-converted SSC region over-approximates the true distribution (a larger region than the "
        "samples' "
        "spread about the same mean)",
        c.volume_vs_samples > 1.0,
        fmt::format("volume ratio {:.3g} (inside its {:.3g} % region: {:.4f})", c.volume_vs_samples,
                    100.0 * level, c.unscented.inside[0]));
    r.check(
        "converting through SSC loses information: the converted region is larger than the proposed joint "
        "prediction's",
        c.volume_vs_joint > 1.0,
        fmt::format("volume ratio against the joint prediction {:.3g}", c.volume_vs_joint));

    repro::Figure f;
    f.file = fmt::format("{}.png", ex.id());
    f.width = 9.0;
    f.height = 6.0;
    f.title = fmt::format("Fig. 5.7: SSC converted by the UT, {:.3g} % regions ({} end poses, N = {})",
                          100.0 * level, s.trajectories, s.steps);
    repro::Panel panel;
    panel.xlabel = "x";
    panel.ylabel = "y";
    panel.aspect = "equal";
    std::vector<double> sx, sy;
    lie::planar_positions(out.samples, sx, sy);
    panel.layers.push_back(repro::scatter_layer(sx, sy, "Monte-Carlo end positions", "0.25", 3.0, 0.2));
    auto region = [&](const lie::SE3& mean, const lie::Mat6& cov, const char* label, const char* color) {
      std::vector<double> x, y;
      lie::planar_lie_region(mean, cov, level, region_points, x, y);
      panel.layers.push_back(repro::scatter_layer(std::move(x), std::move(y), label, color, 2.0));
    };
    std::vector<double> ell_x, ell_y;
    lie::planar_ssc_ellipse(out.ssc, level, 200, ell_x, ell_y);
    panel.layers.push_back(
        repro::line_layer(std::move(ell_x), std::move(ell_y), "SSC head-to-tail", "tab:red"));
    region(c.unscented.mean, c.cov_samples, "true spread (samples, about the same mean)", "tab:pink");
    region(c.unscented.mean, c.unscented.cov, "SSC converted by the UT (eqs. 5.60–5.62)", "tab:green");
    f.panels.push_back(panel);
    r.figure(f);
  });
}
