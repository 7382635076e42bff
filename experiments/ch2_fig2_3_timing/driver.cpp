// Fig. 2.3 (§2.7.1.2): selection time against the number of measurements on simulated 1D worlds — thin driver
// over keel::eval::run_timing_sweep. Wall times go through Results::timing (never diffed; the figure refers
// to them by name); deterministic quantities (mean selected sizes, heuristic match rates) are series.
import keel.core;
import keel.repro;
import keel.pcm;
import keel.sim;
import keel.eval;

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace core = keel::core;
namespace repro = keel::repro;
namespace pcm = keel::pcm;
namespace sim = keel::sim;
namespace eval = keel::eval;

namespace {

// How each curve of run_timing_sweep is drawn (same order).
struct Style {
  const char *label, *color, *marker;
};
const Style kStyles[] = {{"Combinatorial (all 2^m subsets)", "k", "x"},
                         {"Combinatorial (pruned subset search)", "0.5", "+"},
                         {"PCM-Exact", "tab:blue", "o"},
                         {"PCM-Heuristic", "tab:green", "s"},
                         {"SCGP", "tab:orange", "^"},
                         {"RANSAC", "tab:red", "v"}};

}  // namespace

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    eval::TimingSweepOptions o;
    o.base.world = eval::read_world1d_options(p, false);
    o.inlier_fraction = p.number("inlier_fraction");
    o.aliased_fraction = p.number("aliased_fraction");
    const auto sizes = p.numbers("measurements");
    const double pcm_p = p.number("pcm_p"), ransac_p = p.number("ransac_p");
    o.base.scgp = eval::read_scgp_options(p);
    o.exhaustive_max = static_cast<int>(p.integer("combinatorial_exhaustive_max_measurements"));
    o.pruned_max = static_cast<int>(p.integer("combinatorial_pruned_max_measurements"));
    o.base.worlds = p.count("worlds_per_size");
    ex.params_done();
    for (double m : sizes) {
      if (!(m >= 1 && m == std::floor(m)))
        throw core::ConfigError(p.where("measurements") +
                                ": sizes must be positive integers in increasing order");
      o.sizes.push_back(static_cast<int>(m));
    }
    try {
      (void)sim::world1d_options_with_total(o.base.world, o.sizes.empty() ? 1 : o.sizes[0], o.inlier_fraction,
                                            o.aliased_fraction);
      o.validate();
    } catch (const std::invalid_argument& e) {
      throw core::ConfigError(fmt::format("{}: {}", p.file(), e.what()));
    }
    o.base.pcm_gamma = pcm::consistency_threshold(pcm_p, 1);  // γ = χ²₁ quantile of 1 − p (dof 1)
    o.base.ransac_gamma = pcm::consistency_threshold(ransac_p, 1);
    o.base.seed = ex.seed();
    o.base.threads = ex.threads();

    core::Progress progress(ex.id(), o.work());
    const auto sweep = eval::run_timing_sweep(o, &progress);
    progress.finish();
    auto& r = ex.results();
    std::vector<std::vector<std::string>> timing_names(sweep.curves.size());
    for (std::size_t c = 0; c < sweep.curves.size(); ++c) {
      const auto& curve = sweep.curves[c];
      for (std::size_t k = 0; k < curve.m.size(); ++k) {
        const std::string name = fmt::format("time.{}.m{:04d}", curve.name, static_cast<int>(curve.m[k]));
        r.timing(name, curve.median_time_s[k]);  // median wall time of one selection (s)
        timing_names[c].push_back(name);
      }
    }
    r.series("measurements", sizes);
    for (std::size_t c = 0; c < 2; ++c) r.series("measurements." + sweep.curves[c].name, sweep.curves[c].m);
    for (const auto& curve : sweep.curves) r.series("size.mean." + curve.name, curve.size_mean);
    r.series("match_rate.pcm_heuristic", sweep.heuristic_match);
    r.metric("worlds_per_size", static_cast<double>(o.base.worlds));
    r.metric("gamma.pcm", o.base.pcm_gamma);
    r.metric("gamma.ransac", o.base.ransac_gamma);
    r.check(
        "PCM-Exact returns a set of the combinatorial maximum's size wherever the combinatorial search ran",
        sweep.combinatorial_checked > 0 && sweep.combinatorial_mismatch == 0,
        fmt::format("{} combinatorial runs (both variants), {} with a different size",
                    sweep.combinatorial_checked, sweep.combinatorial_mismatch));

    // Fig. 2.3: median time per selection and, beside it, the mean selected size (both log-log).
    repro::Figure f;
    f.file = ex.id() + ".png";
    f.title = fmt::format(
        "Fig. 2.3: selection time vs number of measurements ({} worlds per size; Q not timed; "
        "machine-dependent)",
        o.base.worlds);
    f.width = 13.0;
    f.height = 5.0;
    repro::Panel tp, sp;
    tp.xlabel = sp.xlabel = "number of measurements m";
    tp.ylabel = "median wall time per selection (s)";
    sp.ylabel = "mean number of selected measurements";
    tp.xscale = tp.yscale = sp.xscale = sp.yscale = "log";
    tp.legend = "upper left";
    sp.legend = "none";
    for (std::size_t c = 0; c < sweep.curves.size(); ++c) {
      const auto& st = kStyles[c];
      repro::Layer l = repro::line_layer(sweep.curves[c].m, {}, st.label, st.color, st.marker);
      l.y_timings = timing_names[c];
      tp.layers.push_back(l);
      sp.layers.push_back(
          repro::line_layer(sweep.curves[c].m, sweep.curves[c].size_mean, st.label, st.color, st.marker));
    }
    f.panels = {tp, sp};
    r.figure(f);
  });
}
