// The panels of Fig. 3.5 on the substitute hull — presentation glue of ch3_fig3_5_hull_substitute only (the
// study itself is keel::align's). Include after the imports of driver.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace keel::experiments::fig3_5 {

namespace core = keel::core;
namespace repro = keel::repro;
namespace sim = keel::sim;
namespace align = keel::align;

// The second feature component, κ2, of every position.
std::vector<double> kappa2(const std::vector<double>& features) {
  std::vector<double> c;
  for (std::size_t n = 1; n < features.size(); n += sim::HullWorld::kFeatureDim) c.push_back(features[n]);
  return c;
}

// A survey drawn as its path (grey) and its positions coloured by κ2 (the second feature component).
void survey(repro::Panel& panel, const std::vector<double>& x, const std::vector<double>& y,
            const std::vector<double>& features, double size, double vmin, double vmax,
            std::string path_color = "0.7", double path_width = 0.5) {
  std::vector<double> c = kappa2(features);
  panel.layers.push_back(repro::line_layer(x, y, "", std::move(path_color)));
  panel.layers.back().linewidth = path_width;
  repro::Layer l = repro::scatter_layer(x, y, "", "k", size, 1.0, "o");
  l.c = std::move(c), l.cmap = "viridis", l.vmin = vmin, l.vmax = vmax;
  panel.layers.push_back(std::move(l));
}

// The figure on one world: (a) the reference and (b) the query (its own frame) coloured by κ2, (c) the query
// placed by `estimate` (raw; null: panel left empty), (d) by the ground truth.
inline repro::Figure alignment_figure(const std::string& id, const sim::HullWorld& w,
                                      const align::Transform2* estimate) {
  const std::vector<double> k2 = kappa2(w.ref_features);
  const auto [lo, hi] = std::minmax_element(k2.begin(), k2.end());
  repro::Figure f;
  f.file = id + ".png";
  f.title =
      "SUBSTITUTE for Fig. 3.5: synthetic hull surveys aligned on DVL curvature (world 0, depth gate on)";
  f.rows = 2, f.cols = 2, f.width = 13.0, f.height = 8.5;
  repro::Panel a, b, c, d;
  a.title = "(a) reference survey, coloured by κ₂",
  b.title = "(b) query survey (its own frame), coloured by κ₂";
  c.title = "(c) estimated alignment (proposed, raw)", d.title = "(d) ground truth alignment";
  for (auto* q : {&a, &b, &c, &d})
    q->xlabel = "x (m)", q->ylabel = "y (m)", q->aspect = "equal", q->colorbar = "κ₂ (1/m)";
  survey(a, w.ref_x, w.ref_y, w.ref_features, 10, *lo, *hi);
  survey(b, w.query_x, w.query_y, w.query_features, 16, *lo, *hi);
  const auto place = [&](repro::Panel& q, const align::Transform2& t) {
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

}  // namespace keel::experiments::fig3_5
