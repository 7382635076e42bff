// Fig. 2.2 (§2.7.1.1) beyond the thesis: PCM-Heuristic's and PCM-Exact's rate of returning a set of the
// combinatorial maximum's size (eq. 2.5) as the 1D worlds get denser (outliers drawn closer to the true
// state) — thin driver over keel::eval::run_world1d_study, one study per density.
import keel.core;
import keel.repro;
import keel.pcm;
import keel.eval;

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/world1d.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace eval = keel::eval;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    eval::World1DStudyOptions o = keel::experiments::read_world1d_study(p);
    const auto ranges = p.numbers("outlier_mean_ranges");
    const double reference = p.number("reference_heuristic_rate");
    ex.params_done();
    // RANSAC and SCGP are read with the base experiment's parameters but not run here.
    o.selectors = {eval::Selector1D::combinatorial, eval::Selector1D::pcm_exact,
                   eval::Selector1D::pcm_heuristic};
    o.seed = ex.seed();
    o.threads = ex.threads();

    core::Progress progress(ex.id(), o.worlds * ranges.size());
    std::vector<double> heuristic, exact, max_size;
    auto& r = ex.results();
    for (std::size_t k = 0; k < ranges.size(); ++k) {
      o.world.outlier_mean_range = ranges[k];
      o.stream_base = 0;  // the same worlds' random streams at every density (common random numbers)
      try {
        o.validate();
      } catch (const std::invalid_argument& e) {
        throw core::ConfigError(
            fmt::format("{}: outlier_mean_ranges[{}] = {}: {}", p.file(), k, ranges[k], e.what()));
      }
      const eval::World1DStudy study = eval::run_world1d_study(o, &progress);
      const auto cmp = eval::compare_to_combinatorial(
          study, {eval::Selector1D::pcm_exact, eval::Selector1D::pcm_heuristic});
      exact.push_back(cmp.rows[0].match_rate);
      heuristic.push_back(cmp.rows[1].match_rate);
      double sum = 0;
      for (const auto& c : study.of(eval::Selector1D::combinatorial)) sum += c.size;
      max_size.push_back(sum / static_cast<double>(o.worlds));
      const std::string tag = fmt::format("range{:g}", ranges[k]);
      r.metric(tag + ".match_rate.pcm_heuristic", heuristic.back());
      r.metric(tag + ".match_rate.pcm_exact", exact.back());
      r.metric(tag + ".max_consistent_set.mean", max_size.back());
    }
    progress.finish();
    r.metric("worlds", static_cast<double>(o.worlds));
    r.series("outlier_mean_range", ranges);
    r.series("match_rate.pcm_heuristic", heuristic);
    r.series("match_rate.pcm_exact", exact);
    r.series("max_consistent_set.mean", max_size);
    double lowest = 1.0;
    for (double h : heuristic) lowest = std::min(lowest, h);
    r.metric("match_rate.pcm_heuristic.min", lowest);
    bool exact_always = true;
    for (double e : exact) exact_always = exact_always && e == 1.0;
    r.check("PCM-Exact returns a set of the combinatorial maximum's size in every world at every density",
            exact_always,
            fmt::format("lowest match rate {:.6f}", *std::min_element(exact.begin(), exact.end())), false);

    repro::Figure f;
    f.file = fmt::format("{}.png", ex.id());
    f.title = fmt::format("PCM-Heuristic on denser 1D worlds ({} worlds per R)", o.worlds);
    f.width = 7.5;
    f.height = 5.0;
    repro::Panel panel;
    panel.xlabel = "outlier mean range R (outlier means ~ U[x − R, x + R]); smaller is denser";
    panel.ylabel = "fraction of worlds with a set of the maximum's size";
    panel.xscale = "log";
    panel.layers.push_back(repro::line_layer(ranges, heuristic, "PCM-Heuristic", "tab:cyan", "o"));
    panel.layers.push_back(repro::line_layer(ranges, exact, "PCM-Exact", "tab:blue", "s"));
    panel.layers.push_back(
        repro::hline_layer(reference, fmt::format("thesis: PCM-Heuristic {:.4g} %", 100 * reference), "0.4"));
    f.panels.push_back(panel);
    r.figure(f);
  });
}
