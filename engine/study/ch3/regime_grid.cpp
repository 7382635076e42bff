#include "study/ch3/regime_grid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "core/statistics.hpp"
#include "datasets/manifest.hpp"
#include "repro/grading.hpp"
#include "study/ch3/config.hpp"
#include "study/ch3/shared.hpp"
#include "study/ch3/sweep.hpp"

namespace keel::study::ch3 {

using repro::Figure;
using repro::Layer;
using repro::Panel;
using repro::Results;
using repro::RunContext;

// ---------------------------------------------------------------------------------------------------------------
// Beyond Table 3.1: the regime grid

RegimeGrid::Options RegimeGrid::Options::read(const core::ConfigTable& p) {
  Options o;
  o.study.world = read_alignment_world_options(p);
  o.study.compare = read_comparison_options(p);
  o.study.worlds = p.count("worlds");
  o.scales = read_sigma_ranges(p);
  o.noises = p.numbers("noise_values");
  o.sizes = p.numbers("query_sizes");
  for (const auto& [key, n] :
       {std::pair{"field_sigma_min", o.scales.size()}, std::pair{"noise_values", o.noises.size()},
        std::pair{"query_sizes", o.sizes.size()}})
    if (n == 0) throw core::ConfigError(fmt::format("{}: must not be empty", p.where(key)));
  for (double n : o.noises)
    if (!(n >= 0))
      throw core::ConfigError(fmt::format("{}: {} is not a noise std >= 0", p.where("noise_values"), n));
  for (double s : o.sizes)
    if (!(s > 0 && s <= o.study.world.reference_size))
      throw core::ConfigError(fmt::format("{}: {} m is not in (0, reference_size = {} m]",
                                          p.where("query_sizes"), s, o.study.world.reference_size));
  o.study.compare.certify = false;
  return o;
}

std::vector<RegimeGrid::Point> RegimeGrid::Options::cells() const {
  std::vector<Point> cells;
  for (double size : sizes)
    for (double noise : noises)
      for (const auto& [lo, hi] : scales) cells.push_back(Point{noise, size, lo, hi});
  return cells;
}

sim::AlignmentWorldOptions RegimeGrid::Options::world_at(const Point& p) const {
  return world_of_point(study.world, p);
}

RegimeGrid::Outcome RegimeGrid::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  const std::vector<Point> cells = o.cells();
  core::Progress progress = context.progress(cells.size() * o.study.worlds);
  for (const Point& p : cells) {
    AlignmentStudyOptions q = o.study;
    q.world = o.world_at(p);
    out.cells.push_back(run_alignment_study(q, context, &progress));  // the same worlds in every cell
  }
  progress.finish();
  return out;
}

namespace {

// One cell's summary per method: the quartiles of both errors and the valid rate (95 % Wilson interval).
struct CellSummary {
  double rot[3] = {}, trans[3] = {};  // q25, median, q75
  core::Proportion valid;
};
CellSummary cell_summary(const AlignmentStudyOutcome& st, std::size_t m) {
  std::vector<double> rs, ts;
  double ok = 0;
  for (const auto& w : st.outcomes[m]) rs.push_back(w.rot_se), ts.push_back(w.trans_se), ok += w.valid;
  CellSummary c;
  for (int k = 0; k < 3; ++k)
    c.rot[k] = quantile(rs, 0.25 * (k + 1)), c.trans[k] = quantile(ts, 0.25 * (k + 1));
  c.valid = core::wilson_interval(ok, static_cast<double>(st.outcomes[m].size()));
  return c;
}

// Proposed against each other method on the validity indicator (0 or 100 per world): the difference of the
// valid rates (percentage points) with its paired bootstrap interval, added under
// "<prefix>.valid_rate.<other>".
void add_paired_validity(repro::PairedFamily& family, const repro::KeyPath& prefix,
                         const AlignmentStudyOutcome& st) {
  const std::size_t p = proposed_index(st);
  if (p == SIZE_MAX) return;
  const auto valid = [&](std::size_t m) {
    std::vector<double> v;
    for (const auto& w : st.outcomes[m]) v.push_back(w.valid ? 1.0 : 0.0);
    return v;
  };
  for (std::size_t m = 0; m < st.methods.size(); ++m)
    if (m != p)
      family.add(prefix.under("valid_rate").under(align::to_string(st.methods[m])).name(),
                 repro::paired_rate(valid(p), valid(m)));
}

}  // namespace

void RegimeGrid::record(Results& r, const Outcome& out) {
  const Options& o = out.options;
  const std::vector<Point> cells = o.cells();
  r.metric("worlds", static_cast<double>(o.study.worlds));
  r.metric("cells", static_cast<double>(cells.size()));
  std::vector<double> lo, hi, noise, size, bumps;
  const Point base{o.study.world.feature_noise, o.study.world.query_size, o.study.world.bump_sigma_min,
                   o.study.world.bump_sigma_max};
  double default_cell = -1;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const Point& p = cells[c];
    lo.push_back(p.sigma_min), hi.push_back(p.sigma_max), noise.push_back(p.noise), size.push_back(p.size);
    bumps.push_back(o.world_at(p).bumps);
    if (!(p < base) && !(base < p)) default_cell = static_cast<double>(c);
  }
  r.series("cell.sigma_min", lo);
  r.series("cell.sigma_max", hi);
  r.series("cell.noise", noise);
  r.series("cell.size", size);
  r.series("cell.bumps", bumps);
  r.metric("default_cell", default_cell);  // the cell of ch3_table3_1_alignment's operating point (-1: none)

  const std::vector<Method>& methods = o.study.compare.methods;
  for (std::size_t m = 0; m < methods.size(); ++m) {
    std::map<std::string, std::vector<double>> series;
    for (const auto& st : out.cells) {
      const CellSummary c = cell_summary(st, m);
      const char* q[] = {"q25", "median", "q75"};
      for (int k = 0; k < 3; ++k) {
        series[repro::path("rot_se").key(q[k])].push_back(c.rot[k]);
        series[repro::path("trans_se").key(q[k])].push_back(c.trans[k]);
      }
      series["valid_rate"].push_back(100.0 * c.valid.rate);
      series["valid_rate.ci_low"].push_back(100.0 * c.valid.low);
      series["valid_rate.ci_high"].push_back(100.0 * c.valid.high);
    }
    for (auto& [key, v] : series) r.under(align::to_string(methods[m])).series(key, std::move(v));
  }

  // Paired: Proposed minus each other method in every cell; per cell, the number of other methods Proposed is
  // significantly below (or above) in each error, and in validity. The family: every comparison of every
  // cell.
  repro::PairedFamily family;
  for (std::size_t c = 0; c < out.cells.size(); ++c) {
    add_paired_at(family, repro::path(fmt::format("cell{}", c)), out.cells[c]);
    add_paired_validity(family, repro::path(fmt::format("cell{}", c)), out.cells[c]);
  }
  family.adjust();
  record_family(r, family);
  std::map<std::string, std::vector<double>> series;
  ProposedTally tally;
  std::string where;  // the cells where the thesis's error ordering holds
  for (std::size_t c = 0; c < out.cells.size(); ++c) {
    const auto prefix = repro::path(fmt::format("cell{}", c));
    const PairedAtPoint pp = paired_at(family, prefix, out.cells[c]);
    if (pp.others.empty()) continue;
    tally.add(pp);
    std::vector<repro::PairedComparison> pv;
    for (const auto& other : pp.others)
      pv.push_back(family.at(prefix.under("valid_rate").under(other).name()));
    for (std::size_t k = 0; k < pp.others.size(); ++k)
      for (const auto& [label, pc] : {std::pair{"rot_se", pp.rot[k]}, std::pair{"trans_se", pp.trans[k]},
                                      std::pair{"valid_rate", pv[k]}}) {
        const auto key = repro::path("paired").under(label).under(pp.others[k]);
        series[key.key("difference")].push_back(pc.difference);
        if (std::string_view(label) != "valid_rate")
          series[key.key("difference_of_medians")].push_back(pc.difference_of_medians);
        series[key.key("low")].push_back(pc.low);
        series[key.key("high")].push_back(pc.high);
        series[key.key("p")].push_back(pc.p);
        series[key.key("adjusted_p")].push_back(pc.adjusted_p);
      }
    const int n = static_cast<int>(pp.others.size());
    const int br = count_if_paired(pp.rot, true), bt = count_if_paired(pp.trans, true);
    const int ar = count_if_paired(pp.rot, false), at = count_if_paired(pp.trans, false);
    series["proposed_below.rot_se"].push_back(br), series["proposed_below.trans_se"].push_back(bt);
    series["proposed_above.rot_se"].push_back(ar), series["proposed_above.trans_se"].push_back(at);
    series["proposed_above.valid_rate"].push_back(count_if_paired(pv, false));
    series["proposed_below.valid_rate"].push_back(count_if_paired(pv, true));
    if (br == n && bt == n)
      where += fmt::format("{}σ ∈ [{:g}, {:g}] m, noise {:g}, query {:g} m", where.empty() ? "" : "; ",
                           cells[c].sigma_min, cells[c].sigma_max, cells[c].noise, cells[c].size);
  }
  for (auto& [key, v] : series) r.series(key, std::move(v));
  tally.record(r);
  r.metric("proposed_best.both", tally.best_both);
  if (tally.points > 0)
    r.check(
        "Table 3.1's error ordering (Proposed significantly below SOConvHull, Symmetric and Affine in both "
        "rotation and translation SE, paired rule, Holm-corrected over the grid's comparisons) holds in some "
        "cell of "
        "the grid",
        tally.best_both > 0,
        fmt::format("{} of {} cells, {} worlds each{}{}", tally.best_both, tally.points, o.study.worlds,
                    where.empty() ? "" : ": ", where));
}

// The regime map: one row of panels per (noise, query size), the σ range along x (its midpoint, log axis);
// per method the median with its interquartile bar for both errors, and the valid rate with its Wilson bar.
std::vector<Figure> RegimeGrid::figures(const Outcome& out) {
  const Options& o = out.options;
  const std::vector<Point> cells = o.cells();
  const std::size_t per_row = o.scales.size(), rows = o.noises.size() * o.sizes.size();
  Figure f;
  f.file = ".png";
  f.title = fmt::format(
      "Beyond Table 3.1: regime map, {} worlds per cell (errors: median and interquartile bar; "
      "valid: 95 % Wilson bar)",
      o.study.worlds);
  f.rows = static_cast<int>(rows), f.cols = 3, f.width = 16.5, f.height = 3.8 * static_cast<double>(rows);
  const char* markers[] = {"o", "s", "^", "v"};
  const std::size_t methods = o.study.compare.methods.size();
  for (std::size_t row = 0; row < rows; ++row) {
    const Point& first = cells[row * per_row];
    const std::string where = fmt::format("noise {:g}, query {:g} m", first.noise, first.size);
    Panel pr, pt, pv;
    pr.title = "rotation SE, " + where, pt.title = "translation SE, " + where,
    pv.title = "approx. valid, " + where;
    pr.ylabel = "rad²", pt.ylabel = "m²", pv.ylabel = "% of worlds";
    pr.xlabel = pt.xlabel = pv.xlabel = "feature bump σ, middle of its range (m); tracklines 2 m apart";
    pr.xscale = pt.xscale = pv.xscale = "log";
    pr.yscale = pt.yscale = "log";
    pt.legend = pv.legend = "none";
    pv.ylim = std::make_pair(-5.0, 105.0);
    for (std::size_t m = 0; m < methods; ++m) {
      // Methods side by side at each σ (a small multiplicative offset) so their bars do not overlap.
      const double shift = std::exp(0.04 * (static_cast<double>(m) - 0.5 * static_cast<double>(methods - 1)));
      std::vector<double> x, rot, trans, valid;
      Layer rbar, tbar, vbar;
      for (auto* b : {&rbar, &tbar, &vbar}) b->type = "segments", b->color = kColors[m % 4];
      for (std::size_t k = 0; k < per_row; ++k) {
        const std::size_t c = row * per_row + k;
        const double xk = 0.5 * (cells[c].sigma_min + cells[c].sigma_max) * shift;
        const CellSummary s = cell_summary(out.cells[c], m);
        x.push_back(xk);
        rot.push_back(std::max(s.rot[1], 1e-12)), trans.push_back(std::max(s.trans[1], 1e-12));  // log axis
        valid.push_back(100.0 * s.valid.rate);
        for (auto* b : {&rbar, &tbar, &vbar}) b->x0.push_back(xk), b->x1.push_back(xk);
        rbar.y0.push_back(std::max(s.rot[0], 1e-12)), rbar.y1.push_back(std::max(s.rot[2], 1e-12));
        tbar.y0.push_back(std::max(s.trans[0], 1e-12)), tbar.y1.push_back(std::max(s.trans[2], 1e-12));
        vbar.y0.push_back(100.0 * s.valid.low), vbar.y1.push_back(100.0 * s.valid.high);
      }
      const std::string name(align::to_string(o.study.compare.methods[m]));
      pr.layers.push_back(repro::line_layer(x, rot, name, kColors[m % 4], markers[m % 4]));
      pt.layers.push_back(repro::line_layer(x, trans, name, kColors[m % 4], markers[m % 4]));
      pv.layers.push_back(repro::line_layer(x, valid, name, kColors[m % 4], markers[m % 4]));
      pr.layers.push_back(rbar), pt.layers.push_back(tbar), pv.layers.push_back(vbar);
    }
    f.panels.push_back(pr), f.panels.push_back(pt), f.panels.push_back(pv);
  }
  return {f};
}

}  // namespace keel::study::ch3
