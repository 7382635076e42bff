// Fig. 5.4 (§5.5.2): composition of correlated odometry — thin driver over keel::lie::run_composition_study.
import keel.core;
import keel.lie;

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace core = keel::core;
namespace lie = keel::lie;

int main(int argc, char** argv) {
  return core::experiment_main(argc, argv, [](core::Experiment& ex) {
    const auto& p = ex.params();
    lie::CompositionSetup s;
    s.steps = static_cast<int>(p.integer("steps"));
    s.sigma_t = p.number("sigma_t");
    s.sigma_r = p.number("sigma_r");
    s.rho = p.number("rho");
    const double level = p.number("level");
    s.levels = {level};
    s.trajectories = static_cast<std::size_t>(p.integer("trajectories"));
    const int region_points = static_cast<int>(p.integer("region_points"));
    ex.params_done();
    s.keep_samples = true;
    s.seed = ex.seed();
    s.threads = ex.threads();

    core::Progress progress(ex.id(), s.trajectories);
    const auto out = lie::run_composition_study(s, &progress);
    progress.finish();

    const std::string tag = "inside" + std::to_string(static_cast<int>(std::lround(level * 100)));
    auto& r = ex.results();
    r.metric(tag + ".ssc", out.ssc.inside[0]);
    r.metric(tag + ".lie_independent", out.lie_independent.inside[0]);
    r.metric(tag + ".lie_joint", out.lie_joint.inside[0]);
    r.metric(tag + ".lie_fourth_order", out.lie_fourth_order.inside[0]);

    const double e_ssc = std::fabs(out.ssc.inside[0] - level);
    const double e_ind = std::fabs(out.lie_independent.inside[0] - level);
    const double e_joint = std::fabs(out.lie_joint.inside[0] - level);
    char detail[256];
    std::snprintf(detail, sizeof detail, "|inside - %.2f|: joint %.4f, independent %.4f, SSC %.4f", level, e_joint,
                  e_ind, e_ssc);
    r.check("the joint Lie-algebra prediction is the closest of SSC / independent / joint to the nominal level",
            e_joint < e_ind && e_joint < e_ssc, detail);
    // "Consistent" within 3 Monte-Carlo standard errors of a fraction at the nominal level.
    const double se3 = 3.0 * std::sqrt(level * (1.0 - level) / static_cast<double>(s.trajectories));
    std::snprintf(detail, sizeof detail, "inside: joint %.4f, nominal %.2f ± %.4f (3 standard errors)",
                  out.lie_joint.inside[0], level, se3);
    r.check("the joint Lie-algebra 95 % region is consistent (covers the nominal fraction of samples)", e_joint <= se3,
            detail);
    std::snprintf(detail, sizeof detail, "inside: independent %.4f vs nominal %.2f", out.lie_independent.inside[0],
                  level);
    r.check("ignoring correlation under-approximates the spread (fewer samples inside than nominal)",
            out.lie_independent.inside[0] < level, detail);
    std::snprintf(detail, sizeof detail, "inside: SSC %.4f, joint %.4f", out.ssc.inside[0], out.lie_joint.inside[0]);
    r.check("SSC head-to-tail is less consistent than the joint Lie-algebra composition",
            out.ssc.inside[0] < out.lie_joint.inside[0], detail);

    core::Figure f;
    f.file = ex.id() + ".png";
    f.title = "Fig. 5.4: " + std::to_string(s.trajectories) + " end poses (N = " + std::to_string(s.steps) + "), " +
              std::to_string(static_cast<int>(std::lround(level * 100))) + " % regions";
    core::Panel panel;
    panel.xlabel = "x";
    panel.ylabel = "y";
    panel.aspect = "equal";
    core::Layer samples;
    samples.type = "scatter";
    lie::planar_positions(out.samples, samples.x, samples.y);
    samples.label = "Monte-Carlo end positions";
    samples.color = "0.25";
    samples.size = 3.0;
    samples.alpha = 0.25;
    samples.marker = ".";
    panel.layers.push_back(samples);
    core::Layer ssc;
    ssc.type = "line";
    lie::planar_ssc_ellipse(out.ssc, level, 200, ssc.x, ssc.y);
    ssc.label = "SSC head-to-tail";
    ssc.color = "tab:red";
    ssc.linewidth = 1.5;
    panel.layers.push_back(ssc);
    auto region = [&](const lie::CompositionPrediction& pr, const char* label, const char* color) {
      core::Layer l;
      l.type = "scatter";
      lie::planar_lie_region(pr, level, region_points, l.x, l.y);
      l.label = label;
      l.color = color;
      l.size = 2.0;
      l.marker = ".";
      panel.layers.push_back(l);
    };
    region(out.lie_independent, "Lie algebra, correlation ignored", "tab:cyan");
    region(out.lie_joint, "Lie algebra, joint (proposed)", "tab:green");
    f.panels.push_back(panel);
    r.figure(f);
  });
}
