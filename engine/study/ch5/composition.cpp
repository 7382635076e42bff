#include "study/ch5/composition.hpp"

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
// Fig. 5.4

Composition::Options Composition::Options::read(const core::ConfigTable& p) {
  Options o;
  o.setup = read_composition_setup(p, true);
  o.region_points = static_cast<int>(p.count("region_points"));
  return o;
}

Composition::Outcome Composition::run(const Options& o, const RunContext& context) {
  CompositionSetup s = o.setup;
  s.keep_samples = true;
  core::Progress progress = context.progress(s.trajectories);
  Outcome out{o, simulate_composition(s, context, &progress)};
  progress.finish();
  return out;
}

void Composition::record(Results& r, const Outcome& out) {
  const CompositionSetup& s = out.options.setup;
  const CompositionOutcome& c = out.composition;
  const double level = s.levels[0];
  const auto tag = r.under(fmt::format("inside{}", repro::level_tag(level)));
  const double ssc = c.ssc.inside[0], ssc_ind = c.ssc_independent.inside[0];
  const double ind = c.lie_independent.inside[0], joint = c.lie_joint.inside[0];
  tag.metric("ssc", ssc);
  tag.metric("ssc_independent", ssc_ind);
  tag.metric("lie_independent", ind);
  tag.metric("lie_joint", joint);
  tag.metric("lie_fourth_order", c.lie_fourth_order.inside[0]);
  if (c.has_joint_fourth_order) {
    tag.metric("lie_joint_fourth_order", c.lie_joint_fourth_order.inside[0]);
  }

  const double pct = 100.0 * level;
  const double e_ssc = std::fabs(ssc - level), e_ind = std::fabs(ind - level),
               e_joint = std::fabs(joint - level);
  // Monte-Carlo standard error of a fraction at the nominal level.
  const double se = std::sqrt(level * (1.0 - level) / static_cast<double>(s.trajectories));
  tag.metric("mc_3se", 3 * se);
  r.check("the joint Lie-algebra prediction is the closest of SSC / independent / joint to the nominal level",
          e_joint < e_ind && e_joint < e_ssc,
          fmt::format("|inside - {:.3g}|: joint {:.4f}, independent {:.4f}, SSC {:.4f}", level, e_joint,
                      e_ind, e_ssc));
  r.check(fmt::format("the joint Lie-algebra {:.3g} % region is consistent (within 3 standard errors)", pct),
          e_joint <= 3 * se,
          fmt::format("inside: joint {:.4f}, nominal {:.3g} ± {:.4f}", joint, level, 3 * se));
  r.check(
      "dropping the cross-covariance under-approximates the spread (fewer samples inside than the joint "
      "region)",
      ind < joint, fmt::format("inside: independent {:.4f} < joint {:.4f}", ind, joint));
  r.check(
      "the Lie algebra beats SSC head-to-tail like for like (joint vs SSC, independent vs independent SSC)",
      e_joint < e_ssc && std::fabs(ind - level) < std::fabs(ssc_ind - level),
      fmt::format("with correlation: joint {:.4f} vs SSC {:.4f}; without: Lie {:.4f} vs SSC {:.4f}", joint,
                  ssc, ind, ssc_ind));
}

std::vector<Figure> Composition::figures(const Outcome& out) {
  const CompositionSetup& s = out.options.setup;
  const CompositionOutcome& c = out.composition;
  const double level = s.levels[0], pct = 100.0 * level;
  const int region_points = out.options.region_points;
  Figure f;
  f.file = ".png";
  f.width = 13.0;
  f.height = 5.5;
  f.title = fmt::format("Fig. 5.4: {} end poses (N = {}); regions are shadows of the (x, y, yaw) ellipsoids",
                        s.trajectories, s.steps);
  std::vector<double> sx, sy;
  planar_positions(c.samples, sx, sy);
  auto base_panel = [&](std::string title) {
    Panel panel;
    panel.title = std::move(title);
    panel.xlabel = "x";
    panel.ylabel = "y";
    panel.aspect = "equal";
    panel.layers.push_back(repro::scatter_layer(sx, sy, "Monte-Carlo end positions", "0.25", 3.0, 0.2));
    return panel;
  };
  auto region = [&](Panel& panel, const CompositionPrediction& pr, const char* label, const char* color) {
    std::vector<double> x, y;
    planar_lie_region(pr, level, region_points, x, y);
    panel.layers.push_back(repro::scatter_layer(std::move(x), std::move(y), label, color, 2.0));
  };
  Panel thesis = base_panel(fmt::format("as in the thesis: {:.3g} % regions", pct));
  std::vector<double> ell_x, ell_y;
  planar_ssc_ellipse(c.ssc, level, 200, ell_x, ell_y);
  thesis.layers.push_back(
      repro::line_layer(std::move(ell_x), std::move(ell_y), "SSC head-to-tail", "tab:red"));
  region(thesis, c.lie_independent, "Lie algebra, correlation ignored", "tab:cyan");
  region(thesis, c.lie_joint, "Lie algebra, joint (proposed)", "tab:green");
  f.panels.push_back(thesis);
  if (c.has_joint_fourth_order) {
    Panel beyond = base_panel(fmt::format("beyond the thesis: first vs fourth order, {:.3g} % regions", pct));
    region(beyond, c.lie_joint, "joint, first order (eq. 5.39)", "tab:green");
    region(beyond, c.lie_joint_fourth_order, "joint, fourth order (Isserlis)", "tab:purple");
    f.panels.push_back(beyond);
  }
  return {f};
}

}  // namespace keel::study::ch5
