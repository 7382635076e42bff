// The panels of Fig. 3.4 — presentation glue of ch3_fig3_4_example only (the study itself is
// keel::align's). Include after the imports of driver.cpp.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace keel::experiments::fig3_4 {

namespace core = keel::core;
namespace repro = keel::repro;
namespace sim = keel::sim;
namespace align = keel::align;

// The query's footprint (the four corners of its lawn-mower, closed) in its own frame, placed by t.
repro::Layer footprint(const sim::AlignmentWorld& w, const sim::LawnMower& shape, const align::Transform2& t,
                       std::string label, std::string color, double linewidth) {
  const auto per = static_cast<std::size_t>(shape.per_track), n = w.query_x.size();
  const bool even = (shape.tracks - 1) % 2 == 0;  // the last track runs the way the first does
  std::vector<double> x, y;
  for (std::size_t j :
       {std::size_t{0}, per - 1, even ? n - 1 : n - per, even ? n - per : n - 1, std::size_t{0}}) {
    x.push_back(t.a11 * w.query_x[j] + t.a12 * w.query_y[j] + t.tx);
    y.push_back(t.a21 * w.query_x[j] + t.a22 * w.query_y[j] + t.ty);
  }
  repro::Layer l = repro::line_layer(std::move(x), std::move(y), std::move(label), std::move(color), "o");
  l.linewidth = linewidth;
  return l;
}

repro::Layer colored(std::vector<double> x, std::vector<double> y, std::vector<double> c, double size,
                     double vmin, double vmax, std::string marker = "o") {
  repro::Layer l = repro::scatter_layer(std::move(x), std::move(y), "", "k", size, 1.0, std::move(marker));
  l.c = std::move(c), l.cmap = "viridis", l.vmin = vmin, l.vmax = vmax;
  return l;
}

// The figure: (a) the noiseless field on a grid of `grid` metres (one panel per component, at most three),
// (b) the reference and (c) the query (its own frame) coloured by the observed first component, (d) the
// query's footprint placed by the truth and by every method's raw estimate.
inline repro::Figure example_figure(const std::string& id, const sim::AlignmentWorld& w,
                                    const align::AlignmentStudyOptions& o,
                                    const align::AlignmentStudyOutcome& out, const sim::LawnMower& shape,
                                    double grid) {
  // (a) the noiseless field, one panel per component (at most three).
  repro::Figure f;
  f.file = id + ".png";
  f.title = fmt::format("Fig. 3.4: example simulated trajectory alignment (world {} of Table 3.1's seed)",
                        o.stream_base);
  const double half = 0.5 * o.world.reference_size;
  const int dims = std::min(w.feature_dim, 3);
  const auto steps = static_cast<int>(std::floor(o.world.reference_size / grid + 1e-9));
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
    repro::Panel a;
    a.title = fmt::format("(a) feature field, component {}", k + 1);
    a.xlabel = "x (m)", a.ylabel = "y (m)", a.aspect = "equal", a.colorbar = "feature value (unit RMS)";
    const double size = std::pow(320.0 * grid / o.world.reference_size, 2);  // squares that tile the panel
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
  repro::Panel b, c, d;
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
  d.layers.push_back(footprint(w, shape, {ct, -st, st, ct, w.tx, w.ty}, "ground truth", "k", 3.0));
  const char* colors[] = {"tab:blue", "tab:orange", "tab:green", "tab:red"};
  for (std::size_t m = 0; m < out.methods.size(); ++m)
    d.layers.push_back(footprint(w, shape, out.outcomes[m][0].raw,
                                 std::string(align::to_string(out.methods[m])), colors[m % 4], 1.5));
  d.legend = "best";
  f.panels.push_back(b), f.panels.push_back(c), f.panels.push_back(d);
  f.cols = 3;
  f.rows = static_cast<int>((f.panels.size() + 2) / 3);
  f.width = 17.0, f.height = 5.2 * f.rows;
  return f;
}

}  // namespace keel::experiments::fig3_4
