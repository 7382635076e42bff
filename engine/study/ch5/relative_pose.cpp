#include "study/ch5/relative_pose.hpp"

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
