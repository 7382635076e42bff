// Fig. 5.4 (§5.5.2): composition of correlated odometry — thin driver over keel::lie::run_composition_study.
import keel.core;
import keel.repro;
import keel.lie;

#include <fmt/format.h>

#include <cmath>
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
    s.seed = ex.seed();
    s.threads = ex.threads();

    core::Progress progress(ex.id(), s.trajectories);
    const auto out = lie::run_composition_study(s, &progress);
    progress.finish();

    const std::string tag = fmt::format("inside{}", repro::level_tag(level));
    const double ssc = out.ssc.inside[0], ssc_ind = out.ssc_independent.inside[0];
    const double ind = out.lie_independent.inside[0], joint = out.lie_joint.inside[0];
    auto& r = ex.results();
    r.metric(fmt::format("{}.ssc", tag), ssc);
    r.metric(fmt::format("{}.ssc_independent", tag), ssc_ind);
    r.metric(fmt::format("{}.lie_independent", tag), ind);
    r.metric(fmt::format("{}.lie_joint", tag), joint);
    r.metric(fmt::format("{}.lie_fourth_order", tag), out.lie_fourth_order.inside[0]);
    if (out.has_joint_fourth_order) {
      r.metric(fmt::format("{}.lie_joint_fourth_order", tag), out.lie_joint_fourth_order.inside[0]);
    }

    const double pct = 100.0 * level;
    const double e_ssc = std::fabs(ssc - level), e_ind = std::fabs(ind - level),
                 e_joint = std::fabs(joint - level);
    // Monte-Carlo standard error of a fraction at the nominal level.
    const double se = std::sqrt(level * (1.0 - level) / static_cast<double>(s.trajectories));
    r.metric(fmt::format("{}.mc_3se", tag), 3 * se);
    r.check(
        "the joint Lie-algebra prediction is the closest of SSC / independent / joint to the nominal level",
        e_joint < e_ind && e_joint < e_ssc,
        fmt::format("|inside - {:.3g}|: joint {:.4f}, independent {:.4f}, SSC {:.4f}", level, e_joint, e_ind,
                    e_ssc));
    r.check(
        fmt::format("the joint Lie-algebra {:.3g} % region is consistent (within 3 standard errors)", pct),
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

    repro::Figure f;
    f.file = fmt::format("{}.png", ex.id());
    f.width = 13.0;
    f.height = 5.5;
    f.title =
        fmt::format("Fig. 5.4: {} end poses (N = {}); regions are shadows of the (x, y, yaw) ellipsoids",
                    s.trajectories, s.steps);
    std::vector<double> sx, sy;
    lie::planar_positions(out.samples, sx, sy);
    auto base_panel = [&](std::string title) {
      repro::Panel panel;
      panel.title = std::move(title);
      panel.xlabel = "x";
      panel.ylabel = "y";
      panel.aspect = "equal";
      panel.layers.push_back(repro::scatter_layer(sx, sy, "Monte-Carlo end positions", "0.25", 3.0, 0.2));
      return panel;
    };
    auto region = [&](repro::Panel& panel, const lie::CompositionPrediction& pr, const char* label,
                      const char* color) {
      std::vector<double> x, y;
      lie::planar_lie_region(pr, level, region_points, x, y);
      panel.layers.push_back(repro::scatter_layer(std::move(x), std::move(y), label, color, 2.0));
    };
    repro::Panel thesis = base_panel(fmt::format("as in the thesis: {:.3g} % regions", pct));
    std::vector<double> ell_x, ell_y;
    lie::planar_ssc_ellipse(out.ssc, level, 200, ell_x, ell_y);
    thesis.layers.push_back(
        repro::line_layer(std::move(ell_x), std::move(ell_y), "SSC head-to-tail", "tab:red"));
    region(thesis, out.lie_independent, "Lie algebra, correlation ignored", "tab:cyan");
    region(thesis, out.lie_joint, "Lie algebra, joint (proposed)", "tab:green");
    f.panels.push_back(thesis);
    if (out.has_joint_fourth_order) {
      repro::Panel beyond =
          base_panel(fmt::format("beyond the thesis: first vs fourth order, {:.3g} % regions", pct));
      region(beyond, out.lie_joint, "joint, first order (eq. 5.39)", "tab:green");
      region(beyond, out.lie_joint_fourth_order, "joint, fourth order (Isserlis)", "tab:purple");
      f.panels.push_back(beyond);
    }
    r.figure(f);
  });
}
