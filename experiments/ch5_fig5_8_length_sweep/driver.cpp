// Fig. 5.8 (§5.9.1): consistency of composition against trajectory length — thin driver.
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
    const auto n_min = p.integer("steps_min"), n_max = p.integer("steps_max"),
               stride = p.integer("steps_stride");
    auto base = keel::experiments::read_composition_setup(p, false);
    const double level = base.levels[0];
    base.joint_fourth_order_max_steps = static_cast<int>(p.integer("joint_fourth_order_max_steps"));
    ex.params_done();
    if (n_min < 1 || n_max < n_min || stride < 1) {
      throw core::ConfigError(
          fmt::format("{}: need 1 <= steps_min <= steps_max and steps_stride >= 1", p.where("steps_min")));
    }
    base.seed = ex.seed();
    base.threads = ex.threads();

    std::vector<double> ns;
    for (auto n = n_min; n <= n_max; n += stride) ns.push_back(static_cast<double>(n));
    core::Progress progress(ex.id(), ns.size() * base.trajectories);
    std::vector<double> ssc, ssc_ind, ind, joint, fourth, n_j4, joint4;
    for (std::size_t k = 0; k < ns.size(); ++k) {
      auto s = base;
      s.steps = static_cast<int>(ns[k]);
      s.stream_base =
          0;  // common random numbers: every N reuses the same streams (cleaner comparisons across N)
      const auto out = lie::run_composition_study(s, &progress);
      ssc.push_back(out.ssc.inside[0]);
      ssc_ind.push_back(out.ssc_independent.inside[0]);
      ind.push_back(out.lie_independent.inside[0]);
      joint.push_back(out.lie_joint.inside[0]);
      fourth.push_back(out.lie_fourth_order.inside[0]);
      if (out.has_joint_fourth_order) {
        n_j4.push_back(ns[k]);
        joint4.push_back(out.lie_joint_fourth_order.inside[0]);
      }
    }
    progress.finish();

    auto& r = ex.results();
    const std::string tag = fmt::format("inside{}", repro::level_tag(level));
    r.series("N", ns);
    r.series(fmt::format("{}.ssc", tag), ssc);
    r.series(fmt::format("{}.ssc_independent", tag), ssc_ind);
    r.series(fmt::format("{}.lie_independent", tag), ind);
    r.series(fmt::format("{}.lie_joint", tag), joint);
    r.series(fmt::format("{}.lie_fourth_order", tag), fourth);
    r.series("N_joint_fourth_order", n_j4);
    r.series(fmt::format("{}.lie_joint_fourth_order", tag), joint4);
    // The first N from which the fourth-order (independent) compounding keeps more samples inside than the
    // first-order joint method at every longer N; absent if it never does.
    std::size_t cross = ns.size();
    while (cross > 0 && fourth[cross - 1] > joint[cross - 1]) --cross;
    if (cross < ns.size()) r.metric("crossover.fourth_order_over_joint.N", ns[cross]);

    // "Closest" allows a tie within two Monte-Carlo standard errors of a fraction at the nominal level.
    const double tie = 2.0 * std::sqrt(level * (1.0 - level) / static_cast<double>(base.trajectories));
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

    repro::Figure f;
    f.file = fmt::format("{}.png", ex.id());
    f.width = 7.5;
    f.height = 5.5;
    f.title = "Fig. 5.8: fraction inside the 99.9 % ellipsoid vs trajectory length";
    repro::Panel panel;
    panel.xlabel = "number of composed poses N";
    panel.ylabel = "fraction of samples inside";
    panel.layers.push_back(repro::line_layer(ns, ssc, "SSC head-to-tail", "tab:red", "^"));
    panel.layers.push_back(repro::line_layer(ns, ssc_ind, "SSC, correlation ignored", "tab:orange", "v"));
    panel.layers.push_back(repro::line_layer(ns, ind, "Lie, correlation ignored", "tab:cyan", "s"));
    panel.layers.push_back(repro::line_layer(ns, fourth, "Lie, 4th order (independent)", "tab:purple", "x"));
    panel.layers.push_back(repro::line_layer(ns, joint, "Lie, joint (proposed)", "tab:green", "o"));
    panel.layers.push_back(repro::line_layer(n_j4, joint4, "Lie, joint 4th order (ours)", "tab:brown", "D"));
    panel.layers.push_back(repro::hline_layer(level, "nominal", "0.3"));
    f.panels.push_back(panel);
    r.figure(f);
  });
}
