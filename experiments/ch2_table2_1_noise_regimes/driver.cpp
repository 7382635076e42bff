// Table 2.1 (§2.7.2), PCM rows, across noise regimes: how PCM-11 %'s outcome on the City10000 two-robot data sets
// depends on the noise level of the measurements and on the realization of the local maps, and how well the
// consistency metric is calibrated in each regime — thin driver over keel.graph (data), keel.pcm (scenario,
// resampling, local maps, consistency matrix, map merging) and keel.core.
import keel.core;
import keel.lie;
import keel.graph;
import keel.pgo;
import keel.cov;
import keel.pcm;
import keel.sim;
import keel.eval;

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "common/two_robot.hpp"

namespace core = keel::core;
namespace pcm = keel::pcm;
namespace sim = keel::sim;
namespace eval = keel::eval;
namespace ke = keel::experiments;

namespace {

// A number as a metric-name tag: %g with '.' replaced by '_' (0.12 -> "0_12", 1 -> "1", 11 -> "11").
std::string tag_of(double v) {
  std::string s = ke::fmt(v);
  std::replace(s.begin(), s.end(), '.', '_');
  return s;
}

// One regime: the file's own measurements, or every measurement redrawn about the ground truth at noise scale s.
struct Regime {
  std::string name;  // "dataset" or "s<tag>", the metric prefix
  bool resampled = false;
  double scale = 1.0;  // s (1 for the dataset regime: its candidates' aliased groups use the stated noise)
  std::size_t realizations = 1;
};

// One realization of a regime: its scenario, both solved local maps and the calibration of Q on its pool.
struct Realization {
  std::size_t regime = 0, index = 0;
  sim::TwoRobotScenario2 scenario;
  eval::LocalSolution2 a, b;
  // Per composition (0 joint, 1 independent): fraction of ordered pool pairs with q > γ(p) per calibration level p,
  // and the mean q over the ordered pairs.
  std::vector<double> fail[2];
  double q_mean[2] = {0.0, 0.0};
  double pool_chi2 = 0.0;  // mean over the pool of r^T Ω r / 3 at the ground truth (the measurements' own noise)
};

// Mean over the pool of rᵀ Ω r / dof, r = ρ(z⁻¹ X) the residual of pool edge u at its true value
// X = (T^a_i)⁻¹ T_ab T^b_k (graph/pose_graph.hpp: ρ = (x, y, θ) in 2D). Nominal: 1 for the stated noise, s² redrawn.
double pool_chi2_at_truth(const sim::TwoRobotScenario2& s) {
  double sum = 0.0;
  for (std::size_t u = 0; u < s.pool.size(); ++u) {
    const auto& c = s.pool[u];
    const keel::lie::SE2 X = s.truth_a[static_cast<std::size_t>(c.pose_a)].inverse() * s.true_anchor *
                             s.truth_b[static_cast<std::size_t>(c.pose_b)];
    const keel::lie::SE2 E = c.z.inverse() * X;
    keel::lie::Vec3 r;
    r << E.translation()(0), E.translation()(1), E.angle();
    sum += r.dot(s.pool_information[u] * r) / 3.0;
  }
  return sum / static_cast<double>(s.pool.size());
}

// Per (realization, data set, method): what the summary needs.
struct Outcome {
  eval::Classification c;
  double chi2 = 0.0;
  double selection_time_s = 0.0;
};

struct Stats {
  double mean = 0.0, min = 0.0, max = 0.0;
};
Stats stats_of(const std::vector<double>& v) {
  Stats s;
  if (v.empty()) return s;
  s.min = s.max = v[0];
  for (double x : v) {
    s.mean += x;
    s.min = std::min(s.min, x);
    s.max = std::max(s.max, x);
  }
  s.mean /= static_cast<double>(v.size());
  return s;
}

// `name` as a series over the realizations plus its .mean, .min and .max.
Stats record(core::Results& r, const std::string& name, const std::vector<double>& v) {
  const Stats s = stats_of(v);
  r.series(name, v);
  r.metric(name + ".mean", s.mean);
  r.metric(name + ".min", s.min);
  r.metric(name + ".max", s.max);
  return s;
}

std::string join(const std::vector<double>& v, const char* format) {
  std::string out;
  char one[48];
  for (double x : v) {
    std::snprintf(one, sizeof one, format, x);
    out += (out.empty() ? "" : ", ") + std::string(one);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  return core::experiment_main(argc, argv, [](core::Experiment& ex) {
    const auto& p = ex.params();
    const std::string dataset = p.string("dataset"), graph_file = p.string("graph_file"),
                      truth_file = p.string("ground_truth_file");
    const auto split = ke::read_split(p);
    const sim::CandidateOptions copt_base = ke::read_candidate_options(p);
    const std::vector<double> scales = p.numbers("noise_scales");
    const auto resample_seed_raw = p.integer("resample_seed");
    const std::size_t realizations = p.count("realizations");
    const std::size_t datasets = p.count("datasets");
    const std::vector<double> pair_p = p.numbers("pair_p_values");
    const auto methods = ke::read_methods(p);
    std::vector<std::string> colors;
    {
      const auto t = p.table("color");
      for (const auto& m : methods) colors.push_back(t.string(m.method.name));
    }
    const auto claims = p.table("claims");
    const std::string claim_method = claims.string("method");
    const double claim_scale = claims.number("noise_scale");
    const double tpr_min = claims.number("tpr_min"), fpr_max = claims.number("fpr_max");
    const double cal_scale = claims.number("calibration_scale"), cal_p = claims.number("calibration_p");
    const auto cal_range = ke::range_of(claims, "calibration_range");
    ex.params_done();

    // Validation (before any long work).
    if (scales.empty()) throw core::ConfigError(p.where("noise_scales") + ": needs at least one scale");
    for (std::size_t k = 0; k < scales.size(); ++k)
      if (!(std::isfinite(scales[k]) && scales[k] > 0.0) || (k > 0 && scales[k] <= scales[k - 1]))
        throw core::ConfigError(p.where("noise_scales") + ": must be increasing, positive and finite");
    if (resample_seed_raw < 0) throw core::ConfigError(p.where("resample_seed") + ": must be >= 0");
    const auto resample_seed = static_cast<std::uint64_t>(resample_seed_raw);
    // resample_measurements draws from Rng::stream(seed', 0/1/2) and generate_candidates from Rng::stream(seed, d):
    // with seed' = seed the first three data sets would reuse the resampling's random numbers.
    for (std::size_t k = 0; k < realizations; ++k)
      if (resample_seed + k == ex.seed())
        throw core::ConfigError(p.where("resample_seed") + ": resample_seed + realization index must never equal "
                                "the experiment seed (" + std::to_string(ex.seed()) + "), which drives the "
                                "candidate streams");
    if (pair_p.empty()) throw core::ConfigError(p.where("pair_p_values") + ": needs at least one level");
    for (double x : pair_p)
      if (!(x > 0.0 && x < 1.0)) throw core::ConfigError(p.where("pair_p_values") + ": levels must lie in (0, 1)");
    std::size_t i_claim = methods.size(), i_ref = methods.size();
    for (std::size_t k = 0; k < methods.size(); ++k) {
      if (methods[k].method.name == claim_method) i_claim = k;
      if (methods[k].method.kind == eval::MergeMethodKind::no_outliers) i_ref = k;
    }
    if (i_claim == methods.size())
      throw core::ConfigError(claims.where("method") + ": '" + claim_method + "' is not in `methods`");
    if (i_ref == methods.size())
      throw core::ConfigError(p.where("methods") + ": needs a no_outliers method (the reference)");
    for (const auto& m : methods)
      if (m.method.kind == eval::MergeMethodKind::dcs)
        throw core::ConfigError(p.where("methods") + ": DCS is not part of this study");
    const auto find_scale = [&](double s, const std::string& key) {
      for (std::size_t k = 0; k < scales.size(); ++k)
        if (scales[k] == s) return k;
      throw core::ConfigError(claims.where(key) + ": must be one of `noise_scales`");
    };
    const std::size_t k_claim = find_scale(claim_scale, "noise_scale"), k_cal = find_scale(cal_scale,
                                                                                           "calibration_scale");
    std::size_t j_cal = pair_p.size();
    for (std::size_t j = 0; j < pair_p.size(); ++j)
      if (pair_p[j] == cal_p) j_cal = j;
    if (j_cal == pair_p.size())
      throw core::ConfigError(claims.where("calibration_p") + ": must be one of `pair_p_values`");

    // Regimes: the file's own measurements (one realization: they are fixed), then each noise scale.
    std::vector<Regime> regimes;
    regimes.push_back({"dataset", false, 1.0, 1});
    for (double s : scales) regimes.push_back({"s" + tag_of(s), true, s, realizations});
    const std::size_t r_claim = 1 + k_claim, r_cal = 1 + k_cal;
    std::vector<std::string> p_tags;
    std::vector<double> gammas;
    for (double x : pair_p) {
      p_tags.push_back(tag_of(100.0 * x));
      gammas.push_back(pcm::consistency_threshold(x, 3));
    }

    auto& r = ex.results();
    auto t0 = std::chrono::steady_clock::now();
    const auto graph = keel::graph::read_pose_graph_2d(keel::graph::resolve_dataset_file(dataset, graph_file));
    const auto truth = keel::graph::read_poses_2d(keel::graph::resolve_dataset_file(dataset, truth_file));
    const auto base = sim::split_two_robots(graph, truth, split);
    r.timing("read_and_split", ke::seconds_since(t0));
    r.metric("scenario.pool", static_cast<double>(base.pool.size()));
    r.metric("datasets", static_cast<double>(datasets));
    r.metric("realizations", static_cast<double>(realizations));
    r.metric("candidates", copt_base.total());
    if (base.pool.size() < 2) throw std::runtime_error("the pool needs at least two true loop closures");

    // Phase 1, per realization: redraw the measurements, solve both local maps once, and measure the calibration
    // of Q on the realization's whole pool of true loop closures (every ordered pair of inliers).
    std::vector<Realization> reals;
    for (std::size_t g = 0; g < regimes.size(); ++g)
      for (std::size_t k = 0; k < regimes[g].realizations; ++k) {
        Realization x;
        x.regime = g;
        x.index = k;
        reals.push_back(std::move(x));
      }
    t0 = std::chrono::steady_clock::now();
    {
      core::Progress progress(ex.id() + " (local maps)", reals.size());
      core::parallel_for(
          reals.size(),
          [&](std::size_t i) {
            auto& x = reals[i];
            const auto& g = regimes[x.regime];
            x.scenario = base;
            if (g.resampled) sim::resample_measurements(x.scenario, g.scale, resample_seed + x.index);
            x.pool_chi2 = pool_chi2_at_truth(x.scenario);
            x.a = eval::solve_local(x.scenario.robot_a);  // one Ceres thread (LocalSolveOptions default)
            x.b = eval::solve_local(x.scenario.robot_b);
            const auto maps = eval::local_maps(x.a, x.b, x.scenario.pool);
            for (int c = 0; c < 2; ++c) {
              pcm::ConsistencyOptions co;
              co.composition = c == 0 ? pcm::Composition::joint : pcm::Composition::independent;
              co.threads = 1;
              const auto Q = pcm::consistency_matrix(maps.a, maps.b, x.scenario.pool, co);
              std::vector<double> above(gammas.size(), 0.0);
              double sum = 0.0, pairs = 0.0;
              for (int u = 0; u < Q.n; ++u)
                for (int v = 0; v < Q.n; ++v) {
                  if (u == v) continue;
                  const double q = Q.at(u, v);
                  sum += q;
                  pairs += 1.0;
                  for (std::size_t j = 0; j < gammas.size(); ++j) above[j] += q > gammas[j];
                }
              for (auto& f : above) f /= pairs;
              x.fail[c] = above;
              x.q_mean[c] = sum / pairs;
            }
          },
          ex.threads(), &progress);
      progress.finish();
    }
    r.timing("local_maps_and_calibration", ke::seconds_since(t0));

    // Phase 2, per (realization, data set): the candidate set of data set d (stream (seed, d): the same index draws
    // in every realization) and every method.
    std::vector<eval::MergeMethod> specs;
    for (const auto& m : methods) specs.push_back(m.method);
    const std::size_t items = reals.size() * datasets;
    std::vector<std::vector<Outcome>> out(items);
    t0 = std::chrono::steady_clock::now();
    {
      core::Progress progress(ex.id(), items);
      core::parallel_for(
          items,
          [&](std::size_t it) {
            const auto& x = reals[it / datasets];
            const std::size_t d = it % datasets;
            sim::CandidateOptions copt = copt_base;
            copt.aliased_noise_scale = regimes[x.regime].scale;
            const auto run = eval::run_merge_dataset(x.scenario, x.a, x.b, copt, specs, ex.seed(), d);
            auto& o = out[it];
            for (const auto& m : run.methods)
              o.push_back({m.metrics.classification, m.metrics.normalized_chi2, m.selection.time_s});
          },
          ex.threads(), &progress);
      progress.finish();
    }
    r.timing("datasets", ke::seconds_since(t0));

    // Summaries: per regime and realization, pooled TPR/FPR and mean merged normalized χ² per method; calibration.
    struct Curve {
      std::vector<double> tpr, fpr, chi2;  // per realization
    };
    std::vector<std::vector<Curve>> curves(regimes.size(), std::vector<Curve>(methods.size()));
    // fails[g][c][j] and qmeans[g][c]: per realization.
    std::vector<std::vector<std::vector<std::vector<double>>>> fails(
        regimes.size(), std::vector<std::vector<std::vector<double>>>(2, std::vector<std::vector<double>>(gammas.size())));
    std::vector<std::vector<std::vector<double>>> qmeans(regimes.size(), std::vector<std::vector<double>>(2));
    std::vector<std::vector<double>> local_chi2_a(regimes.size()), local_chi2_b(regimes.size()),
        pool_chi2(regimes.size());
    std::vector<std::vector<double>> sel_time(methods.size());
    for (std::size_t i = 0; i < reals.size(); ++i) {
      const auto& x = reals[i];
      for (std::size_t m = 0; m < methods.size(); ++m) {
        eval::Classification c;
        double chi2 = 0.0;
        for (std::size_t d = 0; d < datasets; ++d) {
          const auto& o = out[i * datasets + d][m];
          c.tp += o.c.tp;
          c.fp += o.c.fp;
          c.fn += o.c.fn;
          c.tn += o.c.tn;
          chi2 += o.chi2;
          sel_time[m].push_back(o.selection_time_s);
        }
        auto& cv = curves[x.regime][m];
        cv.tpr.push_back(c.tpr());
        cv.fpr.push_back(c.fpr());
        cv.chi2.push_back(chi2 / static_cast<double>(datasets));
      }
      for (int c = 0; c < 2; ++c) {
        for (std::size_t j = 0; j < gammas.size(); ++j) fails[x.regime][c][j].push_back(x.fail[c][j]);
        qmeans[x.regime][c].push_back(x.q_mean[c]);
      }
      local_chi2_a[x.regime].push_back(x.a.summary.normalized_chi2);
      local_chi2_b[x.regime].push_back(x.b.summary.normalized_chi2);
      pool_chi2[x.regime].push_back(x.pool_chi2);
    }
    for (std::size_t m = 0; m < methods.size(); ++m)
      if (methods[m].method.kind != eval::MergeMethodKind::no_outliers)
        r.timing(methods[m].method.name + ".selection_s.mean", stats_of(sel_time[m]).mean);
    const char* comp_name[2] = {"joint", "independent"};
    // Mean/min/max over the realizations: tpr_s/fpr_s/chi2_s[g][m], fail_s[g][c][j], q_s[g][c].
    std::vector<std::vector<Stats>> tpr_s(regimes.size()), fpr_s(regimes.size()), chi2_s(regimes.size());
    std::vector<std::vector<std::vector<Stats>>> fail_s(regimes.size(), std::vector<std::vector<Stats>>(2));
    std::vector<std::vector<Stats>> q_s(regimes.size());
    for (std::size_t g = 0; g < regimes.size(); ++g) {
      const std::string& rn = regimes[g].name;
      r.metric(rn + ".noise_scale", regimes[g].scale);
      for (std::size_t m = 0; m < methods.size(); ++m) {
        const std::string base_name = rn + "." + methods[m].method.name;
        tpr_s[g].push_back(record(r, base_name + ".tpr", curves[g][m].tpr));
        fpr_s[g].push_back(record(r, base_name + ".fpr", curves[g][m].fpr));
        chi2_s[g].push_back(record(r, base_name + ".chi2", curves[g][m].chi2));
      }
      for (int c = 0; c < 2; ++c) {
        for (std::size_t j = 0; j < gammas.size(); ++j)
          fail_s[g][c].push_back(
              record(r, rn + ".pair_fail_" + p_tags[j] + "." + comp_name[c], fails[g][c][j]));
        q_s[g].push_back(record(r, rn + ".pair_q_mean." + comp_name[c], qmeans[g][c]));
      }
      record(r, rn + ".local.a.chi2", local_chi2_a[g]);
      record(r, rn + ".local.b.chi2", local_chi2_b[g]);
      record(r, rn + ".pool_chi2", pool_chi2[g]);
    }

    // Claim checks (they may fail).
    char detail[600];
    {
      const auto& cv = curves[r_claim][i_claim];
      bool ok = true;
      for (std::size_t k = 0; k < cv.tpr.size(); ++k) ok = ok && cv.tpr[k] >= tpr_min && cv.fpr[k] <= fpr_max;
      std::snprintf(detail, sizeof detail, "%s at s = %g, per realization: TPR %s; FPR %s (thesis 0.997 / 0.001)",
                    claim_method.c_str(), claim_scale, join(cv.tpr, "%.4f").c_str(), join(cv.fpr, "%.4f").c_str());
      r.check(claim_method + " at the thesis's implied noise level (s = " + ke::fmt(claim_scale) +
                  ") keeps TPR >= " + ke::fmt(tpr_min) + " and FPR <= " + ke::fmt(fpr_max) + " in every realization",
              ok, detail);
    }
    {
      const auto& f = fails[r_cal][0][j_cal];
      const double m = fail_s[r_cal][0][j_cal].mean;
      std::snprintf(detail, sizeof detail,
                    "joint Q, s = %g: fraction of ordered inlier pairs with q > gamma(%g) = %.3f: mean %.4f "
                    "(realizations %s; nominal %g); independent composition mean %.4f; the file's own measurements "
                    "(dataset regime): joint %.4f, independent %.4f",
                    cal_scale, cal_p, gammas[j_cal], m, join(f, "%.4f").c_str(), cal_p,
                    fail_s[r_cal][1][j_cal].mean, fail_s[0][0][j_cal].mean, fail_s[0][1][j_cal].mean);
      r.check("the joint consistency metric is calibrated at the stated noise (s = " + ke::fmt(cal_scale) +
                  "): inlier pairs fail gamma(" + ke::fmt(cal_p) + ") at a rate in [" + ke::fmt(cal_range.first) +
                  ", " + ke::fmt(cal_range.second) + "] (nominal " + ke::fmt(cal_p) + ")",
              m >= cal_range.first && m <= cal_range.second, detail);
    }

    // Figure: against s, one point per realization, a line through the means, the dataset regime as a horizontal
    // line of the same colour.
    core::Figure fig;
    fig.file = ex.id() + ".png";
    fig.title = "PCM on the City10000 two-robot data sets against the noise scale s of redrawn measurements (" +
                std::to_string(realizations) + " realizations x " + std::to_string(datasets) +
                " data sets; dotted: the file's own measurements)";
    std::vector<double> xs;
    for (const auto& g : regimes)
      if (g.resampled) xs.push_back(g.scale);
    const auto per_realization_x = [&](std::size_t g) {
      return std::vector<double>(regimes[g].realizations, regimes[g].scale);
    };
    // A panel over the selection methods (not the reference) from per-regime series.
    const auto method_panel = [&](const std::string& title, const std::string& ylabel, const char* which,
                                  bool with_ref, const std::string& yscale) {
      core::Panel pa;
      pa.title = title;
      pa.xlabel = "noise scale s (residual ~ N(0, s^2 Omega^-1))";
      pa.ylabel = ylabel;
      pa.xlim = std::make_pair(0.0, 1.05 * xs.back());
      pa.yscale = yscale;
      for (std::size_t m = 0; m < methods.size(); ++m) {
        if (!with_ref && m == i_ref) continue;
        const auto pick = [&](std::size_t g) -> const std::vector<double>& {
          const auto& cv = curves[g][m];
          return which[0] == 't' ? cv.tpr : which[0] == 'f' ? cv.fpr : cv.chi2;
        };
        const auto pick_s = [&](std::size_t g) {
          return which[0] == 't' ? tpr_s[g][m] : which[0] == 'f' ? fpr_s[g][m] : chi2_s[g][m];
        };
        std::vector<double> px, py, my;
        for (std::size_t g = 1; g < regimes.size(); ++g) {
          const auto v = pick(g);
          const auto xg = per_realization_x(g);
          px.insert(px.end(), xg.begin(), xg.end());
          py.insert(py.end(), v.begin(), v.end());
          my.push_back(pick_s(g).mean);
        }
        pa.layers.push_back(core::scatter_layer(px, py, "", colors[m], 22.0, 0.6, "o"));
        pa.layers.push_back(core::line_layer(xs, my, methods[m].label, colors[m], "", "-"));
        pa.layers.push_back(core::hline_layer(pick_s(0).mean, "", colors[m], ":"));
      }
      return pa;
    };
    fig.panels.push_back(method_panel("TPR (pooled over the data sets)", "TPR", "tpr", false, "linear"));
    fig.panels.push_back(method_panel("FPR (pooled over the data sets)", "FPR", "fpr", false, "linear"));
    fig.panels.push_back(
        method_panel("normalized chi2 of the merged graph (mean)", "normalized chi2", "chi2", true, "log"));
    const char* comp_color[2] = {"tab:blue", "tab:green"};
    const auto calibration_panel = [&](const std::string& title, const std::string& ylabel, int j,
                                       double nominal, const std::string& yscale) {
      core::Panel pa;
      pa.title = title;
      pa.xlabel = "noise scale s";
      pa.ylabel = ylabel;
      pa.xlim = std::make_pair(0.0, 1.05 * xs.back());
      pa.yscale = yscale;
      for (int c = 0; c < 2; ++c) {
        std::vector<double> px, py, my;
        for (std::size_t g = 1; g < regimes.size(); ++g) {
          const auto& v = j >= 0 ? fails[g][c][static_cast<std::size_t>(j)] : qmeans[g][c];
          const auto xg = per_realization_x(g);
          px.insert(px.end(), xg.begin(), xg.end());
          py.insert(py.end(), v.begin(), v.end());
          my.push_back(j >= 0 ? fail_s[g][c][static_cast<std::size_t>(j)].mean : q_s[g][c].mean);
        }
        pa.layers.push_back(core::scatter_layer(px, py, "", comp_color[c], 22.0, 0.6, "o"));
        pa.layers.push_back(core::line_layer(xs, my, std::string("Q, ") + comp_name[c] + " composition",
                                             comp_color[c], "", "-"));
        pa.layers.push_back(core::hline_layer(
            j >= 0 ? fail_s[0][c][static_cast<std::size_t>(j)].mean : q_s[0][c].mean, "", comp_color[c], ":"));
      }
      if (j >= 0) {
        pa.layers.push_back(core::hline_layer(nominal, "nominal at s = 1", "0.2", "--"));
      } else {
        std::vector<double> ny;  // E q = 3 s² for calibrated Q
        for (double x : xs) ny.push_back(nominal * x * x);
        pa.layers.push_back(core::line_layer(xs, ny, "nominal 3 s^2", "0.2", "", "--"));
      }
      return pa;
    };
    for (std::size_t j = 0; j < gammas.size(); ++j) {
      char title[160];
      std::snprintf(title, sizeof title, "inlier pairs with q > gamma(%g %%) = %.2f", 100.0 * pair_p[j], gammas[j]);
      fig.panels.push_back(
          calibration_panel(title, "fraction of ordered pool pairs", static_cast<int>(j), pair_p[j], "linear"));
    }
    fig.panels.push_back(calibration_panel("mean q over the ordered pool pairs", "mean q", -1, 3.0,
                                           "log"));
    fig.cols = 3;
    fig.rows = static_cast<int>((fig.panels.size() + 2) / 3);
    fig.width = 17.0;
    fig.height = 4.8 * fig.rows;
    r.figure(fig);
  });
}
