#include "study/ch3/sensitivity.hpp"

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
// Sensitivity

Sensitivity::Options Sensitivity::Options::read(const core::ConfigTable& p) {
  Options o;
  o.study.world = read_alignment_world_options(p);
  o.study.compare = read_comparison_options(p);
  o.study.worlds = p.count("worlds");
  o.noises = p.numbers("noise_values");
  o.sizes = p.numbers("query_sizes");
  if (o.noises.empty())
    throw core::ConfigError(fmt::format("{}: must not be empty", p.where("noise_values")));
  if (o.sizes.empty()) throw core::ConfigError(fmt::format("{}: must not be empty", p.where("query_sizes")));
  if (p.has("field_sigma_min") || p.has("field_sigma_max")) o.scales = read_sigma_ranges(p);
  o.study.compare.certify = false;
  return o;
}

std::vector<Sensitivity::Point> Sensitivity::Options::axis(int which) const {
  const Point base{study.world.feature_noise, study.world.query_size, study.world.bump_sigma_min,
                   study.world.bump_sigma_max};
  std::vector<Point> points;
  if (which == 0)
    for (double n : noises) points.push_back(Point{n, base.size, base.sigma_min, base.sigma_max});
  if (which == 1)
    for (double s : sizes) points.push_back(Point{base.noise, s, base.sigma_min, base.sigma_max});
  if (which == 2)
    for (const auto& [lo, hi] : scales) points.push_back(Point{base.noise, base.size, lo, hi});
  return points;
}

sim::AlignmentWorldOptions Sensitivity::Options::world_at(const Point& p) const {
  return world_of_point(study.world, p);
}

const AlignmentStudyOutcome& Sensitivity::Outcome::at(const Point& p) const { return points.at(p); }

Sensitivity::Outcome Sensitivity::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  std::vector<Point> order;  // the points in the order the sweeps visit them
  for (int a = 0; a < 3; ++a)
    for (const Point& p : o.axis(a)) order.push_back(p);
  std::map<Point, int> seen;
  for (const auto& p : order) seen[p] = 1;
  const std::size_t distinct = seen.size();
  core::Progress progress = context.progress(distinct * o.study.worlds);
  for (const Point& p : order) {
    if (out.points.count(p)) continue;
    AlignmentStudyOptions q = o.study;
    q.world = o.world_at(p);
    out.points.emplace(p, run_alignment_study(q, context, &progress));  // same worlds
  }
  progress.finish();
  return out;
}

namespace {
struct SensitivityAxis {
  std::string tag, what, xlabel;
  std::vector<Sensitivity::Point> points;
  std::vector<double> x;  // the swept value (for a σ range: its midpoint)
};
std::vector<SensitivityAxis> sensitivity_axes(const Sensitivity::Options& o) {
  std::vector<SensitivityAxis> axes = {
      {"noise", "feature noise", "feature noise std (field RMS 1)", o.axis(0), o.noises},
      {"size", "query size", "query square side (m), reference 60 m", o.axis(1), o.sizes}};
  if (!o.scales.empty()) {
    std::vector<double> mid;
    for (const auto& [lo, hi] : o.scales) mid.push_back(0.5 * (lo + hi));
    axes.push_back({"scale", "field length scale",
                    "feature bump σ, middle of its range (m); tracklines 2 m apart", o.axis(2), mid});
  }
  return axes;
}
// Per method: the median rotation SE, median translation SE and valid rate (with its Wilson interval) at each
// point of the axis.
struct SensitivityCurve {
  std::string name;
  std::vector<double> rot, trans, valid, valid_low, valid_high;
};
std::vector<SensitivityCurve> sensitivity_curves(const Sensitivity::Outcome& out,
                                                 const SensitivityAxis& axis) {
  const auto& o = out.options;
  std::vector<SensitivityCurve> curves;
  for (std::size_t m = 0; m < o.study.compare.methods.size(); ++m) {
    SensitivityCurve c;
    c.name = std::string(align::to_string(o.study.compare.methods[m]));
    for (const auto& p : axis.points) {
      const auto& st = out.at(p);
      std::vector<double> rs, ts;
      double ok = 0;
      for (const auto& w : st.outcomes[m]) rs.push_back(w.rot_se), ts.push_back(w.trans_se), ok += w.valid;
      c.rot.push_back(fenced_summary(rs).median);
      c.trans.push_back(fenced_summary(ts).median);
      const core::Proportion v = core::wilson_interval(ok, static_cast<double>(o.study.worlds));
      c.valid.push_back(100.0 * v.rate), c.valid_low.push_back(100.0 * v.low),
          c.valid_high.push_back(100.0 * v.high);
    }
    curves.push_back(std::move(c));
  }
  return curves;
}
}  // namespace

void Sensitivity::record(Results& r, const Outcome& out) {
  r.metric("worlds", static_cast<double>(out.options.study.worlds));
  r.series("noise.feature_noise", out.options.noises);
  r.series("size.query_size", out.options.sizes);
  if (!out.options.scales.empty()) {
    std::vector<double> lo, hi, bumps;
    for (const Point& p : out.options.axis(2)) {
      lo.push_back(p.sigma_min), hi.push_back(p.sigma_max);
      bumps.push_back(out.options.world_at(p).bumps);
    }
    r.series("scale.sigma_min", lo);
    r.series("scale.sigma_max", hi);
    r.series("scale.bumps", bumps);
  }
  // Over the distinct points: where Proposed is significantly below every other method (best), significantly
  // above every other (worst), or neither, in each error; the family is every paired comparison at every
  // point.
  repro::PairedFamily family;
  std::map<Point, repro::KeyPath> prefix;
  for (const auto& [point, st] : out.points) {
    prefix[point] = repro::path(fmt::format("point{}", prefix.size()));
    add_paired_at(family, prefix[point], st);
  }
  family.adjust();
  ProposedTally tally;
  for (const auto& [point, st] : out.points) {
    const PairedAtPoint pp = paired_at(family, prefix.at(point), st);
    if (!pp.others.empty()) tally.add(pp);
  }
  record_family(r, family);
  r.metric("points", tally.points);
  tally.record(r);
  for (const SensitivityAxis& axis : sensitivity_axes(out.options)) {
    for (const SensitivityCurve& c : sensitivity_curves(out, axis)) {
      r.under(c.name).under(axis.tag).series("rot_se.median", c.rot);
      r.under(c.name).under(axis.tag).series("trans_se.median", c.trans);
      r.under(c.name).under(axis.tag).series("valid_rate", c.valid);
      r.under(c.name).under(axis.tag).series("valid_rate.ci_low", c.valid_low);
      r.under(c.name).under(axis.tag).series("valid_rate.ci_high", c.valid_high);
    }
    // Paired: Proposed minus each other method, median of per-world differences with its order-statistic
    // interval, and the Holm-adjusted p.
    std::map<std::string, std::vector<double>> series;
    for (const Point& p : axis.points) {
      const PairedAtPoint pp = paired_at(family, prefix.at(p), out.at(p));
      for (std::size_t k = 0; k < pp.others.size(); ++k)
        for (const auto& [label, c] : {std::pair{"rot_se", pp.rot[k]}, std::pair{"trans_se", pp.trans[k]}}) {
          const auto key = repro::path("paired").under(axis.tag).under(label).under(pp.others[k]);
          series[key.key("difference")].push_back(c.difference);
          series[key.key("difference_of_medians")].push_back(c.difference_of_medians);
          series[key.key("low")].push_back(c.low);
          series[key.key("high")].push_back(c.high);
          series[key.key("adjusted_p")].push_back(c.adjusted_p);
        }
    }
    for (auto& [key, v] : series) r.series(key, std::move(v));
  }
}

std::vector<Figure> Sensitivity::figures(const Outcome& out) {
  const auto& o = out.options;
  Figure f;
  f.file = ".png";
  f.title = fmt::format(
      "Beyond Table 3.1: sensitivity to feature noise (query {:g} m), query size (noise {:g}) and the "
      "field's "
      "length scale, {} worlds per point (valid: 95 % Wilson bars)",
      o.study.world.query_size, o.study.world.feature_noise, o.study.worlds);
  const auto axes = sensitivity_axes(o);
  f.rows = static_cast<int>(axes.size()), f.cols = 3, f.width = 16.5,
  f.height = 4.5 * static_cast<double>(axes.size());
  const char* markers[] = {"o", "s", "^", "v"};
  for (const SensitivityAxis& axis : axes) {
    Panel pr, pt, pv;
    pr.title = "median rotation SE vs " + axis.what, pt.title = "median translation SE vs " + axis.what;
    pv.title = "approx. valid rotations vs " + axis.what;
    pr.ylabel = "rad²", pt.ylabel = "m²", pv.ylabel = "% of worlds";
    pr.xlabel = pt.xlabel = pv.xlabel = axis.xlabel;
    pr.yscale = pt.yscale = "log";
    pt.legend = pv.legend = "none";
    pv.ylim = std::make_pair(-5.0, 105.0);
    const auto curves = sensitivity_curves(out, axis);
    for (std::size_t m = 0; m < curves.size(); ++m) {
      std::vector<double> rot = curves[m].rot, trans = curves[m].trans;
      for (auto* v : {&rot, &trans})
        for (double& x : *v) x = std::max(x, 1e-12);  // log axis
      pr.layers.push_back(repro::line_layer(axis.x, rot, curves[m].name, kColors[m % 4], markers[m % 4]));
      pt.layers.push_back(repro::line_layer(axis.x, trans, curves[m].name, kColors[m % 4], markers[m % 4]));
      pv.layers.push_back(
          repro::line_layer(axis.x, curves[m].valid, curves[m].name, kColors[m % 4], markers[m % 4]));
      Layer bars;
      bars.type = "segments", bars.color = kColors[m % 4];
      bars.x0 = bars.x1 = axis.x, bars.y0 = curves[m].valid_low, bars.y1 = curves[m].valid_high;
      pv.layers.push_back(bars);
    }
    f.panels.push_back(pr), f.panels.push_back(pt), f.panels.push_back(pv);
  }
  return {f};
}

}  // namespace keel::study::ch3
