#include "study/ch5/length_sweep.hpp"

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
// Fig. 5.8

LengthSweep::Options LengthSweep::Options::read(const core::ConfigTable& p) {
  Options o;
  o.steps_min = static_cast<int>(p.integer("steps_min"));
  o.steps_max = static_cast<int>(p.integer("steps_max"));
  o.steps_stride = static_cast<int>(p.integer("steps_stride"));
  o.setup = read_composition_setup(p, false);
  o.setup.joint_fourth_order_max_steps = static_cast<int>(p.integer("joint_fourth_order_max_steps"));
  if (o.steps_min < 1 || o.steps_max < o.steps_min || o.steps_stride < 1) {
    throw core::ConfigError(
        fmt::format("{}: need 1 <= steps_min <= steps_max and steps_stride >= 1", p.where("steps_min")));
  }
  return o;
}

LengthSweep::Outcome LengthSweep::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  for (auto n = o.steps_min; n <= o.steps_max; n += o.steps_stride)
    out.steps.push_back(static_cast<double>(n));
  core::Progress progress = context.progress(out.steps.size() * o.setup.trajectories);
  for (double n : out.steps) {
    CompositionSetup s = o.setup;
    s.steps = static_cast<int>(n);
    // Common random numbers: every N reuses the same streams (cleaner comparisons across N).
    const auto c = simulate_composition(s, context, &progress);
    out.ssc.push_back(c.ssc.inside[0]);
    out.ssc_independent.push_back(c.ssc_independent.inside[0]);
    out.lie_independent.push_back(c.lie_independent.inside[0]);
    out.lie_joint.push_back(c.lie_joint.inside[0]);
    out.lie_fourth_order.push_back(c.lie_fourth_order.inside[0]);
    if (c.has_joint_fourth_order) {
      out.steps_joint_fourth_order.push_back(n);
      out.lie_joint_fourth_order.push_back(c.lie_joint_fourth_order.inside[0]);
    }
  }
  progress.finish();
  return out;
}

void LengthSweep::record(Results& r, const Outcome& out) {
  const double level = out.options.setup.levels[0];
  const auto& ns = out.steps;
  const auto &ssc = out.ssc, &ind = out.lie_independent, &joint = out.lie_joint,
             &fourth = out.lie_fourth_order;
  const auto tag = r.under(fmt::format("inside{}", repro::level_tag(level)));
  r.series("N", ns);
  tag.series("ssc", ssc);
  tag.series("ssc_independent", out.ssc_independent);
  tag.series("lie_independent", ind);
  tag.series("lie_joint", joint);
  tag.series("lie_fourth_order", fourth);
  r.series("N_joint_fourth_order", out.steps_joint_fourth_order);
  tag.series("lie_joint_fourth_order", out.lie_joint_fourth_order);
  // The first N from which the fourth-order (independent) compounding keeps more samples inside than the
  // first-order joint method at every longer N; absent if it never does.
  std::size_t cross = ns.size();
  while (cross > 0 && fourth[cross - 1] > joint[cross - 1]) --cross;
  if (cross < ns.size()) r.metric("crossover.fourth_order_over_joint.N", ns[cross]);

  // "Closest" allows a tie within two Monte-Carlo standard errors of a fraction at the nominal level.
  const double tie =
      2.0 * std::sqrt(level * (1.0 - level) / static_cast<double>(out.options.setup.trajectories));
  int joint_best = 0;
  for (std::size_t k = 0; k < ns.size(); ++k) {
    const double ej = std::fabs(joint[k] - level);
    joint_best += (ej <= std::fabs(ssc[k] - level) + tie && ej <= std::fabs(ind[k] - level) + tie) ? 1 : 0;
  }
  r.check("the joint Lie-algebra method is the most accurate of SSC / independent / joint at every N",
          joint_best == static_cast<int>(ns.size()),
          fmt::format("joint closest to {:.3f} (ties within {:.4f}) at {} of {} values of N", level, tie,
                      joint_best, ns.size()));
  r.check("consistency drops as N grows (joint and SSC lower at the longest N than at the shortest)",
          joint.back() < joint.front() && ssc.back() < ssc.front(),
          fmt::format("inside (joint): N={:g} {:.4f} -> N={:g} {:.4f}; SSC {:.4f} -> {:.4f}", ns.front(),
                      joint.front(), ns.back(), joint.back(), ssc.front(), ssc.back()));
}

std::vector<Figure> LengthSweep::figures(const Outcome& out) {
  const double level = out.options.setup.levels[0];
  const auto& ns = out.steps;
  Figure f;
  f.file = ".png";
  f.width = 7.5;
  f.height = 5.5;
  f.title = "Fig. 5.8: fraction inside the 99.9 % ellipsoid vs trajectory length";
  Panel panel;
  panel.xlabel = "number of composed poses N";
  panel.ylabel = "fraction of samples inside";
  panel.layers.push_back(repro::line_layer(ns, out.ssc, "SSC head-to-tail", "tab:red", "^"));
  panel.layers.push_back(
      repro::line_layer(ns, out.ssc_independent, "SSC, correlation ignored", "tab:orange", "v"));
  panel.layers.push_back(
      repro::line_layer(ns, out.lie_independent, "Lie, correlation ignored", "tab:cyan", "s"));
  panel.layers.push_back(
      repro::line_layer(ns, out.lie_fourth_order, "Lie, 4th order (independent)", "tab:purple", "x"));
  panel.layers.push_back(repro::line_layer(ns, out.lie_joint, "Lie, joint (proposed)", "tab:green", "o"));
  panel.layers.push_back(repro::line_layer(out.steps_joint_fourth_order, out.lie_joint_fourth_order,
                                           "Lie, joint 4th order (ours)", "tab:brown", "D"));
  panel.layers.push_back(repro::hline_layer(level, "nominal", "0.3"));
  f.panels.push_back(panel);
  return {f};
}

}  // namespace keel::study::ch5
