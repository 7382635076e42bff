#include "study/ch2/timing.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/world1d.hpp"
#include "study/ch2/config.hpp"

namespace keel::study::ch2 {

using repro::Figure;
using repro::Panel;
using repro::Results;
using repro::RunContext;

// ---------------------------------------------------------------------------------------------------------------
// Fig. 2.3

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
// The timing names of curve c, one per size it ran at.
std::vector<std::string> timing_names(const TimingCurve& curve) {
  std::vector<std::string> names;
  const auto at = repro::path("time").under(curve.name);
  for (double m : curve.m) names.push_back(at.key(fmt::format("m{:04d}", static_cast<int>(m))));
  return names;
}
}  // namespace

Timing::Options Timing::Options::read(const core::ConfigTable& p) {
  Options o;
  TimingSweepOptions& s = o.sweep;
  s.base.world = read_world1d_options(p, false);
  s.inlier_fraction = p.number("inlier_fraction");
  s.aliased_fraction = p.number("aliased_fraction");
  o.sizes = p.numbers("measurements");
  const double pcm_p = p.number("pcm_p"), ransac_p = p.number("ransac_p");
  s.base.scgp = read_scgp_options(p);
  s.exhaustive_max = static_cast<int>(p.integer("combinatorial_exhaustive_max_measurements"));
  s.pruned_max = static_cast<int>(p.integer("combinatorial_pruned_max_measurements"));
  s.base.worlds = p.count("worlds_per_size");
  for (double m : o.sizes) {
    if (!(m >= 1 && m == std::floor(m)))
      throw core::ConfigError(p.where("measurements") +
                              ": sizes must be positive integers in increasing order");
    s.sizes.push_back(static_cast<int>(m));
  }
  try {
    (void)sim::world1d_options_with_total(s.base.world, s.sizes.empty() ? 1 : s.sizes[0], s.inlier_fraction,
                                          s.aliased_fraction);
    s.validate();
  } catch (const std::invalid_argument& e) {
    throw core::ConfigError(fmt::format("{}: {}", p.file(), e.what()));
  }
  s.base.pcm_gamma = pcm::consistency_threshold(pcm_p, sim::kWorld1DDof);  // γ = χ²₁ quantile of 1 − p
  s.base.ransac_gamma = pcm::consistency_threshold(ransac_p, sim::kWorld1DDof);
  return o;
}

Timing::Outcome Timing::run(const Options& o, const RunContext& context) {
  core::Progress progress = context.progress(o.sweep.work());
  Outcome out{o, run_timing_sweep(o.sweep, context, &progress)};
  progress.finish();
  return out;
}

void Timing::record(Results& r, const Outcome& out) {
  const TimingSweep& sweep = out.sweep;
  for (const auto& curve : sweep.curves) {
    const auto names = timing_names(curve);
    for (std::size_t k = 0; k < curve.m.size(); ++k)
      r.timing(names[k], curve.median_time_s[k]);  // median wall time of one selection (s)
  }
  r.series("measurements", out.options.sizes);
  for (std::size_t c = 0; c < 2; ++c) r.under("measurements").series(sweep.curves[c].name, sweep.curves[c].m);
  for (const auto& curve : sweep.curves) r.under("size").under("mean").series(curve.name, curve.size_mean);
  r.series("match_rate.pcm_heuristic", sweep.heuristic_match);
  r.metric("worlds_per_size", static_cast<double>(out.options.sweep.base.worlds));
  r.metric("gamma.pcm", out.options.sweep.base.pcm_gamma);
  r.metric("gamma.ransac", out.options.sweep.base.ransac_gamma);
  r.check("PCM-Exact returns a set of the combinatorial maximum's size wherever the combinatorial search ran",
          sweep.combinatorial_checked > 0 && sweep.combinatorial_mismatch == 0,
          fmt::format("{} combinatorial runs (both variants), {} with a different size",
                      sweep.combinatorial_checked, sweep.combinatorial_mismatch));
}

std::vector<Figure> Timing::figures(const Outcome& out) {
  const TimingSweep& sweep = out.sweep;
  // Fig. 2.3: median time per selection and, beside it, the mean selected size (both log-log).
  Figure f;
  f.file = ".png";
  f.title = fmt::format(
      "Fig. 2.3: selection time vs number of measurements ({} worlds per size; Q not timed; "
      "machine-dependent)",
      out.options.sweep.base.worlds);
  f.width = 13.0;
  f.height = 5.0;
  Panel tp, sp;
  tp.xlabel = sp.xlabel = "number of measurements m";
  tp.ylabel = "median wall time per selection (s)";
  sp.ylabel = "mean number of selected measurements";
  tp.xscale = tp.yscale = sp.xscale = sp.yscale = "log";
  tp.legend = "upper left";
  sp.legend = "none";
  for (std::size_t c = 0; c < sweep.curves.size(); ++c) {
    const auto& st = kStyles[c];
    repro::Layer l = repro::line_layer(sweep.curves[c].m, {}, st.label, st.color, st.marker);
    l.y_timings = timing_names(sweep.curves[c]);
    tp.layers.push_back(l);
    sp.layers.push_back(
        repro::line_layer(sweep.curves[c].m, sweep.curves[c].size_mean, st.label, st.color, st.marker));
  }
  f.panels = {tp, sp};
  return {f};
}

}  // namespace keel::study::ch2
