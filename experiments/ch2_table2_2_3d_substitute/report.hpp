// The claims of §2.7.3 checked on this experiment's numbers, and Fig. 2.6 — presentation glue of
// ch2_table2_2_3d_substitute only (the study itself is keel::eval's). Include after the imports of
// driver.cpp.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace keel::experiments {

struct Table22Claims {
  std::vector<std::string> pcm, ransac, baselines;  // method names the claims compare
  std::size_t ref = 0, dcs = 0, heuristic = 0;      // method indices: NO-OUT, DCS, PCM-HeuPatt
  double tp_min_fraction = 0, dcs_tpr_max = 0, chi2_rel = 0;
  int inliers = 0;
};

// The claims of §2.7.3 on the table (they may fail).
inline void check_table2_2(keel::repro::Results& r, const std::vector<keel::eval::StudyMethod>& methods,
                           const std::vector<keel::eval::MethodSummary>& sum, const Table22Claims& c,
                           const keel::core::ConfigTable& claims) {
  const auto idx = [&](const std::string& name) { return claimed_method(methods, claims, name); };
  const auto mean = [&](std::size_t k, const char* col) { return sum[k].mean(col); };
  const std::string& heu = methods[c.heuristic].method.name;
  const double ref_chi2 = mean(c.ref, "chi2");
  // " ; name value" for every method of `names`.
  const auto list = [&](const std::vector<std::string>& names, const char* col,
                        fmt::format_string<const std::string&, double> spec) {
    std::string out;
    for (const auto& n : names) out += fmt::format(spec, n, mean(idx(n), col));
    return out;
  };
  for (const auto& name : c.pcm) {
    const std::size_t k = idx(name);
    r.check(
        fmt::format("{} keeps the true inter-robot loop closures (mean TP >= {:g} x inliers)", name,
                    c.tp_min_fraction),
        mean(k, "tp") >= c.tp_min_fraction * c.inliers,
        fmt::format("{} mean TP {:.2f} of {} inliers (thesis: 10 of 10)", name, mean(k, "tp"), c.inliers));
    bool ok = true;
    for (const auto& rn : c.ransac) ok = ok && mean(k, "fp") <= mean(idx(rn), "fp");
    r.check(name + " accepts no more outliers than RANSAC (mean FP <= every RANSAC's)", ok,
            fmt::format("mean FP: {} {:.2f}{} (thesis: PCM 3, RANSAC 6 and 7)", name, mean(k, "fp"),
                        list(c.ransac, "fp", "; {} {:.2f}")));
  }
  const auto& dcs = sum[c.dcs];
  r.check(
      fmt::format("DCS without an initial alignment turns off (nearly) all inter-robot factors (TPR <= {:g})",
                  c.dcs_tpr_max),
      dcs.pooled.tpr() <= c.dcs_tpr_max,
      fmt::format("{} mean TP {:.2f}, FP {:.2f} (TPR {:.4f})", methods[c.dcs].method.name, dcs.mean("tp"),
                  dcs.mean("fp"), dcs.pooled.tpr()));
  for (const auto& name : c.pcm) {
    const std::size_t k = idx(name);
    r.check(
        fmt::format("{}'s merged graphs are as consistent as the outlier-free graph (mean normalized chi2 "
                    "within {:g} % of NO-OUT's)",
                    name, 100 * c.chi2_rel),
        std::abs(mean(k, "chi2") - ref_chi2) <= c.chi2_rel * ref_chi2,
        fmt::format("mean normalized chi2: {} {:.4f}, {} {:.4f} (thesis: 0.3635 vs 0.3428)", name,
                    mean(k, "chi2"), methods[c.ref].method.name, ref_chi2));
  }
  // A material excess: RANSAC's χ² above PCM's by more than chi2_rel × NO-OUT's χ² (the tolerance within
  // which a graph counts as consistent above). A bare `>` would also hold when RANSAC selects exactly the
  // inliers and PCM drops one (fewer factors, a marginally lower χ²), which says nothing about consistency.
  bool ok = true;
  for (const auto& rn : c.ransac)
    ok = ok && mean(idx(rn), "chi2") - mean(c.heuristic, "chi2") > c.chi2_rel * ref_chi2;
  r.check(
      fmt::format(
          "RANSAC's merged graphs are less consistent than PCM's (mean normalized chi2 of every RANSAC "
          "above {}'s by more than {:g} % of NO-OUT's)",
          heu, 100 * c.chi2_rel),
      ok,
      fmt::format("mean normalized chi2: {} {:.4f}{}; NO-OUT {:.4f} (thesis: 0.3635; 1.8643, 3.2795; NO-OUT "
                  "0.3428)",
                  heu, mean(c.heuristic, "chi2"), list(c.ransac, "chi2", "; {} {:.4f}"), ref_chi2));
  for (const auto& [col, what] : {std::pair<const char*, const char*>{"traj_trans_mse", "trajectory"},
                                  {"rel_pose_trans_mse", "relative-pose translation"}}) {
    bool best = true;
    for (const auto& bn : c.baselines) best = best && mean(c.heuristic, col) <= mean(idx(bn), col);
    r.check(fmt::format(
                "PCM gives the best {} MSE of the robust methods (mean <= every baseline's; ties count as "
                "best)",
                what),
            best,
            fmt::format("mean {} (m^2): {} {:.6g}{}; NO-OUT {:.6g}", col, heu, mean(c.heuristic, col),
                        list(c.baselines, col, "; {} {:.6g}"), mean(c.ref, col)));
  }
}

// Fig. 2.6's claims: PCM-HeuPatt consistent at every threshold, RANSAC inconsistent at every threshold.
inline void check_fig2_6(keel::repro::Results& r, const std::vector<double>& sweep_p,
                         const std::vector<double>& ransac_chi2, const std::vector<double>& pcm_chi2,
                         double ref_chi2, std::size_t dataset, double chi2_rel) {
  bool pcm_ok = true, ransac_ok = true;
  std::string pcm_v, ransac_v;
  for (std::size_t k = 0; k < sweep_p.size(); ++k) {
    pcm_ok = pcm_ok && std::abs(pcm_chi2[k] - ref_chi2) <= chi2_rel * ref_chi2;
    ransac_ok = ransac_ok && ransac_chi2[k] > (1 + chi2_rel) * ref_chi2;
    pcm_v += fmt::format("{}{:g}: {:.4f}", k ? ", " : "", sweep_p[k], pcm_chi2[k]);
    ransac_v += fmt::format("{}{:g}: {:.4f}", k ? ", " : "", sweep_p[k], ransac_chi2[k]);
  }
  r.check(
      fmt::format("Fig. 2.6: PCM-HeuPatt's merged graph is consistent at every threshold of the sweep (chi2 "
                  "within {:g} % of NO-OUT's)",
                  100 * chi2_rel),
      pcm_ok,
      fmt::format("data set {}, NO-OUT chi2 {:.4f}; PCM-HeuPatt chi2 at p = {}", dataset, ref_chi2, pcm_v));
  r.check(fmt::format(
              "Fig. 2.6: RANSAC's merged graph is inconsistent at every threshold of the sweep (chi2 more "
              "than {:g} % above NO-OUT's)",
              100 * chi2_rel),
          ransac_ok,
          fmt::format("data set {}, NO-OUT chi2 {:.4f}; RANSAC chi2 at p = {}", dataset, ref_chi2, ransac_v));
}

// Fig. 2.6: χ² and the selection counts of RANSAC (sw[0]) and PCM-HeuPatt (sw[1]) against p; sw[m] = {χ², TP,
// FP}.
inline keel::repro::Figure fig2_6(const std::string& file, std::size_t dataset,
                                  const std::vector<double>& sweep_p, const std::vector<double> (&sw)[2][3],
                                  double ref_chi2) {
  namespace core = keel::core;
  namespace repro = keel::repro;
  repro::Figure f;
  f.file = file;
  f.title = fmt::format(
      "Fig. 2.6 (substitute): RANSAC and PCM-HeuPatt vs threshold p, sphere2500 data set {}", dataset);
  repro::Panel chi2;
  chi2.title = "normalized chi2 of the merged graph";
  chi2.xlabel = "p (gamma = chi2 quantile at 1 - p, 6 dof)";
  chi2.ylabel = "normalized chi2";
  chi2.xscale = "log";
  // From 0, so that differences of 10⁻⁴ (dropped inliers) are not drawn as large as an inconsistent graph.
  double top = 2.0 * ref_chi2;
  for (int m = 0; m < 2; ++m)
    for (double v : sw[m][0]) top = std::max(top, 1.1 * v);
  chi2.ylim = std::make_pair(0.0, top);
  chi2.layers.push_back(repro::line_layer(sweep_p, sw[1][0], "PCM-HeuPatt", "navy", "o"));
  chi2.layers.push_back(repro::line_layer(sweep_p, sw[0][0], "RANSAC", "red", "s"));
  chi2.layers.push_back(repro::hline_layer(ref_chi2, "NO-OUT", "0.4"));
  repro::Panel counts;
  counts.title = "selected inliers (TP) and outliers (FP)";
  counts.xlabel = chi2.xlabel;
  counts.ylabel = "count";
  counts.xscale = "log";
  counts.layers.push_back(repro::line_layer(sweep_p, sw[1][1], "PCM-HeuPatt TP", "navy", "o"));
  counts.layers.push_back(repro::line_layer(sweep_p, sw[1][2], "PCM-HeuPatt FP", "navy", "o", "--"));
  counts.layers.push_back(repro::line_layer(sweep_p, sw[0][1], "RANSAC TP", "red", "s"));
  counts.layers.push_back(repro::line_layer(sweep_p, sw[0][2], "RANSAC FP", "red", "s", "--"));
  f.panels.push_back(chi2);
  f.panels.push_back(counts);
  return f;
}

}  // namespace keel::experiments
