// Fig. 5.9 (§5.9.1): consistency of composition against rotation and translation noise — thin driver.
import keel.core;
import keel.repro;
import keel.lie;

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace core = keel::core;
namespace repro = keel::repro;
namespace lie = keel::lie;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    lie::CompositionSetup base;
    base.steps = static_cast<int>(p.integer("steps"));
    base.rho = p.number("rho");
    const double level = p.number("level");
    base.levels = {level};
    const double fixed = p.number("fixed_sigma");
    const auto sigmas = p.numbers("sigma_values");
    base.trajectories = p.count("trajectories");
    ex.params_done();
    base.seed = ex.seed();
    base.threads = ex.threads();

    core::Progress progress(ex.id(), 2 * sigmas.size() * base.trajectories);
    auto& r = ex.results();
    struct Sweep {
      std::vector<double> ssc, ssc_ind, ind, joint, fourth, joint4;
    };
    auto sweep = [&](bool rotation, std::uint64_t offset) {
      Sweep w;
      for (std::size_t k = 0; k < sigmas.size(); ++k) {
        auto s = base;
        s.sigma_r = rotation ? sigmas[k] : fixed;
        s.sigma_t = rotation ? fixed : sigmas[k];
        s.stream_base = offset;  // common random numbers within a sweep
        const auto out = lie::run_composition_study(s, &progress);
        w.ssc.push_back(out.ssc.inside[0]);
        w.ssc_ind.push_back(out.ssc_independent.inside[0]);
        w.ind.push_back(out.lie_independent.inside[0]);
        w.joint.push_back(out.lie_joint.inside[0]);
        w.fourth.push_back(out.lie_fourth_order.inside[0]);
        if (!out.has_joint_fourth_order)
          throw std::runtime_error("the fourth-order joint chain was not evaluated");
        w.joint4.push_back(out.lie_joint_fourth_order.inside[0]);
      }
      return w;
    };
    const Sweep rot = sweep(true, 0), tra = sweep(false, std::uint64_t{1} << 32);
    progress.finish();

    for (const auto& [prefix, var, w] :
         {std::tuple{"rotation", "sigma_r", &rot}, std::tuple{"translation", "sigma_t", &tra}}) {
      const std::string pre = fmt::format("{}.inside{}", prefix, repro::level_tag(level));
      r.series(fmt::format("{}.{}", prefix, var), sigmas);
      r.series(fmt::format("{}.ssc", pre), w->ssc);
      r.series(fmt::format("{}.ssc_independent", pre), w->ssc_ind);
      r.series(fmt::format("{}.lie_independent", pre), w->ind);
      r.series(fmt::format("{}.lie_joint", pre), w->joint);
      r.series(fmt::format("{}.lie_fourth_order", pre), w->fourth);
      r.series(fmt::format("{}.lie_joint_fourth_order", pre), w->joint4);
    }

    // Claim checks on our numbers. "Closer" allows a tie within two Monte-Carlo standard errors at the level.
    const double tie = 2.0 * std::sqrt(level * (1.0 - level) / static_cast<double>(base.trajectories));
    // Effect of a noise source = how much the joint method's inside fraction falls from the smallest to the
    // largest σ.
    const double rot_effect = rot.joint.front() - rot.joint.back(),
                 tra_effect = tra.joint.front() - tra.joint.back();
    const double rot_effect_ssc = rot.ssc.front() - rot.ssc.back(),
                 tra_effect_ssc = tra.ssc.front() - tra.ssc.back();
    r.check(
        "rotation noise degrades consistency much more than translation noise",
        rot_effect > tra_effect + tie && rot_effect_ssc > tra_effect_ssc + tie,
        fmt::format("drop of inside fraction from σ = {:g} to {:g}: joint σr {:.4f} vs σt {:.4f}; SSC σr "
                    "{:.4f} vs σt "
                    "{:.4f}",
                    sigmas.front(), sigmas.back(), rot_effect, tra_effect, rot_effect_ssc, tra_effect_ssc));
    int joint_beats_ind = 0, total = 0, joint_beats_ssc = 0, ind_beats_ssc_ind = 0;
    auto closer = [&](double a, double b) { return std::fabs(a - level) <= std::fabs(b - level) + tie; };
    for (const Sweep* w : {&rot, &tra}) {
      for (std::size_t k = 0; k < sigmas.size(); ++k, ++total) {
        joint_beats_ind += closer(w->joint[k], w->ind[k]) ? 1 : 0;
        joint_beats_ssc += closer(w->joint[k], w->ssc[k]) ? 1 : 0;
        ind_beats_ssc_ind += closer(w->ind[k], w->ssc_ind[k]) ? 1 : 0;
      }
    }
    r.check("the joint method is more accurate than ignoring correlation at every sweep point",
            joint_beats_ind == total,
            fmt::format(
                "joint at least as close to {:.3f} as independent at {} of {} points (ties within {:.4f})",
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

    repro::Figure f;
    f.file = fmt::format("{}.png", ex.id());
    f.title = fmt::format("Fig. 5.9: fraction inside the 99.9 % ellipsoid vs noise (N = {})", base.steps);
    for (const auto& [title, xlabel, w] : {std::tuple{"rotation noise (σt = 3)", "σr", &rot},
                                           std::tuple{"translation noise (σr = 3)", "σt", &tra}}) {
      repro::Panel panel;
      panel.title = title;
      panel.xlabel = xlabel;
      panel.ylabel = "fraction of samples inside";
      panel.layers.push_back(repro::line_layer(sigmas, w->ssc, "SSC head-to-tail", "tab:red", "^"));
      panel.layers.push_back(
          repro::line_layer(sigmas, w->ssc_ind, "SSC, correlation ignored", "tab:orange", "v"));
      panel.layers.push_back(repro::line_layer(sigmas, w->ind, "Lie, correlation ignored", "tab:cyan", "s"));
      panel.layers.push_back(
          repro::line_layer(sigmas, w->fourth, "Lie, 4th order (independent)", "tab:purple", "x"));
      panel.layers.push_back(repro::line_layer(sigmas, w->joint, "Lie, joint (proposed)", "tab:green", "o"));
      panel.layers.push_back(
          repro::line_layer(sigmas, w->joint4, "Lie, joint 4th order (ours)", "tab:brown", "D"));
      panel.layers.push_back(repro::hline_layer(level, "nominal", "0.3"));
      f.panels.push_back(panel);
    }
    r.figure(f);
  });
}
