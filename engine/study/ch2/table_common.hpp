// What the chapter-2 table studies share: the claimed methods of [params.claims], the merged-maps figure of
// Figs. 2.5 and 2.7, and metric-name tags. Internal to engine/study/ch2 (not exported).
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "core/parallel.hpp"
#include "core/statistics.hpp"
#include "core/timing.hpp"
#include "study/ch2/city_table.hpp"

namespace keel::study::ch2 {

using repro::Figure;
using repro::Layer;
using repro::Panel;

// Index of the method [params.claims] names, as a located configuration error when it is unknown or, with
// `kind`, of another kind.
std::size_t claimed_method(const std::vector<StudyMethod>& methods, const core::ConfigTable& claims,
                           const std::string& name,
                           std::optional<merge::MergeMethodKind> kind = std::nullopt);

std::vector<std::size_t> claimed_methods(const std::vector<StudyMethod>& methods,
                                         const core::ConfigTable& claims,
                                         const std::vector<std::string>& names,
                                         std::optional<merge::MergeMethodKind> kind = std::nullopt);

// Figs. 2.5 / 2.7: one panel per method with the merged trajectories of both robots (axes ax, ay of the
// translation) and every candidate as a segment between its two poses: blue accepted inliers, red accepted
// outliers, pink rejected inliers, grey rejected outliers. `d` must have been run with keep_solutions.
template <class G>
Figure merged_maps_figure(const MergeDataset<G>& d, const std::vector<StudyMethod>& methods,
                          const std::string& file, const std::string& title, int ax, int ay,
                          double trajectory_width, const std::string& xlabel = "",
                          const std::string& ylabel = "") {
  Figure f;
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
    Panel panel;
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
      Layer l;
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

// A number as a metric-name tag: {:g} with '.' replaced by '_' (0.12 -> "0_12", 1 -> "1", 11 -> "11").
std::string tag_of(double v);

std::string join(const std::vector<double>& v);

}  // namespace keel::study::ch2
