// Config checks, summaries over realizations, recorded names, claims and the figure of
// ch2_table2_1_noise_regimes — presentation glue of this experiment only (the study itself is keel::eval's:
// regimes, local maps, calibration of Q on the pool, data sets). Include after the imports of driver.cpp.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace keel::experiments::noise_regimes {

namespace core = keel::core;
namespace repro = keel::repro;
namespace eval = keel::eval;

// A number as a metric-name tag: {:g} with '.' replaced by '_' (0.12 -> "0_12", 1 -> "1", 11 -> "11").
inline std::string tag_of(double v) {
  std::string s = fmt::format("{:g}", v);
  std::replace(s.begin(), s.end(), '.', '_');
  return s;
}

// One regime of the summary: the file's own measurements, or every measurement redrawn at noise scale s.
struct Regime {
  std::string name;  // "dataset" or "s<tag>", the metric prefix
  double scale = 1.0;
  std::size_t realizations = 1;
  bool resampled = false;
};

// One realization: its scenario, local maps, calibration of Q (joint, independent) and per-method summaries.
struct Realization {
  keel::sim::TwoRobotScenario2 scenario;
  eval::LocalPair<keel::lie::SE2> local;
  double pool_chi2 = 0.0;
  std::vector<eval::PoolCalibration> calibration;  // [composition]
  std::vector<eval::MethodSummary> methods;        // [method], over the data sets
};

struct Claims {
  std::string method;
  double scale, tpr_min, fpr_max, calibration_scale, calibration_p;
  std::pair<double, double> calibration_range;
};

// What the validated config fixes: thresholds γ(p) of the calibration levels and the indices the claims use.
struct Setup {
  std::uint64_t resample_seed = 0;
  std::vector<double> pair_p, gammas;
  std::vector<std::string> p_tags;
  std::size_t i_claim = 0, i_ref = 0, r_claim = 0, r_cal = 0, j_cal = 0;
};

inline Setup validate_setup(const core::ConfigTable& p, const core::ConfigTable& claims, std::uint64_t seed,
                            const std::vector<double>& scales, const std::vector<double>& pair_p,
                            std::int64_t resample_seed, std::size_t realizations,
                            const std::vector<eval::StudyMethod>& methods, const Claims& c) {
  using core::ConfigError;
  if (scales.empty()) throw ConfigError(p.where("noise_scales") + ": needs at least one scale");
  for (std::size_t k = 0; k < scales.size(); ++k)
    if (!(std::isfinite(scales[k]) && scales[k] > 0.0) || (k > 0 && scales[k] <= scales[k - 1]))
      throw ConfigError(p.where("noise_scales") + ": must be increasing, positive and finite");
  if (resample_seed < 0) throw ConfigError(p.where("resample_seed") + ": must be >= 0");
  Setup s;
  s.resample_seed = static_cast<std::uint64_t>(resample_seed);
  // resample_measurements draws from Rng::stream(seed', 0/1/2) and generate_candidates from Rng::stream(seed,
  // d): with seed' = seed the first three data sets would reuse the resampling's random numbers.
  for (std::size_t k = 0; k < realizations; ++k)
    if (s.resample_seed + k == seed)
      throw ConfigError(
          fmt::format("{}: resample_seed + realization index must never equal the experiment seed ({}), "
                      "which drives the candidate streams",
                      p.where("resample_seed"), seed));
  if (pair_p.empty()) throw ConfigError(p.where("pair_p_values") + ": needs at least one level");
  for (double x : pair_p)
    if (!(x > 0.0 && x < 1.0)) throw ConfigError(p.where("pair_p_values") + ": levels must lie in (0, 1)");
  s.i_claim = s.i_ref = methods.size();
  for (std::size_t k = 0; k < methods.size(); ++k) {
    if (methods[k].method.name == c.method) s.i_claim = k;
    if (methods[k].method.kind() == eval::MergeMethodKind::no_outliers) s.i_ref = k;
    if (methods[k].method.kind() == eval::MergeMethodKind::dcs)
      throw ConfigError(p.where("methods") + ": DCS is not part of this study");
  }
  if (s.i_claim == methods.size())
    throw ConfigError(fmt::format("{}: '{}' is not in `methods`", claims.where("method"), c.method));
  if (s.i_ref == methods.size())
    throw ConfigError(p.where("methods") + ": needs a no_outliers method (the reference)");
  const auto find_scale = [&](double x, const char* key) {
    for (std::size_t k = 0; k < scales.size(); ++k)
      if (scales[k] == x) return k;
    throw ConfigError(claims.where(key) + ": must be one of `noise_scales`");
  };
  s.r_claim = 1 + find_scale(c.scale, "noise_scale");
  s.r_cal = 1 + find_scale(c.calibration_scale, "calibration_scale");
  s.pair_p = pair_p;
  s.j_cal = pair_p.size();
  for (std::size_t j = 0; j < pair_p.size(); ++j) {
    if (pair_p[j] == c.calibration_p) s.j_cal = j;
    s.p_tags.push_back(tag_of(100.0 * pair_p[j]));
    s.gammas.push_back(keel::pcm::consistency_threshold(pair_p[j], 3));
  }
  if (s.j_cal == pair_p.size())
    throw ConfigError(claims.where("calibration_p") + ": must be one of `pair_p_values`");
  return s;
}

// Per regime, one value per realization: TPR, FPR and mean merged χ² per method; calibration per composition
// and level; mean q; local χ² of both robots and the pool χ² at the truth.
struct Summary {
  std::vector<std::vector<std::vector<double>>> tpr, fpr, chi2;  // [regime][method][realization]
  std::vector<std::vector<std::vector<std::vector<double>>>>
      fail;                                                      // [regime][composition][level][realization]
  std::vector<std::vector<std::vector<double>>> q_mean;          // [regime][composition][realization]
  std::vector<std::vector<double>> local_a, local_b, pool_chi2;  // [regime][realization]
  std::vector<std::vector<double>> selection_time;               // [method], every (realization, data set)
};

inline Summary summarize(const std::vector<Realization>& reals, const std::vector<std::size_t>& regime_of,
                         const std::vector<Regime>& regimes, const std::vector<eval::StudyMethod>& methods,
                         std::size_t levels) {
  const std::size_t G = regimes.size(), M = methods.size();
  Summary s;
  s.tpr.assign(G, std::vector<std::vector<double>>(M));
  s.fpr = s.chi2 = s.tpr;
  s.fail.assign(G,
                std::vector<std::vector<std::vector<double>>>(2, std::vector<std::vector<double>>(levels)));
  s.q_mean.assign(G, std::vector<std::vector<double>>(2));
  s.local_a.assign(G, {});
  s.local_b = s.pool_chi2 = s.local_a;
  s.selection_time.assign(M, {});
  for (std::size_t i = 0; i < reals.size(); ++i) {
    const auto& x = reals[i];
    const std::size_t g = regime_of[i];
    for (std::size_t m = 0; m < M; ++m) {
      const auto& ms = x.methods[m];
      s.tpr[g][m].push_back(ms.pooled.tpr());
      s.fpr[g][m].push_back(ms.pooled.fpr());
      s.chi2[g][m].push_back(ms.mean("chi2"));
      const auto& t = ms.column("selection_time_s");
      s.selection_time[m].insert(s.selection_time[m].end(), t.begin(), t.end());
    }
    for (std::size_t c = 0; c < 2; ++c) {
      for (std::size_t j = 0; j < levels; ++j) s.fail[g][c][j].push_back(x.calibration[c].fail[j]);
      s.q_mean[g][c].push_back(x.calibration[c].q_mean);
    }
    s.local_a[g].push_back(x.local.a.summary.normalized_chi2);
    s.local_b[g].push_back(x.local.b.summary.normalized_chi2);
    s.pool_chi2[g].push_back(x.pool_chi2);
  }
  return s;
}

inline const char* const kComposition[2] = {"joint", "independent"};

// `name` as a series over the realizations plus its .mean, .min and .max.
inline void record_values(repro::Results& r, const std::string& name, const std::vector<double>& v) {
  const auto st = core::mean_std(v);
  r.series(name, v);
  r.metric(name + ".mean", st.mean);
  r.metric(name + ".min", st.min);
  r.metric(name + ".max", st.max);
}

inline void record(repro::Results& r, const Summary& s, const std::vector<Regime>& regimes,
                   const std::vector<eval::StudyMethod>& methods, const Setup& setup) {
  for (std::size_t m = 0; m < methods.size(); ++m)
    if (methods[m].method.kind() != eval::MergeMethodKind::no_outliers)
      r.timing(methods[m].method.name + ".selection_s.mean", core::mean_std(s.selection_time[m]).mean);
  for (std::size_t g = 0; g < regimes.size(); ++g) {
    const std::string& rn = regimes[g].name;
    r.metric(rn + ".noise_scale", regimes[g].scale);
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const std::string base = rn + "." + methods[m].method.name;
      record_values(r, base + ".tpr", s.tpr[g][m]);
      record_values(r, base + ".fpr", s.fpr[g][m]);
      record_values(r, base + ".chi2", s.chi2[g][m]);
    }
    for (std::size_t c = 0; c < 2; ++c) {
      for (std::size_t j = 0; j < setup.gammas.size(); ++j)
        record_values(r, fmt::format("{}.pair_fail_{}.{}", rn, setup.p_tags[j], kComposition[c]),
                      s.fail[g][c][j]);
      const std::string q = fmt::format("{}.pair_q_mean.{}", rn, kComposition[c]);
      record_values(r, q, s.q_mean[g][c]);
      // The calibration of Q: a consistent pair's q is χ²(3), mean 3. The standard error is over the
      // realizations; excess is the relative bias of the mean squared distance, z its distance from 3 in
      // standard errors.
      const auto st = core::mean_std(s.q_mean[g][c]);
      const double se =
          st.std / std::sqrt(static_cast<double>(std::max<std::size_t>(s.q_mean[g][c].size(), 1)));
      r.metric(q + ".se", se);
      r.metric(q + ".excess", st.mean / 3.0 - 1.0);
      if (se > 0) r.metric(q + ".z", (st.mean - 3.0) / se);
    }
    record_values(r, rn + ".local.a.chi2", s.local_a[g]);
    record_values(r, rn + ".local.b.chi2", s.local_b[g]);
    record_values(r, rn + ".pool_chi2", s.pool_chi2[g]);
  }
}

inline std::string join(const std::vector<double>& v) {
  std::string out;
  for (double x : v) out += fmt::format("{}{:.4f}", out.empty() ? "" : ", ", x);
  return out;
}

// The two claims, checked on our numbers (they may fail).
inline void check_claims(repro::Results& r, const Summary& s, const Setup& setup, const Claims& c) {
  const auto& tpr = s.tpr[setup.r_claim][setup.i_claim];
  const auto& fpr = s.fpr[setup.r_claim][setup.i_claim];
  bool ok = true;
  for (std::size_t k = 0; k < tpr.size(); ++k) ok = ok && tpr[k] >= c.tpr_min && fpr[k] <= c.fpr_max;
  r.check(fmt::format(
              "{} at the thesis's implied noise level (s = {:g}) keeps TPR >= {:g} and FPR <= {:g} in every "
              "realization",
              c.method, c.scale, c.tpr_min, c.fpr_max),
          ok,
          fmt::format("{} at s = {:g}, per realization: TPR {}; FPR {} (thesis 0.997 / 0.001)", c.method,
                      c.scale, join(tpr), join(fpr)));
  const auto& f = s.fail[setup.r_cal][0][setup.j_cal];
  const auto mean = [&](std::size_t g, std::size_t comp) {
    return core::mean_std(s.fail[g][comp][setup.j_cal]).mean;
  };
  const double m = mean(setup.r_cal, 0);
  r.check(
      fmt::format(
          "the joint consistency metric is calibrated at the stated noise (s = {:g}): inlier pairs fail "
          "gamma({:g}) at a rate in [{:g}, {:g}] (nominal {:g})",
          c.calibration_scale, c.calibration_p, c.calibration_range.first, c.calibration_range.second,
          c.calibration_p),
      m >= c.calibration_range.first && m <= c.calibration_range.second,
      fmt::format(
          "joint Q, s = {:g}: fraction of ordered inlier pairs with q > gamma({:g}) = {:.3f}: mean {:.4f} "
          "(realizations {}; nominal {:g}); independent composition mean {:.4f}; the file's own "
          "measurements (dataset regime): joint {:.4f}, independent {:.4f}",
          c.calibration_scale, c.calibration_p, setup.gammas[setup.j_cal], m, join(f), c.calibration_p,
          mean(setup.r_cal, 1), mean(0, 0), mean(0, 1)));
}

// Against s, one point per realization, a line through the means, the dataset regime as a dotted line.
inline repro::Figure figure(const std::string& file, const Summary& s, const std::vector<Regime>& regimes,
                            const std::vector<eval::StudyMethod>& methods,
                            const std::vector<std::string>& colors, const Setup& setup,
                            std::size_t realizations, std::size_t datasets) {
  repro::Figure fig;
  fig.file = file;
  fig.title = fmt::format(
      "PCM on the City10000 two-robot data sets against the noise scale s of redrawn measurements "
      "({} realizations x {} data sets; dotted: the file's own measurements)",
      realizations, datasets);
  std::vector<double> xs;
  for (const auto& g : regimes)
    if (g.resampled) xs.push_back(g.scale);
  // Scatter of the realizations, line through the means, dotted line at the dataset regime's mean.
  const auto add = [&](repro::Panel& pa, const std::vector<std::vector<double>>& per_regime,
                       const std::string& label, const std::string& color) {
    std::vector<double> px, py, my;
    for (std::size_t g = 1; g < regimes.size(); ++g) {
      px.insert(px.end(), regimes[g].realizations, regimes[g].scale);
      py.insert(py.end(), per_regime[g].begin(), per_regime[g].end());
      my.push_back(core::mean_std(per_regime[g]).mean);
    }
    pa.layers.push_back(repro::scatter_layer(px, py, "", color, 22.0, 0.6, "o"));
    pa.layers.push_back(repro::line_layer(xs, my, label, color, "", "-"));
    pa.layers.push_back(repro::hline_layer(core::mean_std(per_regime[0]).mean, "", color, ":"));
  };
  const auto panel = [&](const std::string& title, const std::string& xlabel, const std::string& ylabel,
                         const std::string& yscale) {
    repro::Panel pa;
    pa.title = title;
    pa.xlabel = xlabel;
    pa.ylabel = ylabel;
    pa.xlim = std::make_pair(0.0, 1.05 * xs.back());
    pa.yscale = yscale;
    return pa;
  };
  const auto per_method = [&](const auto& v, std::size_t m) {
    std::vector<std::vector<double>> out;
    for (const auto& g : v) out.push_back(g[m]);
    return out;
  };
  const std::string sx = "noise scale s (residual ~ N(0, s^2 Omega^-1))";
  for (const auto& [title, ylabel, values, with_ref, yscale] :
       {std::tuple{"TPR (pooled over the data sets)", "TPR", &s.tpr, false, "linear"},
        std::tuple{"FPR (pooled over the data sets)", "FPR", &s.fpr, false, "linear"},
        std::tuple{"normalized chi2 of the merged graph (mean)", "normalized chi2", &s.chi2, true, "log"}}) {
    auto pa = panel(title, sx, ylabel, yscale);
    for (std::size_t m = 0; m < methods.size(); ++m)
      if (with_ref || m != setup.i_ref) add(pa, per_method(*values, m), methods[m].label, colors[m]);
    fig.panels.push_back(pa);
  }
  const char* comp_color[2] = {"tab:blue", "tab:green"};
  for (std::size_t j = 0; j <= setup.gammas.size(); ++j) {
    const bool q = j == setup.gammas.size();  // the last panel: mean q
    auto pa = q ? panel("mean q over the ordered pool pairs", "noise scale s", "mean q", "log")
                : panel(fmt::format("inlier pairs with q > gamma({:g} %) = {:.2f}", 100.0 * setup.pair_p[j],
                                    setup.gammas[j]),
                        "noise scale s", "fraction of ordered pool pairs", "linear");
    for (std::size_t c = 0; c < 2; ++c) {
      std::vector<std::vector<double>> v;
      for (std::size_t g = 0; g < regimes.size(); ++g) v.push_back(q ? s.q_mean[g][c] : s.fail[g][c][j]);
      add(pa, v, std::string("Q, ") + kComposition[c] + " composition", comp_color[c]);
    }
    if (!q) {
      pa.layers.push_back(repro::hline_layer(setup.pair_p[j], "nominal at s = 1", "0.2", "--"));
    } else {
      std::vector<double> ny;  // E q = 3 s² for a calibrated Q
      for (double x : xs) ny.push_back(3.0 * x * x);
      pa.layers.push_back(repro::line_layer(xs, ny, "nominal 3 s^2", "0.2", "", "--"));
    }
    fig.panels.push_back(pa);
  }
  fig.cols = 3;
  fig.rows = static_cast<int>((fig.panels.size() + 2) / 3);
  fig.width = 17.0;
  fig.height = 4.8 * fig.rows;
  return fig;
}

}  // namespace keel::experiments::noise_regimes
