// Fig. 3.5 (§3.8) on a SUBSTITUTE: synthetic hull surveys aligned by standardised DVL curvature features in
// the known-depth case — thin driver over keel::align::run_hull_study, with sim::make_hull_world for the
// figure's world (same seed and stream, so the same world).
import keel.core;
import keel.repro;
import keel.sim;
import keel.align;

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "ch3_fig3_5_hull_substitute/report.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace sim = keel::sim;
namespace align = keel::align;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    align::HullStudyOptions o;
    o.world = align::read_hull_world_options(p);
    o.compare = align::read_comparison_options(p);
    o.worlds = p.count("worlds");
    const bool without_gate = p.boolean("compare_without_gate");
    const double within = p.number("relocalised_within");
    ex.params_done();
    o.seed = ex.seed();
    o.threads = ex.threads();

    core::Progress progress(ex.id(), o.worlds * (without_gate ? 2 : 1));
    const auto gated = align::run_hull_study(o, &progress);
    align::HullStudyOutcome ungated;
    if (without_gate) {
      align::HullStudyOptions u = o;
      u.compare.align.depth_gate = 0.0;
      ungated = align::run_hull_study(u, &progress);
    }
    progress.finish();

    auto& r = ex.results();
    r.metric("worlds", static_cast<double>(o.worlds));
    r.metric("depth_gate", o.compare.align.depth_gate);
    repro::Figure cdf;
    cdf.file = ex.id() + "_errors.png";
    cdf.title =
        fmt::format("SUBSTITUTE for §3.8: errors over {} synthetic hull worlds (empirical CDFs)", o.worlds);
    repro::Panel pr, pt;
    pr.xlabel = "rotation error |θ̂ − θ| (rad)";
    pt.xlabel = "translation error at the query centroid (m)";
    pr.ylabel = pt.ylabel = "fraction of worlds";
    pr.xscale = pt.xscale = "log";
    pt.legend = "none";
    repro::Layer bound;
    bound.type = "vline", bound.value = within, bound.color = "0.4", bound.linestyle = ":";
    pt.layers.push_back(bound);
    const char* colors[] = {"tab:blue", "tab:orange", "tab:green", "tab:red"};
    double proposed_median = -1;
    auto summarise = [&](const align::HullStudyOutcome& out, const std::string& prefix, const char* style) {
      for (std::size_t m = 0; m < out.methods.size(); ++m) {
        const std::string name = prefix + std::string(align::to_string(out.methods[m]));
        std::vector<double> rot, trans, time;
        double valid = 0, relocalised = 0;
        for (const auto& w : out.outcomes[m]) {
          rot.push_back(std::sqrt(w.rot_se)), trans.push_back(std::sqrt(w.trans_se)),
              time.push_back(w.time_s);
          valid += w.valid, relocalised += std::sqrt(w.trans_se) < within;
        }
        const double n = static_cast<double>(out.outcomes[m].size());
        const double tmed = align::fenced_summary(trans).median;
        r.metric(name + ".rot_err.median", align::fenced_summary(rot).median);
        r.metric(name + ".trans_err.median", tmed);
        r.metric(name + ".valid_rate", 100.0 * valid / n);
        r.metric(name + ".relocalised_rate", 100.0 * relocalised / n);
        r.timing(name + ".time_s", core::mean_std(time).mean);
        if (prefix.empty() && out.methods[m] == align::Method::proposed) proposed_median = tmed;
        const std::string label = name.substr(prefix.size()) + (prefix.empty() ? "" : " (no gate)");
        pr.layers.push_back(repro::ecdf_layer(rot, label, colors[m % 4], 1e-6, style));  // log axes
        pt.layers.push_back(repro::ecdf_layer(trans, label, colors[m % 4], 1e-6, style));
      }
    };
    summarise(gated, "", "-");
    if (without_gate) summarise(ungated, "no_gate.", "--");
    cdf.panels = {pr, pt};
    cdf.width = 12.0, cdf.height = 4.8;
    if (proposed_median >= 0)
      r.check(fmt::format("the proposed method re-localises the query: median translation error below {:g} m",
                          within),
              proposed_median < within,
              fmt::format("median {:.3g} m over {} worlds, depth gate {:g} m", proposed_median, o.worlds,
                          o.compare.align.depth_gate));

    // The Fig. 3.5 panels on world 0 (regenerated: same seed and stream).
    const auto it = std::find(gated.methods.begin(), gated.methods.end(), align::Method::proposed);
    const align::Transform2* proposed =
        it == gated.methods.end()
            ? nullptr
            : &gated.outcomes[static_cast<std::size_t>(it - gated.methods.begin())][0].raw;
    r.figure(keel::experiments::fig3_5::alignment_figure(
        ex.id(), sim::make_hull_world(o.world, o.seed, o.stream_base), proposed));
    r.figure(cdf);
  });
}
