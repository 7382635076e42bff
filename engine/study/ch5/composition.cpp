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

CompositionSetup read_composition_setup(const core::ConfigTable& p, bool with_steps) {
  CompositionSetup s;
  if (with_steps) s.steps = static_cast<int>(p.count("steps"));
  s.sigma_t = p.number("sigma_t");
  s.sigma_r = p.number("sigma_r");
  s.rho = p.number("rho");
  s.levels = {p.number("level")};
  s.trajectories = p.count("trajectories");
  p.validate(s);
  return s;
}

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
  const std::string tag = fmt::format("inside{}", repro::level_tag(level));
  const double ssc = c.ssc.inside[0], ssc_ind = c.ssc_independent.inside[0];
  const double ind = c.lie_independent.inside[0], joint = c.lie_joint.inside[0];
  r.metric(fmt::format("{}.ssc", tag), ssc);
  r.metric(fmt::format("{}.ssc_independent", tag), ssc_ind);
  r.metric(fmt::format("{}.lie_independent", tag), ind);
  r.metric(fmt::format("{}.lie_joint", tag), joint);
  r.metric(fmt::format("{}.lie_fourth_order", tag), c.lie_fourth_order.inside[0]);
  if (c.has_joint_fourth_order) {
    r.metric(fmt::format("{}.lie_joint_fourth_order", tag), c.lie_joint_fourth_order.inside[0]);
  }

  const double pct = 100.0 * level;
  const double e_ssc = std::fabs(ssc - level), e_ind = std::fabs(ind - level),
               e_joint = std::fabs(joint - level);
  // Monte-Carlo standard error of a fraction at the nominal level.
  const double se = std::sqrt(level * (1.0 - level) / static_cast<double>(s.trajectories));
  r.metric(fmt::format("{}.mc_3se", tag), 3 * se);
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
  const std::string tag = fmt::format("inside{}", repro::level_tag(level));
  r.metric(tag + ".ssc", out.composition.ssc.inside[0]);
  r.metric(tag + ".ssc_unscented", c.unscented.inside[0]);
  r.metric(tag + ".lie_joint", out.composition.lie_joint.inside[0]);
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
  const std::string tag = fmt::format("inside{}", repro::level_tag(level));
  r.series("N", ns);
  r.series(fmt::format("{}.ssc", tag), ssc);
  r.series(fmt::format("{}.ssc_independent", tag), out.ssc_independent);
  r.series(fmt::format("{}.lie_independent", tag), ind);
  r.series(fmt::format("{}.lie_joint", tag), joint);
  r.series(fmt::format("{}.lie_fourth_order", tag), fourth);
  r.series("N_joint_fourth_order", out.steps_joint_fourth_order);
  r.series(fmt::format("{}.lie_joint_fourth_order", tag), out.lie_joint_fourth_order);
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
    const std::string pre = fmt::format("{}.inside{}", prefix, repro::level_tag(level));
    r.series(fmt::format("{}.{}", prefix, var), sigmas);
    r.series(fmt::format("{}.ssc", pre), w->ssc);
    r.series(fmt::format("{}.ssc_independent", pre), w->ssc_independent);
    r.series(fmt::format("{}.lie_independent", pre), w->lie_independent);
    r.series(fmt::format("{}.lie_joint", pre), w->lie_joint);
    r.series(fmt::format("{}.lie_fourth_order", pre), w->lie_fourth_order);
    r.series(fmt::format("{}.lie_joint_fourth_order", pre), w->lie_joint_fourth_order);
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

// ---------------------------------------------------------------------------------------------------------------
// Figs. 5.5–5.6

RelativePose::Options RelativePose::Options::read(const core::ConfigTable& p) {
  Options o;
  o.yaw = p.number("yaw_deg") * M_PI / 180.0;
  o.t_g1 = p.numbers("t_g1");
  o.t_g2 = p.numbers("t_g2");
  o.marginal_diag = p.numbers("marginal_diag");
  o.cross_diag = p.numbers("cross_diag");
  o.alphas = p.numbers("alphas");
  o.example_alpha = p.number("example_alpha");
  o.level = p.number("level");
  o.region_points = static_cast<int>(p.count("region_points"));
  o.samples = p.count("samples");
  if (o.alphas.empty()) throw core::ConfigError(fmt::format("{}: must not be empty", p.where("alphas")));
  return o;
}

RelativePose::Outcome RelativePose::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  // Each α gets the study's sample set plus an independent second Monte-Carlo set (the noise floor of ε).
  core::Progress progress = context.progress(2 * o.samples * (o.alphas.size() + 1));
  auto simulate = [&](double alpha, std::uint64_t offset, bool keep) {
    RelativePoseSetup s = relative_pose_setup(o.yaw, o.t_g1, o.t_g2, o.marginal_diag, o.cross_diag, alpha);
    s.samples = o.samples;
    s.keep_samples = keep;
    return simulate_relative_pose(s, context.with_streams(context.streams().offset(offset)), &progress);
  };
  for (std::size_t k = 0; k < o.alphas.size(); ++k) {
    const auto a = simulate(o.alphas[k], (2 * k) << 32, false);
    const auto b = simulate(o.alphas[k], (2 * k + 1) << 32, false);
    out.error_joint.push_back(a.error_joint);
    out.error_independent.push_back(a.error_independent);
    // ε between two independent estimates is √2 times the error of one estimate against the truth.
    out.error_mc_noise.push_back(lie::covariance_error(a.cov_mc, b.cov_mc) / std::sqrt(2.0));
  }
  out.example = simulate(o.example_alpha, std::uint64_t{1} << 40, true);
  progress.advance(o.samples);  // the example run has no second set
  progress.finish();
  return out;
}

void RelativePose::record(Results& r, const Outcome& out) {
  const auto& alphas = out.options.alphas;
  r.series("alpha", alphas);
  r.series("cov_error.joint", out.error_joint);
  r.series("cov_error.independent", out.error_independent);
  r.series("cov_error.mc_noise", out.error_mc_noise);
  r.metric("example.cov_error.joint", out.example.error_joint);
  r.metric("example.cov_error.independent", out.example.error_independent);

  bool below = true;
  double worst_ratio = 0;
  for (std::size_t k = 0; k < alphas.size(); ++k) {
    below = below && out.error_joint[k] < out.error_independent[k];
    worst_ratio = std::max(worst_ratio, out.error_joint[k] / out.error_independent[k]);
  }
  r.check(
      "ε with cross-covariance is below ε without it at every α", below,
      fmt::format("largest ε_joint/ε_independent over {} values of α: {:.3g}", alphas.size(), worst_ratio));
  r.check("at α = 1, including correlation reduces ε by more than 10×",
          out.example.error_joint * 10 < out.example.error_independent,
          fmt::format("α = {:g}: ε_joint = {:.3g}, ε_independent = {:.3g}", out.options.example_alpha,
                      out.example.error_joint, out.example.error_independent));
}

std::vector<Figure> RelativePose::figures(const Outcome& out) {
  const Options& o = out.options;
  Figure f;
  f.file = ".png";
  f.title = "Figs. 5.5–5.6: relative pose of two correlated poses";
  Panel err;
  err.title = "covariance error ε (eq. 5.56) vs α";
  err.xlabel = "α";
  err.ylabel = "ε";
  err.xscale = "log";
  err.yscale = "log";
  err.layers.push_back(
      repro::line_layer(o.alphas, out.error_independent, "correlation ignored", "tab:cyan", "s"));
  err.layers.push_back(repro::line_layer(o.alphas, out.error_joint, "joint (proposed)", "tab:green", "o"));
  err.layers.push_back(
      repro::line_layer(o.alphas, out.error_mc_noise, "Monte-Carlo noise of Σ_mc", "0.5", "", ":"));
  Panel ex_panel;
  ex_panel.title = fmt::format("relative pose samples, α = {:g} (cf. Fig. 5.5)", o.example_alpha);
  ex_panel.xlabel = "x";
  ex_panel.ylabel = "y";
  ex_panel.aspect = "equal";
  std::vector<double> px, py;
  planar_positions(out.example.samples, px, py);
  ex_panel.layers.push_back(
      repro::scatter_layer(std::move(px), std::move(py), "Monte-Carlo T₁₂", "0.25", 3.0, 0.2));
  auto region = [&](const Mat6& cov, const char* label, const char* color) {
    std::vector<double> x, y;
    planar_lie_region(out.example.mean, cov, o.level, o.region_points, x, y);
    ex_panel.layers.push_back(repro::scatter_layer(std::move(x), std::move(y), label, color, 2.0));
  };
  region(out.example.cov_independent, "95 %, correlation ignored", "tab:cyan");
  region(out.example.cov_joint, "95 %, joint (proposed)", "tab:green");
  f.panels.push_back(err);
  f.panels.push_back(ex_panel);
  return {f};
}

}  // namespace keel::study::ch5
