#include "study/ch5/noise_sweep.hpp"

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
// Fig. 5.9

NoiseSweep::Options NoiseSweep::Options::read(const core::ConfigTable& p) {
  Options o;
  o.setup.steps = static_cast<int>(p.integer("steps"));
  o.setup.rho = p.number("rho");
  o.setup.levels = {p.number("level")};
  o.fixed_sigma = p.number("fixed_sigma");
  o.sigmas = p.numbers("sigma_values");
  o.setup.trajectories = p.count("trajectories");
  return o;
}

NoiseSweep::Outcome NoiseSweep::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  core::Progress progress = context.progress(2 * o.sigmas.size() * o.setup.trajectories);
  auto sweep = [&](bool rotation, std::uint64_t offset) {
    Sweep w;
    const RunContext common =
        context.with_streams(context.streams().offset(offset));  // common within a sweep
    for (double sigma : o.sigmas) {
      CompositionSetup s = o.setup;
      s.sigma_r = rotation ? sigma : o.fixed_sigma;
      s.sigma_t = rotation ? o.fixed_sigma : sigma;
      const auto c = simulate_composition(s, common, &progress);
      w.ssc.push_back(c.ssc.inside[0]);
      w.ssc_independent.push_back(c.ssc_independent.inside[0]);
      w.lie_independent.push_back(c.lie_independent.inside[0]);
      w.lie_joint.push_back(c.lie_joint.inside[0]);
      w.lie_fourth_order.push_back(c.lie_fourth_order.inside[0]);
      if (!c.has_joint_fourth_order)
        throw std::runtime_error("the fourth-order joint chain was not evaluated");
      w.lie_joint_fourth_order.push_back(c.lie_joint_fourth_order.inside[0]);
    }
    return w;
  };
  out.rotation = sweep(true, 0);
  out.translation = sweep(false, std::uint64_t{1} << 32);
  progress.finish();
  return out;
}

void NoiseSweep::record(Results& r, const Outcome& out) {
  const double level = out.options.setup.levels[0];
  const auto& sigmas = out.options.sigmas;
  const Sweep &rot = out.rotation, &tra = out.translation;
  for (const auto& [prefix, var, w] :
       {std::tuple{"rotation", "sigma_r", &rot}, std::tuple{"translation", "sigma_t", &tra}}) {
    const auto pre = r.under(prefix).under(fmt::format("inside{}", repro::level_tag(level)));
    r.under(prefix).series(var, sigmas);
    pre.series("ssc", w->ssc);
    pre.series("ssc_independent", w->ssc_independent);
    pre.series("lie_independent", w->lie_independent);
    pre.series("lie_joint", w->lie_joint);
    pre.series("lie_fourth_order", w->lie_fourth_order);
    pre.series("lie_joint_fourth_order", w->lie_joint_fourth_order);
  }

  // Claim checks on our numbers. "Closer" allows a tie within two Monte-Carlo standard errors at the level.
  const double tie =
      2.0 * std::sqrt(level * (1.0 - level) / static_cast<double>(out.options.setup.trajectories));
  // Effect of a noise source = how much the joint method's inside fraction falls from the smallest to the
  // largest σ.
  const double rot_effect = rot.lie_joint.front() - rot.lie_joint.back(),
               tra_effect = tra.lie_joint.front() - tra.lie_joint.back();
  const double rot_effect_ssc = rot.ssc.front() - rot.ssc.back(),
               tra_effect_ssc = tra.ssc.front() - tra.ssc.back();
  r.check("rotation noise degrades consistency much more than translation noise",
          rot_effect > tra_effect + tie && rot_effect_ssc > tra_effect_ssc + tie,
          fmt::format("drop of inside fraction from σ = {:g} to {:g}: joint σr {:.4f} vs σt {:.4f}; SSC σr "
                      "{:.4f} vs σt "
                      "{:.4f}",
                      sigmas.front(), sigmas.back(), rot_effect, tra_effect, rot_effect_ssc, tra_effect_ssc));
  int joint_beats_ind = 0, total = 0, joint_beats_ssc = 0, ind_beats_ssc_ind = 0;
  auto closer = [&](double a, double b) { return std::fabs(a - level) <= std::fabs(b - level) + tie; };
  for (const Sweep* w : {&rot, &tra}) {
    for (std::size_t k = 0; k < sigmas.size(); ++k, ++total) {
      joint_beats_ind += closer(w->lie_joint[k], w->lie_independent[k]) ? 1 : 0;
      joint_beats_ssc += closer(w->lie_joint[k], w->ssc[k]) ? 1 : 0;
      ind_beats_ssc_ind += closer(w->lie_independent[k], w->ssc_independent[k]) ? 1 : 0;
    }
  }
  r.check(
      "the joint method is more accurate than ignoring correlation at every sweep point",
      joint_beats_ind == total,
      fmt::format("joint at least as close to {:.3f} as independent at {} of {} points (ties within {:.4f})",
                  level, joint_beats_ind, total, tie));
  r.check(
      "the Lie-algebra methods beat SSC like for like at every point of both sweeps (neither sweep has "
      "very low "
      "rotation together with very high translation noise, the thesis's exception)",
      joint_beats_ssc == total && ind_beats_ssc_ind == total,
      fmt::format(
          "joint vs SSC: Lie at least as close at {} of {} points; independent Lie vs independent SSC: {} "
          "of {}",
          joint_beats_ssc, total, ind_beats_ssc_ind, total));
}

std::vector<Figure> NoiseSweep::figures(const Outcome& out) {
  const double level = out.options.setup.levels[0];
  const auto& sigmas = out.options.sigmas;
  Figure f;
  f.file = ".png";
  f.title = fmt::format("Fig. 5.9: fraction inside the 99.9 % ellipsoid vs noise (N = {})",
                        out.options.setup.steps);
  for (const auto& [title, xlabel, w] : {std::tuple{"rotation noise (σt = 3)", "σr", &out.rotation},
                                         std::tuple{"translation noise (σr = 3)", "σt", &out.translation}}) {
    Panel panel;
    panel.title = title;
    panel.xlabel = xlabel;
    panel.ylabel = "fraction of samples inside";
    panel.layers.push_back(repro::line_layer(sigmas, w->ssc, "SSC head-to-tail", "tab:red", "^"));
    panel.layers.push_back(
        repro::line_layer(sigmas, w->ssc_independent, "SSC, correlation ignored", "tab:orange", "v"));
    panel.layers.push_back(
        repro::line_layer(sigmas, w->lie_independent, "Lie, correlation ignored", "tab:cyan", "s"));
    panel.layers.push_back(
        repro::line_layer(sigmas, w->lie_fourth_order, "Lie, 4th order (independent)", "tab:purple", "x"));
    panel.layers.push_back(
        repro::line_layer(sigmas, w->lie_joint, "Lie, joint (proposed)", "tab:green", "o"));
    panel.layers.push_back(repro::line_layer(sigmas, w->lie_joint_fourth_order, "Lie, joint 4th order (ours)",
                                             "tab:brown", "D"));
    panel.layers.push_back(repro::hline_layer(level, "nominal", "0.3"));
    f.panels.push_back(panel);
  }
  return {f};
}

}  // namespace keel::study::ch5
