// The figure shared by the two-robot map-merging experiments of chapter 2 (Figs. 2.5 and 2.7). Include after
// `import keel.core; import keel.repro; import keel.eval;` (DESIGN rule 4); it imports nothing itself and
// does no linear algebra.
#pragma once

#include <fmt/format.h>

#include <string>
#include <vector>

namespace keel::experiments {

// Figs. 2.5 / 2.7: one panel per method with the merged trajectories of both robots (axes ax, ay of the
// translation) and every candidate as a segment between its two poses: blue accepted inliers, red accepted
// outliers, pink rejected inliers, grey rejected outliers. `d` must have been run with keep_solutions.
template <class G>
keel::repro::Figure merged_maps_figure(const keel::eval::MergeDataset<G>& d,
                                       const std::vector<keel::eval::StudyMethod>& methods,
                                       const std::string& file, const std::string& title, int ax, int ay,
                                       double trajectory_width, const std::string& xlabel = "",
                                       const std::string& ylabel = "") {
  namespace core = keel::core;
  namespace repro = keel::repro;
  repro::Figure f;
  f.file = file;
  f.title =
      title +
      " (blue: accepted inliers, red: accepted outliers, pink: rejected inliers, grey: rejected outliers)";
  f.cols = 4;
  f.rows = static_cast<int>((methods.size() + 3) / 4);
  f.width = 22.0;
  f.height = 5.5 * f.rows;
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const auto& o = d.methods.at(k);
    const auto& m = o.merged;
    repro::Panel panel;
    panel.title = fmt::format("{}: TP {}, FP {}", methods[k].label, o.metrics.classification.tp,
                              o.metrics.classification.fp);
    panel.xlabel = xlabel;
    panel.ylabel = ylabel;
    panel.aspect = "equal";
    panel.legend = "none";
    std::vector<double> xa, ya, xb, yb;
    for (const auto& T : m.poses_a) {
      xa.push_back(T.translation()(ax));
      ya.push_back(T.translation()(ay));
    }
    for (const auto& T : m.poses_b) {
      xb.push_back(T.translation()(ax));
      yb.push_back(T.translation()(ay));
    }
    auto la = repro::line_layer(xa, ya, "robot a", "0.25");
    la.linewidth = trajectory_width;
    auto lb = repro::line_layer(xb, yb, "robot b", "0.55");
    lb.linewidth = trajectory_width;
    panel.layers.push_back(la);
    panel.layers.push_back(lb);
    std::vector<char> chosen(d.candidates.candidates.size(), 0);
    for (int u : o.selection.selected) chosen.at(static_cast<std::size_t>(u)) = 1;
    // Drawing order: rejected outliers, rejected inliers, accepted inliers, accepted outliers (on top).
    const struct {
      bool accepted, inlier;
      const char *label, *color;
      double width, alpha;
    } groups[] = {{false, false, "rejected outliers", "0.6", 0.4, 0.35},
                  {false, true, "rejected inliers", "pink", 1.2, 1.0},
                  {true, true, "accepted inliers", "navy", 1.4, 1.0},
                  {true, false, "accepted outliers", "red", 1.4, 1.0}};
    for (const auto& g : groups) {
      repro::Layer l;
      l.type = "segments";
      l.label = g.label;
      l.color = g.color;
      l.linewidth = g.width;
      l.alpha = g.alpha;
      for (std::size_t u = 0; u < d.candidates.candidates.size(); ++u) {
        if ((chosen[u] != 0) != g.accepted || d.candidates.labels[u].is_inlier() != g.inlier) continue;
        const auto& c = d.candidates.candidates[u];
        const auto& pa = m.poses_a.at(static_cast<std::size_t>(c.pose_a)).translation();
        const auto& pb = m.poses_b.at(static_cast<std::size_t>(c.pose_b)).translation();
        l.x0.push_back(pa(ax));
        l.y0.push_back(pa(ay));
        l.x1.push_back(pb(ax));
        l.y1.push_back(pb(ay));
      }
      if (!l.x0.empty()) panel.layers.push_back(l);
    }
    f.panels.push_back(panel);
  }
  return f;
}

}  // namespace keel::experiments
