#include "study/ch2/noise_regimes.hpp"

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
#include "lie/se2.hpp"
#include "study/ch2/table_common.hpp"

namespace keel::study::ch2 {

using repro::Figure;
using repro::Layer;
using repro::Panel;
using repro::Results;
using repro::RunContext;

// ---------------------------------------------------------------------------------------------------------------
// Table 2.1 in noise regimes

NoiseRegimes::Options NoiseRegimes::Options::read(const core::ConfigTable& p) {
  using core::ConfigError;
  Options o;
  o.candidates = read_candidate_options(p);
  o.scales = p.numbers("noise_scales");
  o.pair_p = p.numbers("pair_p_values");
  const auto resample_seed = p.integer("resample_seed");
  o.resample_seed_key = p.where("resample_seed");
  o.realizations = p.count("realizations");
  o.datasets = p.count("datasets");
  o.methods = read_methods(p);
  const auto color = p.table("color");
  for (const auto& m : o.methods) o.colors.push_back(color.string(m.method.name));
  const auto claims = p.table("claims");
  o.claim_method = claims.string("method");
  o.claim_scale = claims.number("noise_scale");
  o.tpr_min = claims.number("tpr_min");
  o.fpr_max = claims.number("fpr_max");
  o.calibration_scale = claims.number("calibration_scale");
  o.calibration_p = claims.number("calibration_p");
  o.calibration_range = read_range(claims, "calibration_range");
  o.scenario = ScenarioFiles::read(p);

  if (o.scales.empty()) throw ConfigError(p.where("noise_scales") + ": needs at least one scale");
  for (std::size_t k = 0; k < o.scales.size(); ++k)
    if (!(std::isfinite(o.scales[k]) && o.scales[k] > 0.0) || (k > 0 && o.scales[k] <= o.scales[k - 1]))
      throw ConfigError(p.where("noise_scales") + ": must be increasing, positive and finite");
  if (resample_seed < 0) throw ConfigError(p.where("resample_seed") + ": must be >= 0");
  o.resample_seed = static_cast<std::uint64_t>(resample_seed);
  if (o.pair_p.empty()) throw ConfigError(p.where("pair_p_values") + ": needs at least one level");
  for (double x : o.pair_p)
    if (!(x > 0.0 && x < 1.0)) throw ConfigError(p.where("pair_p_values") + ": levels must lie in (0, 1)");
  o.i_claim = o.i_ref = o.methods.size();
  for (std::size_t k = 0; k < o.methods.size(); ++k) {
    if (o.methods[k].method.name == o.claim_method) o.i_claim = k;
    if (o.methods[k].method.kind() == merge::MergeMethodKind::no_outliers) o.i_ref = k;
    if (o.methods[k].method.kind() == merge::MergeMethodKind::dcs)
      throw ConfigError(p.where("methods") + ": DCS is not part of this study");
  }
  if (o.i_claim == o.methods.size())
    throw ConfigError(fmt::format("{}: '{}' is not in `methods`", claims.where("method"), o.claim_method));
  if (o.i_ref == o.methods.size())
    throw ConfigError(p.where("methods") + ": needs a no_outliers method (the reference)");
  const auto find_scale = [&](double x, const char* key) {
    for (std::size_t k = 0; k < o.scales.size(); ++k)
      if (o.scales[k] == x) return k;
    throw ConfigError(claims.where(key) + ": must be one of `noise_scales`");
  };
  o.r_claim = 1 + find_scale(o.claim_scale, "noise_scale");
  o.r_cal = 1 + find_scale(o.calibration_scale, "calibration_scale");
  o.j_cal = o.pair_p.size();
  for (std::size_t j = 0; j < o.pair_p.size(); ++j) {
    if (o.pair_p[j] == o.calibration_p) o.j_cal = j;
    o.p_tags.push_back(tag_of(100.0 * o.pair_p[j]));
    o.gammas.push_back(pcm::consistency_threshold(o.pair_p[j], lie::SE2::DoF));
  }
  if (o.j_cal == o.pair_p.size())
    throw ConfigError(claims.where("calibration_p") + ": must be one of `pair_p_values`");
  return o;
}

namespace {

// One realization: its scenario, local maps, calibration of Q (joint, independent) and per-method summaries.
struct Realization {
  sim::TwoRobotScenario2 scenario;
  LocalPair<lie::SE2> local;
  double pool_chi2 = 0.0;
  std::vector<PoolCalibration> calibration;  // [composition]
  std::vector<MethodSummary> methods;        // [method], over the data sets
};

NoiseRegimes::Summary summarize(const std::vector<Realization>& reals,
                                const std::vector<std::size_t>& regime_of,
                                const std::vector<NoiseRegimes::Regime>& regimes,
                                const std::vector<StudyMethod>& methods, std::size_t levels) {
  const std::size_t G = regimes.size(), M = methods.size();
  NoiseRegimes::Summary s;
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

const char* const kComposition[2] = {"joint", "independent"};

// `field` of `row` as a series over the realizations plus its .mean, .min and .max.
void record_values(const repro::Scope& row, std::string_view field, const std::vector<double>& v) {
  const auto st = core::mean_std(v);
  row.series(field, v);
  const auto f = row.under(field);
  f.metric("mean", st.mean);
  f.metric("min", st.min);
  f.metric("max", st.max);
}

}  // namespace

NoiseRegimes::Outcome NoiseRegimes::run(const Options& o, const RunContext& context) {
  // resample_measurements draws from Rng::stream(seed', 0/1/2) and generate_candidates from Rng::stream(seed,
  // d): with seed' = seed the first three data sets would reuse the resampling's random numbers.
  const std::uint64_t seed = context.streams().seed();
  for (std::size_t k = 0; k < o.realizations; ++k)
    if (o.resample_seed + k == seed)
      throw core::ConfigError(
          fmt::format("{}: resample_seed + realization index must never equal the experiment seed ({}), "
                      "which drives the candidate streams",
                      o.resample_seed_key, seed));
  Outcome out;
  out.options = o;
  auto t0 = core::Clock::now();
  const auto base = load_scenario_2d(o.scenario);
  out.read_time_s = core::seconds_since(t0);
  out.pool = base.pool.size();
  if (base.pool.size() < 2) throw std::runtime_error("the pool needs at least two true loop closures");

  // Regimes: the file's own measurements (one realization: they are fixed), then each noise scale, whose
  // realization k redraws every measurement from the streams (resample_seed + k, 0/1/2).
  std::vector<MeasurementRegime> realization_regimes;
  std::vector<std::size_t> regime_of;  // per realization
  out.regimes = {{"dataset", 1.0, 1, false}};
  realization_regimes.push_back({"dataset", "", false, 1.0, 0});
  regime_of.push_back(0);
  for (double x : o.scales) {
    out.regimes.push_back({"s" + tag_of(x), x, o.realizations, true});
    for (std::size_t k = 0; k < o.realizations; ++k) {
      realization_regimes.push_back({out.regimes.back().name, "", true, x, o.resample_seed + k});
      regime_of.push_back(out.regimes.size() - 1);
    }
  }

  // Per realization: the scenario, both local maps solved once, and the calibration of Q on its whole pool;
  // then every data set and method (data set d draws from stream d: the same index in every realization).
  const std::size_t n = realization_regimes.size();
  std::vector<Realization> reals(n);
  core::Progress progress = context.progress(n * (1 + o.datasets));
  t0 = core::Clock::now();
  core::parallel_for(
      n,
      [&](std::size_t i) {
        auto& x = reals[i];
        x.scenario = apply_regime(base, realization_regimes[i]);
        x.pool_chi2 = pool_chi2_at_truth(x.scenario);
        x.local = solve_local_pair(x.scenario);  // one Ceres thread (LocalSolveOptions' default)
        for (auto comp : {pcm::Composition::joint, pcm::Composition::independent})
          x.calibration.push_back(pool_calibration(x.local, x.scenario, comp, o.gammas));
      },
      context.threads(), &progress);
  out.local_time_s = core::seconds_since(t0);
  t0 = core::Clock::now();
  for (std::size_t i = 0; i < n; ++i) {
    const auto runs = run_merge_datasets(reals[i].scenario, reals[i].local,
                                         apply_regime(o.candidates, realization_regimes[i]),
                                         methods_of(o.methods), context, o.datasets, o.datasets, &progress);
    for (std::size_t m = 0; m < o.methods.size(); ++m) reals[i].methods.push_back(summarize_method(runs, m));
  }
  progress.finish();
  out.datasets_time_s = core::seconds_since(t0);
  out.summary = summarize(reals, regime_of, out.regimes, o.methods, o.gammas.size());
  return out;
}

void NoiseRegimes::record(Results& r, const Outcome& out) {
  const Options& setup = out.options;
  const Summary& s = out.summary;
  const auto& regimes = out.regimes;
  const auto& methods = setup.methods;
  r.timing("read_and_split", out.read_time_s);
  r.metric("scenario.pool", static_cast<double>(out.pool));
  r.metric("datasets", static_cast<double>(setup.datasets));
  r.metric("realizations", static_cast<double>(setup.realizations));
  r.metric("candidates", setup.candidates.total());
  r.timing("local_maps_and_calibration", out.local_time_s);
  r.timing("datasets", out.datasets_time_s);

  for (std::size_t m = 0; m < methods.size(); ++m)
    if (methods[m].method.kind() != merge::MergeMethodKind::no_outliers)
      r.under(methods[m].method.name).timing("selection_s.mean", core::mean_std(s.selection_time[m]).mean);
  for (std::size_t g = 0; g < regimes.size(); ++g) {
    const auto rn = r.under(regimes[g].name);
    rn.metric("noise_scale", regimes[g].scale);
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const auto base = rn.under(methods[m].method.name);
      record_values(base, "tpr", s.tpr[g][m]);
      record_values(base, "fpr", s.fpr[g][m]);
      record_values(base, "chi2", s.chi2[g][m]);
    }
    for (std::size_t c = 0; c < 2; ++c) {
      for (std::size_t j = 0; j < setup.gammas.size(); ++j)
        record_values(rn.under(fmt::format("pair_fail_{}", setup.p_tags[j])), kComposition[c],
                      s.fail[g][c][j]);
      record_values(rn.under("pair_q_mean"), kComposition[c], s.q_mean[g][c]);
      const auto q = rn.under("pair_q_mean").under(kComposition[c]);
      // The calibration of Q: a consistent pair's q is χ²(3), mean 3. The standard error is over the
      // realizations; excess is the relative bias of the mean squared distance, z its distance from 3 in
      // standard errors.
      const auto st = core::mean_std(s.q_mean[g][c]);
      const double se =
          st.std / std::sqrt(static_cast<double>(std::max<std::size_t>(s.q_mean[g][c].size(), 1)));
      q.metric("se", se);
      q.metric("excess", st.mean / 3.0 - 1.0);
      if (se > 0) q.metric("z", (st.mean - 3.0) / se);
    }
    record_values(rn.under("local").under("a"), "chi2", s.local_a[g]);
    record_values(rn.under("local").under("b"), "chi2", s.local_b[g]);
    record_values(rn, "pool_chi2", s.pool_chi2[g]);
  }

  // The two claims, checked on our numbers (they may fail).
  const auto& tpr = s.tpr[setup.r_claim][setup.i_claim];
  const auto& fpr = s.fpr[setup.r_claim][setup.i_claim];
  bool ok = true;
  for (std::size_t k = 0; k < tpr.size(); ++k) ok = ok && tpr[k] >= setup.tpr_min && fpr[k] <= setup.fpr_max;
  r.check(fmt::format(
              "{} at the thesis's implied noise level (s = {:g}) keeps TPR >= {:g} and FPR <= {:g} in every "
              "realization",
              setup.claim_method, setup.claim_scale, setup.tpr_min, setup.fpr_max),
          ok,
          fmt::format("{} at s = {:g}, per realization: TPR {}; FPR {} (thesis 0.997 / 0.001)",
                      setup.claim_method, setup.claim_scale, join(tpr), join(fpr)));
  const auto& f = s.fail[setup.r_cal][0][setup.j_cal];
  const auto mean = [&](std::size_t g, std::size_t comp) {
    return core::mean_std(s.fail[g][comp][setup.j_cal]).mean;
  };
  const double m = mean(setup.r_cal, 0);
  r.check(
      fmt::format(
          "the joint consistency metric is calibrated at the stated noise (s = {:g}): inlier pairs fail "
          "gamma({:g}) at a rate in [{:g}, {:g}] (nominal {:g})",
          setup.calibration_scale, setup.calibration_p, setup.calibration_range.first,
          setup.calibration_range.second, setup.calibration_p),
      m >= setup.calibration_range.first && m <= setup.calibration_range.second,
      fmt::format(
          "joint Q, s = {:g}: fraction of ordered inlier pairs with q > gamma({:g}) = {:.3f}: mean {:.4f} "
          "(realizations {}; nominal {:g}); independent composition mean {:.4f}; the file's own "
          "measurements (dataset regime): joint {:.4f}, independent {:.4f}",
          setup.calibration_scale, setup.calibration_p, setup.gammas[setup.j_cal], m, join(f),
          setup.calibration_p, mean(setup.r_cal, 1), mean(0, 0), mean(0, 1)));
}

// Against s, one point per realization, a line through the means, the dataset regime as a dotted line.
std::vector<Figure> NoiseRegimes::figures(const Outcome& out) {
  const Options& setup = out.options;
  const Summary& s = out.summary;
  const auto& regimes = out.regimes;
  const auto& methods = setup.methods;
  Figure fig;
  fig.file = ".png";
  fig.title = fmt::format(
      "PCM on the City10000 two-robot data sets against the noise scale s of redrawn measurements "
      "({} realizations x {} data sets; dotted: the file's own measurements)",
      setup.realizations, setup.datasets);
  std::vector<double> xs;
  for (const auto& g : regimes)
    if (g.resampled) xs.push_back(g.scale);
  // Scatter of the realizations, line through the means, dotted line at the dataset regime's mean.
  const auto add = [&](Panel& pa, const std::vector<std::vector<double>>& per_regime,
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
    Panel pa;
    pa.title = title;
    pa.xlabel = xlabel;
    pa.ylabel = ylabel;
    pa.xlim = std::make_pair(0.0, 1.05 * xs.back());
    pa.yscale = yscale;
    return pa;
  };
  const auto per_method = [&](const auto& v, std::size_t m) {
    std::vector<std::vector<double>> r;
    for (const auto& g : v) r.push_back(g[m]);
    return r;
  };
  const std::string sx = "noise scale s (residual ~ N(0, s^2 Omega^-1))";
  for (const auto& [title, ylabel, values, with_ref, yscale] :
       {std::tuple{"TPR (pooled over the data sets)", "TPR", &s.tpr, false, "linear"},
        std::tuple{"FPR (pooled over the data sets)", "FPR", &s.fpr, false, "linear"},
        std::tuple{"normalized chi2 of the merged graph (mean)", "normalized chi2", &s.chi2, true, "log"}}) {
    auto pa = panel(title, sx, ylabel, yscale);
    for (std::size_t m = 0; m < methods.size(); ++m)
      if (with_ref || m != setup.i_ref) add(pa, per_method(*values, m), methods[m].label, setup.colors[m]);
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
  return {fig};
}

}  // namespace keel::study::ch2
