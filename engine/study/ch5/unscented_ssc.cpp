#include "study/ch5/unscented_ssc.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "lie/metrics.hpp"

namespace keel::study::ch5 {

using repro::Figure;
using repro::Panel;
using repro::Results;
using repro::RunContext;

// ---------------------------------------------------------------------------------------------------------------
// Fig. 5.7

UnscentedSsc::Outcome UnscentedSsc::run(const Options& o, const RunContext& context) {
  CompositionSetup s = o.setup;
  s.keep_samples = true;
  s.joint_fourth_order_max_steps = 0;  // not used here
  core::Progress progress = context.progress(s.trajectories);
  Outcome out{o, simulate_composition(s, context, &progress), {}};
  progress.finish();
  out.conversion = convert_ssc_prediction(out.composition, s.levels);
  return out;
}

void UnscentedSsc::record(Results& r, const Outcome& out) {
  const double level = out.options.setup.levels[0];
  const SscConversion& c = out.conversion;
  const auto tag = r.under(fmt::format("inside{}", repro::level_tag(level)));
  tag.metric("ssc", out.composition.ssc.inside[0]);
  tag.metric("ssc_unscented", c.unscented.inside[0]);
  tag.metric("lie_joint", out.composition.lie_joint.inside[0]);
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
}

std::vector<Figure> UnscentedSsc::figures(const Outcome& out) {
  const CompositionSetup& s = out.options.setup;
  const double level = s.levels[0];
  const SscConversion& c = out.conversion;
  Figure f;
  f.file = ".png";
  f.width = 9.0;
  f.height = 6.0;
  f.title = fmt::format("Fig. 5.7: SSC converted by the UT, {:.3g} % regions ({} end poses, N = {})",
                        100.0 * level, s.trajectories, s.steps);
  Panel panel;
  panel.xlabel = "x";
  panel.ylabel = "y";
  panel.aspect = "equal";
  std::vector<double> sx, sy;
  planar_positions(out.composition.samples, sx, sy);
  panel.layers.push_back(repro::scatter_layer(sx, sy, "Monte-Carlo end positions", "0.25", 3.0, 0.2));
  auto region = [&](const SE3& mean, const Mat6& cov, const char* label, const char* color) {
    std::vector<double> x, y;
    planar_lie_region(mean, cov, level, out.options.region_points, x, y);
    panel.layers.push_back(repro::scatter_layer(std::move(x), std::move(y), label, color, 2.0));
  };
  std::vector<double> ell_x, ell_y;
  planar_ssc_ellipse(out.composition.ssc, level, 200, ell_x, ell_y);
  panel.layers.push_back(
      repro::line_layer(std::move(ell_x), std::move(ell_y), "SSC head-to-tail", "tab:red"));
  region(c.unscented.mean, c.cov_samples, "true spread (samples, about the same mean)", "tab:pink");
  region(c.unscented.mean, c.unscented.cov, "SSC converted by the UT (eqs. 5.60–5.62)", "tab:green");
  f.panels.push_back(panel);
  return {f};
}

}  // namespace keel::study::ch5
