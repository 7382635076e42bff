#include "study/ch3/hull_substitute.hpp"

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

namespace keel::study::ch3 {

using repro::Figure;
using repro::Layer;
using repro::Panel;
using repro::Results;
using repro::RunContext;

// ---------------------------------------------------------------------------------------------------------------
// Fig. 3.5

HullSubstitute::Options HullSubstitute::Options::read(const core::ConfigTable& p) {
  Options o;
  o.study.world = read_hull_world_options(p);
  o.study.compare = read_comparison_options(p);
  o.study.worlds = p.count("worlds");
  o.compare_without_gate = p.boolean("compare_without_gate");
  o.relocalised_within = p.number("relocalised_within");
  return o;
}

HullSubstitute::Outcome HullSubstitute::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  core::Progress progress = context.progress(o.study.worlds * (o.compare_without_gate ? 2 : 1));
  out.gated = run_hull_study(o.study, context, &progress);
  if (o.compare_without_gate) {
    HullStudyOptions u = o.study;
    u.compare.align.depth_gate = 0.0;
    out.ungated = run_hull_study(u, context, &progress);
  }
  progress.finish();
  // The Fig. 3.5 panels are drawn on world 0 (regenerated: same seed and stream).
  out.world0 = sim::make_hull_world(o.study.world, context.streams().seed(), context.streams().index(0));
  return out;
}

namespace {
// One method's row of the hull substitute: its errors (not squared) and rates.
struct HullRow {
  std::string name, label;
  std::vector<double> rot, trans, time;
  double valid_rate = 0, relocalised_rate = 0;
  bool proposed = false;
};
// `ungated`: the run without the depth gate (its keys under "no_gate.", its labels "(no gate)").
std::vector<HullRow> hull_rows(const HullStudyOutcome& out, bool ungated, double within) {
  std::vector<HullRow> rows;
  for (std::size_t m = 0; m < out.methods.size(); ++m) {
    HullRow row;
    row.name = std::string(align::to_string(out.methods[m]));
    row.label = row.name + (ungated ? " (no gate)" : "");
    row.proposed = out.methods[m] == Method::proposed;
    double valid = 0, relocalised = 0;
    for (const auto& w : out.outcomes[m]) {
      row.rot.push_back(std::sqrt(w.rot_se)), row.trans.push_back(std::sqrt(w.trans_se)),
          row.time.push_back(w.time_s);
      valid += w.valid, relocalised += std::sqrt(w.trans_se) < within;
    }
    const double n = static_cast<double>(out.outcomes[m].size());
    row.valid_rate = 100.0 * valid / n;
    row.relocalised_rate = 100.0 * relocalised / n;
    rows.push_back(std::move(row));
  }
  return rows;
}
}  // namespace

void HullSubstitute::record(Results& r, const Outcome& out) {
  const Options& o = out.options;
  r.metric("worlds", static_cast<double>(o.study.worlds));
  r.metric("depth_gate", o.study.compare.align.depth_gate);
  double proposed_median = -1;
  auto summarise = [&](const HullStudyOutcome& st, bool ungated) {
    for (const HullRow& row : hull_rows(st, ungated, o.relocalised_within)) {
      const double tmed = fenced_summary(row.trans).median;
      const auto at = ungated ? r.under("no_gate").under(row.name) : r.under(row.name);
      at.metric("rot_err.median", fenced_summary(row.rot).median);
      at.metric("trans_err.median", tmed);
      at.metric("valid_rate", row.valid_rate);
      at.metric("relocalised_rate", row.relocalised_rate);
      at.timing("time_s", core::mean_std(row.time).mean);
      if (!ungated && row.proposed) proposed_median = tmed;
    }
  };
  summarise(out.gated, false);
  if (out.ungated) summarise(*out.ungated, true);
  if (proposed_median >= 0)
    r.check(fmt::format("the proposed method re-localises the query: median translation error below {:g} m",
                        o.relocalised_within),
            proposed_median < o.relocalised_within,
            fmt::format("median {:.3g} m over {} worlds, depth gate {:g} m", proposed_median, o.study.worlds,
                        o.study.compare.align.depth_gate));
}

namespace {

// The second feature component, κ2, of every position.
std::vector<double> kappa2(const std::vector<double>& features) {
  std::vector<double> c;
  for (std::size_t n = 1; n < features.size(); n += sim::HullWorld::kFeatureDim) c.push_back(features[n]);
  return c;
}

// A survey drawn as its path (grey) and its positions coloured by κ2 (the second feature component).
void survey(Panel& panel, const std::vector<double>& x, const std::vector<double>& y,
            const std::vector<double>& features, double size, double vmin, double vmax,
            std::string path_color = "0.7", double path_width = 0.5) {
  std::vector<double> c = kappa2(features);
  panel.layers.push_back(repro::line_layer(x, y, "", std::move(path_color)));
  panel.layers.back().linewidth = path_width;
  Layer l = repro::scatter_layer(x, y, "", "k", size, 1.0, "o");
  l.c = std::move(c), l.cmap = "viridis", l.vmin = vmin, l.vmax = vmax;
  panel.layers.push_back(std::move(l));
}

// The figure on one world: (a) the reference and (b) the query (its own frame) coloured by κ2, (c) the query
// placed by `estimate` (raw; null: panel left empty), (d) by the ground truth.
Figure alignment_figure(const sim::HullWorld& w, const Transform2* estimate) {
  const std::vector<double> k2 = kappa2(w.ref_features);
  const auto [lo, hi] = std::minmax_element(k2.begin(), k2.end());
  Figure f;
  f.file = ".png";
  f.title =
      "SUBSTITUTE for Fig. 3.5: synthetic hull surveys aligned on DVL curvature (world 0, depth gate on)";
  f.rows = 2, f.cols = 2, f.width = 13.0, f.height = 8.5;
  Panel a, b, c, d;
  a.title = "(a) reference survey, coloured by κ₂",
  b.title = "(b) query survey (its own frame), coloured by κ₂";
  c.title = "(c) estimated alignment (proposed, raw)", d.title = "(d) ground truth alignment";
  for (auto* q : {&a, &b, &c, &d})
    q->xlabel = "x (m)", q->ylabel = "y (m)", q->aspect = "equal", q->colorbar = "κ₂ (1/m)";
  survey(a, w.ref_x, w.ref_y, w.ref_features, 10, *lo, *hi);
  survey(b, w.query_x, w.query_y, w.query_features, 16, *lo, *hi);
  const auto place = [&](Panel& q, const Transform2& t) {
    std::vector<double> x, y;
    for (std::size_t j = 0; j < w.query_x.size(); ++j) {
      x.push_back(t.a11 * w.query_x[j] + t.a12 * w.query_y[j] + t.tx);
      y.push_back(t.a21 * w.query_x[j] + t.a22 * w.query_y[j] + t.ty);
    }
    survey(q, w.ref_x, w.ref_y, w.ref_features, 5, *lo, *hi, "0.85");
    survey(q, x, y, w.query_features, 16, *lo, *hi, "k", 0.8);
  };
  if (estimate) place(c, *estimate);
  const double ct = std::cos(w.theta), st = std::sin(w.theta);
  place(d, {ct, -st, st, ct, w.tx, w.ty});
  f.panels = {a, b, c, d};
  return f;
}

}  // namespace

std::vector<Figure> HullSubstitute::figures(const Outcome& out) {
  const Options& o = out.options;
  // The Fig. 3.5 panels on world 0, then the errors' CDFs.
  const auto it = std::find(out.gated.methods.begin(), out.gated.methods.end(), Method::proposed);
  const Transform2* proposed =
      it == out.gated.methods.end()
          ? nullptr
          : &out.gated.outcomes[static_cast<std::size_t>(it - out.gated.methods.begin())][0].raw;
  Figure cdf;
  cdf.file = "_errors.png";
  cdf.title = fmt::format("SUBSTITUTE for §3.8: errors over {} synthetic hull worlds (empirical CDFs)",
                          o.study.worlds);
  Panel pr, pt;
  pr.xlabel = "rotation error |θ̂ − θ| (rad)";
  pt.xlabel = "translation error at the query centroid (m)";
  pr.ylabel = pt.ylabel = "fraction of worlds";
  pr.xscale = pt.xscale = "log";
  pt.legend = "none";
  Layer bound;
  bound.type = "vline", bound.value = o.relocalised_within, bound.color = "0.4", bound.linestyle = ":";
  pt.layers.push_back(bound);
  auto curves = [&](const HullStudyOutcome& st, bool ungated, const char* style) {
    const auto rows = hull_rows(st, ungated, o.relocalised_within);
    for (std::size_t m = 0; m < rows.size(); ++m) {
      pr.layers.push_back(
          repro::ecdf_layer(rows[m].rot, rows[m].label, kColors[m % 4], 1e-6, style));  // log axes
      pt.layers.push_back(repro::ecdf_layer(rows[m].trans, rows[m].label, kColors[m % 4], 1e-6, style));
    }
  };
  curves(out.gated, false, "-");
  if (out.ungated) curves(*out.ungated, true, "--");
  cdf.panels = {pr, pt};
  cdf.width = 12.0, cdf.height = 4.8;
  return {alignment_figure(out.world0, proposed), cdf};
}

}  // namespace keel::study::ch3
