#include "study/ch2/density_sweep.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "study/ch2/config.hpp"

namespace keel::study::ch2 {

using repro::Figure;
using repro::Panel;
using repro::Results;
using repro::RunContext;

// ---------------------------------------------------------------------------------------------------------------
// Density sweep

DensitySweep::Options DensitySweep::Options::read(const core::ConfigTable& p) {
  Options o;
  o.study = read_world1d_study(p);
  o.ranges = p.numbers("outlier_mean_ranges");
  o.reference_heuristic_rate = p.number("reference_heuristic_rate");
  // RANSAC and SCGP are read with the base experiment's parameters but not run here.
  o.study.selectors = {Selector1D::combinatorial, Selector1D::pcm_exact, Selector1D::pcm_heuristic};
  for (std::size_t k = 0; k < o.ranges.size(); ++k) {
    World1DStudyOptions at = o.study;
    at.world.outlier_mean_range = o.ranges[k];
    try {
      at.validate();
    } catch (const std::invalid_argument& e) {
      throw core::ConfigError(
          fmt::format("{}: outlier_mean_ranges[{}] = {}: {}", p.file(), k, o.ranges[k], e.what()));
    }
  }
  return o;
}

DensitySweep::Outcome DensitySweep::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  core::Progress progress = context.progress(o.study.worlds * o.ranges.size());
  for (double range : o.ranges) {
    World1DStudyOptions at = o.study;
    at.world.outlier_mean_range = range;
    // The same worlds' random streams at every density (common random numbers).
    const World1DStudy study = run_world1d_study(at, context, &progress);
    const auto cmp = compare_to_combinatorial(study, {Selector1D::pcm_exact, Selector1D::pcm_heuristic});
    out.exact.push_back(cmp.rows[0].match_rate);
    out.heuristic.push_back(cmp.rows[1].match_rate);
    double sum = 0;
    for (const auto& c : study.of(Selector1D::combinatorial)) sum += c.size;
    out.max_size.push_back(sum / static_cast<double>(o.study.worlds));
  }
  progress.finish();
  return out;
}

void DensitySweep::record(Results& r, const Outcome& out) {
  const auto& ranges = out.options.ranges;
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    const auto tag = r.under(fmt::format("range{:g}", ranges[k]));
    tag.metric("match_rate.pcm_heuristic", out.heuristic[k]);
    tag.metric("match_rate.pcm_exact", out.exact[k]);
    tag.metric("max_consistent_set.mean", out.max_size[k]);
  }
  r.metric("worlds", static_cast<double>(out.options.study.worlds));
  r.series("outlier_mean_range", ranges);
  r.series("match_rate.pcm_heuristic", out.heuristic);
  r.series("match_rate.pcm_exact", out.exact);
  r.series("max_consistent_set.mean", out.max_size);
  double lowest = 1.0;
  for (double h : out.heuristic) lowest = std::min(lowest, h);
  r.metric("match_rate.pcm_heuristic.min", lowest);
  bool exact_always = true;
  for (double e : out.exact) exact_always = exact_always && e == 1.0;
  r.check("PCM-Exact returns a set of the combinatorial maximum's size in every world at every density",
          exact_always,
          fmt::format("lowest match rate {:.6f}", *std::min_element(out.exact.begin(), out.exact.end())),
          false);
}

std::vector<Figure> DensitySweep::figures(const Outcome& out) {
  const auto& ranges = out.options.ranges;
  Figure f;
  f.file = ".png";
  f.title = fmt::format("PCM-Heuristic on denser 1D worlds ({} worlds per R)", out.options.study.worlds);
  f.width = 7.5;
  f.height = 5.0;
  Panel panel;
  panel.xlabel = "outlier mean range R (outlier means ~ U[x − R, x + R]); smaller is denser";
  panel.ylabel = "fraction of worlds with a set of the maximum's size";
  panel.xscale = "log";
  panel.layers.push_back(repro::line_layer(ranges, out.heuristic, "PCM-Heuristic", "tab:cyan", "o"));
  panel.layers.push_back(repro::line_layer(ranges, out.exact, "PCM-Exact", "tab:blue", "s"));
  const double reference = out.options.reference_heuristic_rate;
  panel.layers.push_back(
      repro::hline_layer(reference, fmt::format("thesis: PCM-Heuristic {:.4g} %", 100 * reference), "0.4"));
  f.panels.push_back(panel);
  return {f};
}

}  // namespace keel::study::ch2
