#include "study/ch3/example.hpp"

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
// Fig. 3.4

Example::Options Example::Options::read(const core::ConfigTable& p) {
  Options o;
  o.study.world = read_alignment_world_options(p);
  o.study.compare = read_comparison_options(p);
  o.world_index = static_cast<std::uint64_t>(p.integer("world_index"));
  o.field_grid_spacing = p.number("field_grid_spacing");
  if (!(o.field_grid_spacing > 0))
    throw core::ConfigError(fmt::format("{}: must be > 0", p.where("field_grid_spacing")));
  o.study.worlds = 1;
  o.study.compare.certify = false;
  return o;
}

Example::Outcome Example::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  const RunContext world = context.with_streams(context.streams().offset(o.world_index));
  out.study = run_alignment_study(o.study, world);
  out.world = sim::make_alignment_world(o.study.world, world.streams().seed(), world.streams().index(0));
  out.shape = sim::lawn_mower(0, 0, o.study.world.query_size, o.study.world.query_size,
                              o.study.world.track_spacing, o.study.world.sample_spacing);
  if (static_cast<std::size_t>(out.shape.tracks * out.shape.per_track) != out.world.query_x.size())
    throw std::logic_error("ch3 Example: the query is not the lawn-mower of query_size");
  return out;
}

void Example::record(Results& r, const Outcome& out) {
  const sim::AlignmentWorld& w = out.world;
  const ComparisonOptions& compare = out.options.study.compare;
  using Named = std::pair<const char*, double>;
  for (const auto& [key, v] :
       {Named{"world.theta", w.theta}, Named{"world.tx", w.tx}, Named{"world.ty", w.ty},
        Named{"reference_points", static_cast<double>(w.ref_x.size())},
        Named{"query_points", static_cast<double>(w.query_x.size())}})
    r.metric(key, v);
  for (std::size_t m = 0; m < out.study.methods.size(); ++m) {
    const auto& mo = out.study.outcomes[m][0];
    const std::string name(align::to_string(out.study.methods[m]));
    for (const auto& [key, v] :
         {Named{"rot_se", mo.rot_se}, Named{"trans_se", mo.trans_se}, Named{"valid", mo.valid ? 1.0 : 0.0},
          Named{"cost", mo.cost}, Named{"singular_min", mo.singular_min},
          Named{"singular_max", mo.singular_max}})
      r.under(name).metric(key, v);
    r.under(name).timing("time_s", mo.time_s);
    if (out.study.methods[m] == Method::proposed)
      r.check("the proposed estimate is an approximately valid rotation", mo.valid,
              fmt::format("singular values {:.4f}, {:.4f} (valid: within {} of 1, det > 0; the octagon is "
                          "within ±4.1 % of the circle)",
                          mo.singular_max, mo.singular_min, compare.valid_tolerance),
              compare.valid_tolerance <= 1.0 / align::kBarniDelta - 1.0);  // counted only if not guaranteed
  }
}

namespace {

// The query's footprint (the four corners of its lawn-mower, closed) in its own frame, placed by t.
Layer footprint(const sim::AlignmentWorld& w, const sim::LawnMower& shape, const Transform2& t,
                std::string label, std::string color, double linewidth) {
  const auto per = static_cast<std::size_t>(shape.per_track), n = w.query_x.size();
  const bool even = (shape.tracks - 1) % 2 == 0;  // the last track runs the way the first does
  std::vector<double> x, y;
  for (std::size_t j :
       {std::size_t{0}, per - 1, even ? n - 1 : n - per, even ? n - per : n - 1, std::size_t{0}}) {
    x.push_back(t.a11 * w.query_x[j] + t.a12 * w.query_y[j] + t.tx);
    y.push_back(t.a21 * w.query_x[j] + t.a22 * w.query_y[j] + t.ty);
  }
  Layer l = repro::line_layer(std::move(x), std::move(y), std::move(label), std::move(color), "o");
  l.linewidth = linewidth;
  return l;
}

Layer colored(std::vector<double> x, std::vector<double> y, std::vector<double> c, double size, double vmin,
              double vmax, std::string marker = "o") {
  Layer l = repro::scatter_layer(std::move(x), std::move(y), "", "k", size, 1.0, std::move(marker));
  l.c = std::move(c), l.cmap = "viridis", l.vmin = vmin, l.vmax = vmax;
  return l;
}

}  // namespace

// (a) the noiseless field on a grid (one panel per component, at most three), (b) the reference and (c) the
// query (its own frame) coloured by the observed first component, (d) the query's footprint placed by the
// truth and by every method's raw estimate.
std::vector<Figure> Example::figures(const Outcome& out) {
  const sim::AlignmentWorld& w = out.world;
  const sim::AlignmentWorldOptions& wo = out.options.study.world;
  const double grid = out.options.field_grid_spacing;
  Figure f;
  f.file = ".png";
  f.title = fmt::format("Fig. 3.4: example simulated trajectory alignment (world {} of Table 3.1's seed)",
                        out.options.world_index);
  const double half = 0.5 * wo.reference_size;
  const int dims = std::min(w.feature_dim, 3);
  const auto steps = static_cast<int>(std::floor(wo.reference_size / grid + 1e-9));
  double vmin0 = 0, vmax0 = 0;
  for (int k = 0; k < dims; ++k) {
    std::vector<double> gx, gy, gc;
    for (int a = 0; a <= steps; ++a)
      for (int b = 0; b <= steps; ++b) {
        const double x = -half + a * grid, y = -half + b * grid;
        gx.push_back(x), gy.push_back(y), gc.push_back(w.field.value(x, y)[k]);
      }
    const auto [lo, hi] = std::minmax_element(gc.begin(), gc.end());
    if (k == 0) vmin0 = *lo, vmax0 = *hi;
    Panel a;
    a.title = fmt::format("(a) feature field, component {}", k + 1);
    a.xlabel = "x (m)", a.ylabel = "y (m)", a.aspect = "equal", a.colorbar = "feature value (unit RMS)";
    const double size = std::pow(320.0 * grid / wo.reference_size, 2);  // squares that tile the panel
    a.layers.push_back(colored(std::move(gx), std::move(gy), std::move(gc), size, *lo, *hi, "s"));
    f.panels.push_back(a);
  }
  // (b), (c): both trajectories, coloured by the observed first component (same scale as (a), component 1).
  auto component0 = [&](const std::vector<double>& feat) {
    std::vector<double> c;
    for (std::size_t n = 0; n < feat.size(); n += static_cast<std::size_t>(w.feature_dim))
      c.push_back(feat[n]);
    return c;
  };
  Panel b, c, d;
  b.title = "(b) reference trajectory (reference frame)";
  c.title = "(c) query trajectory (its own frame)";
  b.xlabel = c.xlabel = d.xlabel = "x (m)";
  b.ylabel = c.ylabel = d.ylabel = "y (m)";
  b.aspect = c.aspect = d.aspect = "equal";
  b.colorbar = c.colorbar = "observed feature 1";
  b.layers.push_back(repro::line_layer(w.ref_x, w.ref_y, "", "0.8"));
  c.layers.push_back(repro::line_layer(w.query_x, w.query_y, "", "0.8"));
  b.layers.back().linewidth = c.layers.back().linewidth = 0.4;
  b.layers.push_back(colored(w.ref_x, w.ref_y, component0(w.ref_features), 8, vmin0, vmax0));
  c.layers.push_back(colored(w.query_x, w.query_y, component0(w.query_features), 16, vmin0, vmax0));
  // (d): the reference, and the query's footprint placed by the truth and by every method's raw estimate.
  d.title = "(d) query footprint placed by each estimate (raw)";
  d.layers.push_back(repro::scatter_layer(w.ref_x, w.ref_y, "reference positions", "0.75", 2.0, 1.0, "o"));
  const double ct = std::cos(w.theta), st = std::sin(w.theta);
  d.layers.push_back(footprint(w, out.shape, {ct, -st, st, ct, w.tx, w.ty}, "ground truth", "k", 3.0));
  for (std::size_t m = 0; m < out.study.methods.size(); ++m)
    d.layers.push_back(footprint(w, out.shape, out.study.outcomes[m][0].raw,
                                 std::string(align::to_string(out.study.methods[m])), kColors[m % 4], 1.5));
  d.legend = "best";
  f.panels.push_back(b), f.panels.push_back(c), f.panels.push_back(d);
  f.cols = 3;
  f.rows = static_cast<int>((f.panels.size() + 2) / 3);
  f.width = 17.0, f.height = 5.2 * f.rows;
  return {f};
}

}  // namespace keel::study::ch3
