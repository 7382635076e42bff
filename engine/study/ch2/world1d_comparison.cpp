#include "study/ch2/world1d_comparison.hpp"

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
    r.under("match_rate").metric(name, row.match_rate);
    r.under("larger_rate").metric(name, row.larger_rate);
    r.under("smaller_rate").metric(name, row.smaller_rate);
    r.under("inconsistent_pairs").under("mean").metric(name, row.inconsistent_mean);
    r.under("inconsistent_rate").metric(name, row.inconsistent_rate);
    r.under("hist").under("size_diff").series(name, row.size_diff_hist);
    r.under("hist").under("inconsistent_pairs").series(name, row.inconsistent_hist);
    r.under("mean_time").timing(name, row.time_mean_s);
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

}  // namespace keel::study::ch2
