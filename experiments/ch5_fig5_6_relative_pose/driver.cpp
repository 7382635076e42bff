// Figs. 5.5–5.6 (§5.7.2): relative pose of correlated poses — thin driver over
// keel::lie::run_relative_pose_study.
import keel.core;
import keel.repro;
import keel.lie;

#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

namespace core = keel::core;
namespace repro = keel::repro;
namespace lie = keel::lie;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    const double yaw = p.number("yaw_deg") * M_PI / 180.0;
    const auto t1 = p.numbers("t_g1"), t2 = p.numbers("t_g2");
    const auto marginal = p.numbers("marginal_diag"), cross = p.numbers("cross_diag");
    const auto alphas = p.numbers("alphas");
    const double example_alpha = p.number("example_alpha");
    const double level = p.number("level");
    const int region_points = static_cast<int>(p.count("region_points"));
    const auto samples = p.count("samples");
    ex.params_done();
    if (alphas.empty()) throw core::ConfigError(fmt::format("{}: must not be empty", p.where("alphas")));

    // Each α gets the study's sample set plus an independent second Monte-Carlo set (the noise floor of ε).
    core::Progress progress(ex.id(), 2 * samples * (alphas.size() + 1));
    std::vector<double> err_joint, err_ind, err_floor;
    auto run = [&](double alpha, std::uint64_t base, bool keep) {
      auto s = lie::relative_pose_setup(yaw, t1, t2, marginal, cross, alpha);
      s.samples = samples;
      s.seed = ex.seed();
      s.stream_base = base;
      s.threads = ex.threads();
      s.keep_samples = keep;
      return lie::run_relative_pose_study(s, &progress);
    };
    for (std::size_t k = 0; k < alphas.size(); ++k) {
      const auto a = run(alphas[k], (2 * k) << 32, false);
      const auto b = run(alphas[k], (2 * k + 1) << 32, false);
      err_joint.push_back(a.error_joint);
      err_ind.push_back(a.error_independent);
      // ε between two independent estimates is √2 times the error of one estimate against the truth.
      err_floor.push_back(lie::covariance_error(a.cov_mc, b.cov_mc) / std::sqrt(2.0));
    }
    const auto example = run(example_alpha, std::uint64_t{1} << 40, true);
    progress.advance(samples);  // the example run has no second set
    progress.finish();

    auto& r = ex.results();
    r.series("alpha", alphas);
    r.series("cov_error.joint", err_joint);
    r.series("cov_error.independent", err_ind);
    r.series("cov_error.mc_noise", err_floor);
    r.metric("example.cov_error.joint", example.error_joint);
    r.metric("example.cov_error.independent", example.error_independent);

    bool below = true;
    double worst_ratio = 0;
    for (std::size_t k = 0; k < alphas.size(); ++k) {
      below = below && err_joint[k] < err_ind[k];
      worst_ratio = std::max(worst_ratio, err_joint[k] / err_ind[k]);
    }
    r.check(
        "ε with cross-covariance is below ε without it at every α", below,
        fmt::format("largest ε_joint/ε_independent over {} values of α: {:.3g}", alphas.size(), worst_ratio));
    r.check("at α = 1, including correlation reduces ε by more than 10×",
            example.error_joint * 10 < example.error_independent,
            fmt::format("α = {:g}: ε_joint = {:.3g}, ε_independent = {:.3g}", example_alpha,
                        example.error_joint, example.error_independent));

    repro::Figure f;
    f.file = fmt::format("{}.png", ex.id());
    f.title = "Figs. 5.5–5.6: relative pose of two correlated poses";
    repro::Panel err;
    err.title = "covariance error ε (eq. 5.56) vs α";
    err.xlabel = "α";
    err.ylabel = "ε";
    err.xscale = "log";
    err.yscale = "log";
    err.layers.push_back(repro::line_layer(alphas, err_ind, "correlation ignored", "tab:cyan", "s"));
    err.layers.push_back(repro::line_layer(alphas, err_joint, "joint (proposed)", "tab:green", "o"));
    err.layers.push_back(repro::line_layer(alphas, err_floor, "Monte-Carlo noise of Σ_mc", "0.5", "", ":"));
    repro::Panel ex_panel;
    ex_panel.title = fmt::format("relative pose samples, α = {:g} (cf. Fig. 5.5)", example_alpha);
    ex_panel.xlabel = "x";
    ex_panel.ylabel = "y";
    ex_panel.aspect = "equal";
    std::vector<double> px, py;
    lie::planar_positions(example.samples, px, py);
    ex_panel.layers.push_back(
        repro::scatter_layer(std::move(px), std::move(py), "Monte-Carlo T₁₂", "0.25", 3.0, 0.2));
    auto region = [&](const auto& cov, const char* label, const char* color) {
      std::vector<double> x, y;
      lie::planar_lie_region(example.mean, cov, level, region_points, x, y);
      ex_panel.layers.push_back(repro::scatter_layer(std::move(x), std::move(y), label, color, 2.0));
    };
    region(example.cov_independent, "95 %, correlation ignored", "tab:cyan");
    region(example.cov_joint, "95 %, joint (proposed)", "tab:green");
    f.panels.push_back(err);
    f.panels.push_back(ex_panel);
    r.figure(f);
  });
}
