#include "study/ch2/world1d_studies.hpp"

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

World1DStudyOptions read_world1d_study(const core::ConfigTable& p) {
  World1DStudyOptions o;
  o.world = read_world1d_options(p, true);
  o.pcm_gamma = pcm::consistency_threshold(p.number("pcm_p"), 1);
  o.ransac_gamma = pcm::consistency_threshold(p.number("ransac_p"), 1);
  o.scgp = read_scgp_options(p);
  o.combinatorial = p.parse("combinatorial", pcm::combinatorial_method_from_string);
  o.worlds = p.count("worlds");
  return o;
}

// ---------------------------------------------------------------------------------------------------------------
// Fig. 2.2

World1DComparison::Options World1DComparison::Options::read(const core::ConfigTable& p) {
  Options o{read_world1d_study(p)};
  try {
    o.study.validate();
  } catch (const std::invalid_argument& e) {
    throw core::ConfigError(fmt::format("{}: {}", p.file(), e.what()));
  }
  return o;
}

World1DComparison::Outcome World1DComparison::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  core::Progress progress = context.progress(o.study.worlds);
  out.study = run_world1d_study(o.study, context, &progress);
  progress.finish();
  out.comparison = compare_to_combinatorial(
      out.study, {Selector1D::pcm_exact, Selector1D::pcm_heuristic, Selector1D::scgp, Selector1D::ransac});
  return out;
}

void World1DComparison::record(Results& r, const Outcome& out) {
  const auto& cmp = out.comparison;
  const auto& comb = out.study.of(Selector1D::combinatorial);
  const std::size_t n = out.options.study.worlds;
  r.series("hist.size_diff.bins", cmp.size_diff_bins);
  r.series("hist.inconsistent_pairs.bins", cmp.inconsistent_bins);
  double m_sum = 0, max_sum = 0, comb_time = 0;
  for (std::size_t i = 0; i < n; ++i) {
    m_sum += out.study.measurements[i];
    max_sum += comb[i].size;
    comb_time += comb[i].time_s;
  }
  r.metric("worlds", static_cast<double>(n));
  r.metric("measurements.mean", m_sum / n);
  r.metric("max_consistent_set.mean", max_sum / n);
  r.metric("gamma.pcm", out.options.study.pcm_gamma);
  r.metric("gamma.ransac", out.options.study.ransac_gamma);
  r.timing("mean_time.combinatorial", comb_time / n);
  for (const auto& row : cmp.rows) {
    const std::string name(to_string(row.selector));
    r.metric("match_rate." + name, row.match_rate);
    r.metric("larger_rate." + name, row.larger_rate);
    r.metric("smaller_rate." + name, row.smaller_rate);
    r.metric("inconsistent_pairs.mean." + name, row.inconsistent_mean);
    r.metric("inconsistent_rate." + name, row.inconsistent_rate);
    r.series("hist.size_diff." + name, row.size_diff_hist);
    r.series("hist.inconsistent_pairs." + name, row.inconsistent_hist);
    r.timing("mean_time." + name, row.time_mean_s);
  }
  const auto &rx = cmp.rows[0], &rh = cmp.rows[1], &rs = cmp.rows[2], &rr = cmp.rows[3];
  r.check("PCM-Exact returns a set of the combinatorial maximum's size in every world (eq. 2.5)",
          rx.match_rate == 1.0,
          fmt::format("PCM-Exact has the combinatorial maximum's size in {:.0f} of {} worlds",
                      rx.match_rate * n, n));
  r.check("PCM selections are always pairwise consistent (0 inconsistent pairs, eq. 2.3)",
          rx.inconsistent_total == 0 && rh.inconsistent_total == 0,
          fmt::format("inconsistent pairs in PCM selections: exact {}, heuristic {} ({} worlds)",
                      rx.inconsistent_total, rh.inconsistent_total, n));
  r.check("PCM-Heuristic never returns more than PCM-Exact",
          cmp.heuristic_above_exact == 0 && rh.larger_rate == 0.0,
          fmt::format(
              "heuristic larger than exact in {} worlds; heuristic matches the maximum in {:.4f} of worlds",
              cmp.heuristic_above_exact, rh.match_rate));
  r.check(
      "SCGP and RANSAC do not enforce pairwise consistency (some of their selections hold inconsistent "
      "pairs)",
      rs.inconsistent_rate > 0.0 && rr.inconsistent_rate > 0.0,
      fmt::format("worlds with >= 1 inconsistent pair: SCGP {:.4f}, RANSAC {:.4f}; mean pairs: SCGP {:.3f}, "
                  "RANSAC {:.3f}",
                  rs.inconsistent_rate, rr.inconsistent_rate, rs.inconsistent_mean, rr.inconsistent_mean));
  r.check("RANSAC sometimes returns more and sometimes fewer measurements than the combinatorial maximum",
          rr.larger_rate > 0.0 && rr.smaller_rate > 0.0,
          fmt::format("RANSAC larger than the maximum in {:.4f} of worlds, smaller in {:.4f}", rr.larger_rate,
                      rr.smaller_rate));
}

std::vector<Figure> World1DComparison::figures(const Outcome& out) {
  const auto& cmp = out.comparison;
  // Plot range of the inconsistent-pair histograms: what covers 99.9 % of the worlds of every method (the
  // series keep the whole range).
  int ishow = 1;
  for (const auto& row : cmp.rows) {
    double cum = 0;
    for (std::size_t b = 0; b < row.inconsistent_hist.size(); ++b) {
      cum += row.inconsistent_hist[b];
      if (cum >= 0.999) {
        ishow = std::max(ishow, static_cast<int>(b) + 1);
        break;
      }
    }
  }
  // Fig. 2.2: first row, size returned − maximum size; second row, inconsistent pairs of the returned set.
  const char* titles[] = {"PCM-Exact", "PCM-Heuristic", "SCGP", "RANSAC"};
  const char* colors[] = {"tab:blue", "tab:green", "tab:orange", "tab:red"};
  Figure f;
  f.file = ".png";
  f.title = fmt::format("Fig. 2.2: selections on {} 1D worlds vs the combinatorial maximum (eq. 2.5)",
                        out.options.study.worlds);
  f.rows = 2;
  f.cols = 4;
  f.width = 16.0;
  f.height = 7.5;
  for (int row = 0; row < 2; ++row) {
    for (std::size_t k = 0; k < cmp.rows.size(); ++k) {
      Panel panel;
      panel.title = titles[k];
      panel.xlabel =
          row == 0 ? "size returned − maximum size" : "inconsistent pairs returned (99.9 % of worlds)";
      panel.ylabel = "fraction of worlds";
      panel.ylim = std::make_pair(0.0, 1.05);
      if (row == 1) panel.xlim = std::make_pair(-1.0, ishow + 0.5);
      panel.legend = "none";
      panel.layers.push_back(
          row == 0
              ? repro::histogram_layer(cmp.size_diff_bins, cmp.rows[k].size_diff_hist, "", colors[k])
              : repro::histogram_layer(cmp.inconsistent_bins, cmp.rows[k].inconsistent_hist, "", colors[k]));
      f.panels.push_back(panel);
    }
  }
  return {f};
}

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
    const std::string tag = fmt::format("range{:g}", ranges[k]);
    r.metric(tag + ".match_rate.pcm_heuristic", out.heuristic[k]);
    r.metric(tag + ".match_rate.pcm_exact", out.exact[k]);
    r.metric(tag + ".max_consistent_set.mean", out.max_size[k]);
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
  for (double m : curve.m) names.push_back(fmt::format("time.{}.m{:04d}", curve.name, static_cast<int>(m)));
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
  s.base.pcm_gamma = pcm::consistency_threshold(pcm_p, 1);  // γ = χ²₁ quantile of 1 − p (dof 1)
  s.base.ransac_gamma = pcm::consistency_threshold(ransac_p, 1);
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
  for (std::size_t c = 0; c < 2; ++c) r.series("measurements." + sweep.curves[c].name, sweep.curves[c].m);
  for (const auto& curve : sweep.curves) r.series("size.mean." + curve.name, curve.size_mean);
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
