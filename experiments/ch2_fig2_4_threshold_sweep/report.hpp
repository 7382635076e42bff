// The claims of §2.7.2.1 and the panels of Fig. 2.4 — presentation glue of ch2_fig2_4_threshold_sweep only
// (the study itself is keel::eval's). Include after the imports of driver.cpp.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace keel::experiments::fig2_4 {

// One curve family: a selection method swept over p.
struct Family {
  std::string name, label, color;
  keel::eval::MergeMethodKind kind = keel::eval::MergeMethodKind::pcm_exact;
  keel::pcm::Composition composition = keel::pcm::Composition::joint;
};

// One family's pooled TPR/FPR, mean normalized χ² and mean selection size against p.
struct Curve {
  std::vector<double> tpr, fpr, chi2, selected;
};

// Indices of the PCM-Exact, PCM-Heuristic and RANSAC families.
struct Claimed {
  std::size_t fe, fh, fr;
};

// The claims of §2.7.2.1 on one regime's curves (they may fail); `in` names the regime in the check names.
inline void check_fig2_4(keel::repro::Results& r, const std::vector<double>& p_values,
                         const std::vector<Curve>& curves, Claimed c, double chi2_no_out, double claim_p_max,
                         double claim_tpr_spread, double claim_fpr_max, const std::string& in) {
  const auto [fe, fh, fr] = c;
  double tmin = 1.0, tmax = 0.0, fmax = 0.0;
  std::string at;
  for (std::size_t k = 0; k < p_values.size(); ++k) {
    if (p_values[k] > claim_p_max) continue;
    tmin = std::min(tmin, curves[fe].tpr[k]);
    tmax = std::max(tmax, curves[fe].tpr[k]);
    fmax = std::max(fmax, curves[fe].fpr[k]);
    at += fmt::format("{}p={:g}: {:.3f}/{:.4f}", at.empty() ? "" : ", ", p_values[k], curves[fe].tpr[k],
                      curves[fe].fpr[k]);
  }
  const std::string detail = "PCM-Exact TPR/FPR " + at;
  r.check(fmt::format("PCM's TPR is relatively unaffected by the threshold for p <= {:g} (spread <= {:g}){}",
                      claim_p_max, claim_tpr_spread, in),
          tmax - tmin <= claim_tpr_spread, detail);
  r.check(fmt::format("PCM's FPR stays <= {:g} for p <= {:g}{}", claim_fpr_max, claim_p_max, in),
          fmax <= claim_fpr_max, detail);
  const double fmin = *std::min_element(curves[fr].fpr.begin(), curves[fr].fpr.end());
  r.check("RANSAC never reaches an FPR of zero" + in, fmin > 0.0,
          fmt::format("smallest RANSAC FPR over the sweep {:.4f}", fmin));
  std::size_t higher = 0, same = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < p_values.size(); ++k) {
    higher += curves[fr].fpr[k] > curves[fe].fpr[k];
    same += curves[fe].tpr[k] == curves[fh].tpr[k] && curves[fe].fpr[k] == curves[fh].fpr[k];
    worst = std::max(worst, std::abs(curves[fe].chi2[k] - chi2_no_out) / chi2_no_out);
  }
  r.check("RANSAC accepts more outliers than PCM at every threshold" + in, higher == p_values.size(),
          fmt::format("RANSAC FPR above PCM-Exact's at {} of {} thresholds", higher, p_values.size()));
  r.check(
      "PCM's merged graphs are consistent at every threshold (normalized chi2 within 10 % of NO-OUT's)" + in,
      worst <= 0.1,
      fmt::format("largest relative difference to NO-OUT's {:.4g}: {:.4f}", chi2_no_out, worst));
  r.check("PCM-Heuristic tracks PCM-Exact across the sweep (all but at most one threshold)" + in,
          same + 1 >= p_values.size(),
          fmt::format("identical pooled TPR and FPR at {} of {} thresholds", same, p_values.size()));
}

// One row of three panels (TPR, FPR, χ²) of Fig. 2.4 for one regime.
inline void add_fig2_4_row(keel::repro::Figure& fig, const std::vector<double>& p_values,
                           const std::vector<Curve>& curves, const std::vector<Family>& families,
                           double chi2_no_out, const std::string& label) {
  namespace core = keel::core;
  namespace repro = keel::repro;
  const char* names[3] = {"TPR", "FPR", "normalized χ²"};
  for (int panel = 0; panel < 3; ++panel) {
    repro::Panel pa;
    pa.title = fmt::format("{} — {}", names[panel], label);
    pa.xlabel = "p";
    pa.ylabel = names[panel];
    pa.xscale = "logit";  // p spans 0.001 … 0.99: both ends matter
    if (panel == 2) pa.yscale = "log";
    pa.legend = panel == 0 ? "" : "none";
    for (std::size_t f = 0; f < families.size(); ++f) {
      const auto& y = panel == 0 ? curves[f].tpr : panel == 1 ? curves[f].fpr : curves[f].chi2;
      pa.layers.push_back(repro::line_layer(p_values, y, families[f].label, families[f].color, "o",
                                            families[f].name == "pcm_heuristic" ? "--" : ""));
    }
    if (panel == 2) pa.layers.push_back(repro::hline_layer(chi2_no_out, "NO-OUT", "0.3"));
    fig.panels.push_back(pa);
  }
}

}  // namespace keel::experiments::fig2_4
