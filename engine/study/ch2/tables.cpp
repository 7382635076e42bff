#include "study/ch2/tables.hpp"

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

namespace keel::study::ch2 {

using repro::Figure;
using repro::Layer;
using repro::Panel;
using repro::Results;
using repro::RunContext;

namespace {

// Index of the method [params.claims] names, as a located configuration error when it is unknown or, with
// `kind`, of another kind.
std::size_t claimed_method(const std::vector<StudyMethod>& methods, const core::ConfigTable& claims,
                           const std::string& name,
                           std::optional<merge::MergeMethodKind> kind = std::nullopt) {
  std::size_t k = 0;
  try {
    k = method_index(methods, name, "[params.claims]");
  } catch (const std::invalid_argument& e) {
    throw core::ConfigError(fmt::format("{}: {}", claims.file(), e.what()));
  }
  if (kind && methods[k].method.kind() != *kind)
    throw core::ConfigError(fmt::format("{}: [params.claims] names '{}' where a {} method is needed",
                                        claims.file(), name, merge::to_string(*kind)));
  return k;
}

std::vector<std::size_t> claimed_methods(const std::vector<StudyMethod>& methods,
                                         const core::ConfigTable& claims,
                                         const std::vector<std::string>& names,
                                         std::optional<merge::MergeMethodKind> kind = std::nullopt) {
  std::vector<std::size_t> out;
  for (const auto& n : names) out.push_back(claimed_method(methods, claims, n, kind));
  return out;
}

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
std::string tag_of(double v) {
  std::string s = fmt::format("{:g}", v);
  std::replace(s.begin(), s.end(), '.', '_');
  return s;
}

std::string join(const std::vector<double>& v) {
  std::string out;
  for (double x : v) out += fmt::format("{}{:.4f}", out.empty() ? "" : ", ", x);
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// Table 2.1

CityTable::Options CityTable::Options::read(const core::ConfigTable& p) {
  Options o;
  o.regime = read_regime(p, "dataset");
  o.candidates = apply_regime(read_candidate_options(p), o.regime);
  o.datasets = p.count("datasets");
  o.figure_dataset = static_cast<std::size_t>(p.integer("figure_dataset"));
  o.methods = read_methods(p);
  const auto claims = p.table("claims");
  o.pcm = claimed_methods(o.methods, claims, claims.strings("pcm"));
  o.baselines = claimed_methods(o.methods, claims, claims.strings("baselines"));
  o.tpr_min = claims.number("pcm_tpr_min");
  o.fpr_max = claims.number("pcm_fpr_max");
  o.reference =
      claimed_method(o.methods, claims, claims.string("reference"), merge::MergeMethodKind::no_outliers);
  o.dcs = claimed_method(o.methods, claims, claims.string("dcs"));
  o.ransac_low = claimed_method(o.methods, claims, claims.string("ransac_low"));
  o.ransac_high = claimed_method(o.methods, claims, claims.string("ransac_high"));
  o.exact = claimed_method(o.methods, claims, claims.string("pcm_exact"));
  o.heuristic = claimed_method(o.methods, claims, claims.string("pcm_heuristic"));
  o.dcs_tpr_max = claims.number("dcs_tpr_max");
  o.chi2_rel = claims.number("pcm_chi2_rel");
  o.same_selection_min = claims.number("heuristic_same_selection_min");
  o.scenario = ScenarioFiles::read(p);
  if (o.figure_dataset >= o.datasets)
    throw core::ConfigError(
        fmt::format("{}: must be < datasets ({})", p.where("figure_dataset"), o.datasets));
  return o;
}

CityTable::Outcome CityTable::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  auto t0 = core::Clock::now();
  out.scenario = apply_regime(load_scenario_2d(o.scenario), o.regime);
  out.read_time_s = core::seconds_since(t0);
  out.local = solve_local_pair(out.scenario);
  t0 = core::Clock::now();
  core::Progress progress = context.progress(o.datasets);
  out.runs = run_merge_datasets(out.scenario, out.local, o.candidates, methods_of(o.methods), context,
                                o.datasets, o.figure_dataset, &progress);
  progress.finish();
  out.datasets_time_s = core::seconds_since(t0);
  return out;
}

void CityTable::record(Results& r, const Outcome& out) {
  const Options& o = out.options;
  const auto& methods = o.methods;
  const auto& runs = out.runs;
  r.timing("read_and_split", out.read_time_s);
  record_local_pair(r, out.scenario, out.local);
  r.metric("datasets", static_cast<double>(o.datasets));
  r.metric("candidates", o.candidates.total());
  r.timing("datasets", out.datasets_time_s);
  record_dataset_timings(r, runs);

  // Table 2.1: per method over the data sets.
  std::vector<MethodSummary> sum;
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const std::string& n = methods[k].method.name;
    const auto s = sum.emplace_back(summarize_method(runs, k));
    for (const char* key : {"trans_mse", "rot_mse", "residual", "chi2"}) {
      const auto v = s.stats(key);
      r.metric(fmt::format("{}.{}", n, key), v.mean);
      r.metric(fmt::format("{}.{}.std", n, key), v.std);
    }
    r.metric(n + ".tpr", s.pooled.tpr());
    r.metric(n + ".fpr", s.pooled.fpr());
    r.metric(n + ".selected", s.mean("selected"));
    r.series(n + ".trans_mse", s.column("trans_mse"));  // per data set
    r.series(n + ".fp", s.column("fp"));
    r.metric(n + ".accepted_aliased",
             s.accepted_aliased);  // totals over the data sets (false positives by kind)
    r.metric(n + ".accepted_random", s.accepted_random);
    if (methods[k].method.kind() != merge::MergeMethodKind::dcs)
      r.metric(n + ".empty_selections", s.empty_selections);
    if (methods[k].method.kind() == merge::MergeMethodKind::densest) {
      // What the relaxation returned before its repair to a clique: its size and its inconsistent pairs.
      const auto& v = s.column("violations");
      r.metric(n + ".raw_size", s.mean("raw_size"));
      r.metric(n + ".violations", s.mean("violations"));
      r.metric(n + ".violating_datasets",
               static_cast<double>(std::count_if(v.begin(), v.end(), [](double x) { return x > 0; })));
    }
    const auto ts = s.stats("selection_time_s"), tv = s.stats("solve_time_s");
    r.timing(n + ".time_s", ts.mean);
    r.timing(n + ".time_s.max", ts.max);
    r.timing(n + ".solve_s.mean", tv.mean);
    r.timing(n + ".solve_s.max", tv.max);
  }
  const std::string& exact = methods[o.exact].method.name;
  const std::string& heuristic = methods[o.heuristic].method.name;
  const std::string& reference = methods[o.reference].method.name;
  const std::size_t same = same_selections(runs, o.exact, o.heuristic);
  const double same_fraction = static_cast<double>(same) / static_cast<double>(o.datasets);
  r.metric(heuristic + ".same_selection_as_exact", same_fraction);
  r.metric(exact + ".proven_optimal",
           static_cast<double>(proven_optimal(runs, o.exact)) / static_cast<double>(o.datasets));

  // Claims of §2.7.2, checked on our numbers (they may fail).
  for (std::size_t k : o.pcm) {
    const auto& c = sum[k].pooled;
    r.check(
        fmt::format("{} keeps the true loop closures and rejects the outliers (TPR >= {:g} and FPR <= {:g})",
                    methods[k].method.name, o.tpr_min, o.fpr_max),
        c.tpr() >= o.tpr_min && c.fpr() <= o.fpr_max,
        fmt::format("TPR {:.4f} (thesis 0.997), FPR {:.4f} (thesis 0.001)", c.tpr(), c.fpr()));
  }
  const auto& e = sum[o.exact];
  std::string worst;
  bool lowest_mse = true, lowest_fpr = true;
  for (std::size_t k : o.baselines) {
    lowest_mse = lowest_mse && e.mean("trans_mse") < sum[k].mean("trans_mse");
    if (methods[k].method.kind() != merge::MergeMethodKind::dcs)
      lowest_fpr = lowest_fpr && e.pooled.fpr() <= sum[k].pooled.fpr();
    worst += fmt::format("{}{} MSE {:.4g} FPR {:.4f}", worst.empty() ? "" : "; ", methods[k].method.name,
                         sum[k].mean("trans_mse"), sum[k].pooled.fpr());
  }
  r.check("PCM merges with a lower translation MSE than every baseline (DCS, SCGP, RANSAC)", lowest_mse,
          fmt::format("{}: MSE {:.4g}; {}", exact, e.mean("trans_mse"), worst));
  r.check("PCM accepts no more outliers than the selection baselines (SCGP, RANSAC): lowest FPR", lowest_fpr,
          fmt::format("{} FPR {:.4f}; {}", exact, e.pooled.fpr(), worst));
  r.check(
      fmt::format("DCS without an initial alignment turns off (nearly) all inter-robot factors (TPR <= {:g})",
                  o.dcs_tpr_max),
      sum[o.dcs].pooled.tpr() <= o.dcs_tpr_max,
      fmt::format("{} TPR {:.4f} FPR {:.4f}", methods[o.dcs].method.name, sum[o.dcs].pooled.tpr(),
                  sum[o.dcs].pooled.fpr()));
  // The looser RANSAC is the one with the larger γ(p) = F⁻¹(1 − p), i.e. the smaller p (pcm/consistency.hpp).
  const std::size_t i_lo = o.ransac_low, i_hi = o.ransac_high;
  const std::size_t i_loose =
                        methods[i_lo].method.p().value() < methods[i_hi].method.p().value() ? i_lo : i_hi,
                    i_strict = i_loose == i_lo ? i_hi : i_lo;
  r.check(
      "RANSAC depends on its threshold: the looser threshold (larger gamma) accepts more outliers",
      sum[i_loose].pooled.fpr() > sum[i_strict].pooled.fpr(),
      fmt::format("FPR {} (gamma {:.3g}) {:.4f} vs {} (gamma {:.3g}) {:.4f}", methods[i_loose].method.name,
                  pcm::consistency_threshold(methods[i_loose].method.p().value(), 3),
                  sum[i_loose].pooled.fpr(), methods[i_strict].method.name,
                  pcm::consistency_threshold(methods[i_strict].method.p().value(), 3),
                  sum[i_strict].pooled.fpr()));
  r.check(fmt::format(
              "PCM-HeuPatt is almost indistinguishable from PCM-Exact (same selection in >= {:g} % of the "
              "data sets)",
              100 * o.same_selection_min),
          same_fraction >= o.same_selection_min,
          fmt::format("identical selections in {} of {} data sets", same, o.datasets));
  r.check(
      fmt::format(
          "PCM's merged graphs are as consistent as the outlier-free graph (mean normalized chi2 within "
          "{:g} % of NO-OUT's)",
          100 * o.chi2_rel),
      std::abs(e.mean("chi2") - sum[o.reference].mean("chi2")) <= o.chi2_rel * sum[o.reference].mean("chi2"),
      fmt::format("mean normalized chi2: {} {:.4f}, {} {:.4f}", exact, e.mean("chi2"), reference,
                  sum[o.reference].mean("chi2")));
}

std::vector<Figure> CityTable::figures(const Outcome& out) {
  // Fig. 2.5: one data set, the merged maps of every method with accepted / rejected candidates.
  const std::size_t d = out.options.figure_dataset;
  return {merged_maps_figure(out.runs[d], out.options.methods, ".png",
                             fmt::format("Fig. 2.5: merged maps of data set {}", d), 0, 1, 0.6)};
}

// ---------------------------------------------------------------------------------------------------------------
// Table 2.2

Substitute3D::Options Substitute3D::Options::read(const core::ConfigTable& p) {
  Options o;
  o.candidates = read_candidate_options(p);
  o.datasets = p.count("datasets");
  o.methods = read_methods(p);
  o.sweep_p = p.numbers("sweep_p");
  const std::vector<double> axes = p.numbers("figure_axes");
  o.figure_dataset = static_cast<std::size_t>(p.integer("figure_dataset"));
  const auto claims = p.table("claims");
  o.reference =
      claimed_method(o.methods, claims, claims.string("reference"), merge::MergeMethodKind::no_outliers);
  o.heuristic = claimed_method(o.methods, claims, claims.string("pcm_heuristic"),
                               merge::MergeMethodKind::pcm_heuristic);
  o.ransac_names = claims.strings("ransac");
  o.pcm_names = claims.strings("pcm");
  o.baseline_names = claims.strings("baselines");
  o.tp_min_fraction = claims.number("pcm_tp_min_fraction");
  o.dcs_tpr_max = claims.number("dcs_tpr_max");
  o.chi2_rel = claims.number("pcm_chi2_rel");
  o.dcs = claimed_method(o.methods, claims, claims.string("dcs"));
  o.exact = claimed_method(o.methods, claims, claims.string("pcm_exact"));
  o.scenario = ScenarioFiles::read(p);
  if (o.figure_dataset >= o.datasets)
    throw core::ConfigError(
        fmt::format("{}: must be < datasets ({})", p.where("figure_dataset"), o.datasets));
  if (axes.size() != 2 || axes[0] == axes[1] ||
      std::any_of(axes.begin(), axes.end(), [](double a) { return a != 0 && a != 1 && a != 2; }))
    throw core::ConfigError(p.where("figure_axes") + ": expected two different axes of 0 (x), 1 (y), 2 (z)");
  o.axis_x = static_cast<int>(axes[0]), o.axis_y = static_cast<int>(axes[1]);
  o.ransac = claimed_methods(o.methods, claims, o.ransac_names, merge::MergeMethodKind::ransac);
  o.pcm = claimed_methods(o.methods, claims, o.pcm_names);
  o.baselines = claimed_methods(o.methods, claims, o.baseline_names);
  for (double q : o.sweep_p)
    if (!(q > 0 && q < 1)) throw core::ConfigError(p.where("sweep_p") + ": every p must be in (0, 1)");
  return o;
}

Substitute3D::Outcome Substitute3D::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  auto t0 = core::Clock::now();
  out.scenario = load_scenario_3d(o.scenario);
  out.read_time_s = core::seconds_since(t0);
  // Fig. 2.6: RANSAC (method 0) and PCM-HeuPatt (method 1) at each p on the figure's data set.
  std::vector<std::vector<merge::MergeMethod>> sweep_methods;
  for (double q : o.sweep_p)
    sweep_methods.push_back(
        {merge::MergeMethod::make("sweep_ransac", merge::MergeMethodKind::ransac, q),
         merge::MergeMethod::make("sweep_pcm_heupatt", merge::MergeMethodKind::pcm_heuristic, q)});
  out.local = solve_local_pair(out.scenario);
  t0 = core::Clock::now();
  core::Progress progress = context.progress(o.datasets + o.sweep_p.size());
  out.runs = run_merge_datasets(out.scenario, out.local, o.candidates, methods_of(o.methods), context,
                                o.datasets, o.figure_dataset, &progress);
  out.sweep = run_method_sweep(out.scenario, out.local, o.candidates, sweep_methods, context,
                               o.figure_dataset, &progress);
  progress.finish();
  out.datasets_time_s = core::seconds_since(t0);
  return out;
}

namespace {

// The Fig. 2.6 sweep: χ², TP, FP of RANSAC (0) and PCM-HeuPatt (1) against p.
using SweepCurves = std::vector<double>[2][3];  // [method][chi2, tp, fp]
void sweep_curves(const std::vector<MergeDataset3>& sweep, SweepCurves& sw) {
  for (const auto& d : sweep)
    for (int m = 0; m < 2; ++m) {
      const auto& mm = d.methods[static_cast<std::size_t>(m)].metrics;
      sw[m][0].push_back(mm.normalized_chi2);
      sw[m][1].push_back(mm.classification.tp);
      sw[m][2].push_back(mm.classification.fp);
    }
}

// The claims of §2.7.3 on the table (they may fail).
void check_table2_2(Results& r, const Substitute3D::Options& c, const std::vector<MethodSummary>& sum) {
  const auto& methods = c.methods;
  const auto mean = [&](std::size_t k, const char* col) { return sum[k].mean(col); };
  const std::string& heu = methods[c.heuristic].method.name;
  const double ref_chi2 = mean(c.reference, "chi2");
  // " ; name value" for every method of `ks`.
  const auto list = [&](const std::vector<std::size_t>& ks, const char* col,
                        fmt::format_string<const std::string&, double> spec) {
    std::string out;
    for (std::size_t k : ks) out += fmt::format(spec, methods[k].method.name, mean(k, col));
    return out;
  };
  for (std::size_t k : c.pcm) {
    const std::string& name = methods[k].method.name;
    r.check(fmt::format("{} keeps the true inter-robot loop closures (mean TP >= {:g} x inliers)", name,
                        c.tp_min_fraction),
            mean(k, "tp") >= c.tp_min_fraction * c.candidates.num_inliers,
            fmt::format("{} mean TP {:.2f} of {} inliers (thesis: 10 of 10)", name, mean(k, "tp"),
                        c.candidates.num_inliers));
    bool ok = true;
    for (std::size_t rk : c.ransac) ok = ok && mean(k, "fp") <= mean(rk, "fp");
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
  for (std::size_t k : c.pcm) {
    const std::string& name = methods[k].method.name;
    r.check(
        fmt::format("{}'s merged graphs are as consistent as the outlier-free graph (mean normalized chi2 "
                    "within {:g} % of NO-OUT's)",
                    name, 100 * c.chi2_rel),
        std::abs(mean(k, "chi2") - ref_chi2) <= c.chi2_rel * ref_chi2,
        fmt::format("mean normalized chi2: {} {:.4f}, {} {:.4f} (thesis: 0.3635 vs 0.3428)", name,
                    mean(k, "chi2"), methods[c.reference].method.name, ref_chi2));
  }
  // A material excess: RANSAC's χ² above PCM's by more than chi2_rel × NO-OUT's χ² (the tolerance within
  // which a graph counts as consistent above). A bare `>` would also hold when RANSAC selects exactly the
  // inliers and PCM drops one (fewer factors, a marginally lower χ²), which says nothing about consistency.
  bool ok = true;
  for (std::size_t rk : c.ransac)
    ok = ok && mean(rk, "chi2") - mean(c.heuristic, "chi2") > c.chi2_rel * ref_chi2;
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
    for (std::size_t bk : c.baselines) best = best && mean(c.heuristic, col) <= mean(bk, col);
    r.check(fmt::format(
                "PCM gives the best {} MSE of the robust methods (mean <= every baseline's; ties count as "
                "best)",
                what),
            best,
            fmt::format("mean {} (m^2): {} {:.6g}{}; NO-OUT {:.6g}", col, heu, mean(c.heuristic, col),
                        list(c.baselines, col, "; {} {:.6g}"), mean(c.reference, col)));
  }
}

}  // namespace

void Substitute3D::record(Results& r, const Outcome& out) {
  const Options& o = out.options;
  const auto& methods = o.methods;
  const auto& runs = out.runs;
  r.timing("read_and_split", out.read_time_s);
  record_local_pair(r, out.scenario, out.local);
  r.metric("scenario.dropped_odometry", out.scenario.dropped_odometry);
  r.metric("scenario.true_anchor.translation_norm", out.scenario.true_anchor.translation().norm());
  r.metric("datasets", static_cast<double>(o.datasets));
  r.metric("candidates", o.candidates.total());
  r.timing("datasets_and_sweep", out.datasets_time_s);
  record_dataset_timings(r, runs);

  // Table 2.2: per method, means over the data sets (and data set 0's row: the thesis's table is one data
  // set).
  std::vector<MethodSummary> sum;
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const std::string& n = methods[k].method.name;
    const auto& s = sum.emplace_back(summarize_method(runs, k));
    for (const char* col : {"rel_pose_trans_mse", "rel_pose_rot", "traj_trans_mse", "traj_rot", "residual",
                            "tp", "fp", "chi2"}) {
      const auto& v = s.column(col);
      r.metric(fmt::format("{}.{}", n, col), s.stats(col).mean);
      r.metric(fmt::format("{}.{}.std", n, col), s.stats(col).std);
      r.metric(fmt::format("{}.dataset0.{}", n, col), v[0]);
      r.series(fmt::format("{}.{}", n, col), v);  // per data set
    }
    r.metric(n + ".tpr", s.pooled.tpr());  // pooled over the data sets
    r.metric(n + ".fpr", s.pooled.fpr());
    r.metric(n + ".accepted_aliased",
             s.accepted_aliased);  // totals over the data sets (false positives by kind)
    r.metric(n + ".accepted_random", s.accepted_random);
    const auto ts = s.stats("selection_time_s"), tv = s.stats("solve_time_s");
    r.timing(n + ".time_s", ts.mean);  // Table 2.2 "Evaluation Time": the selection given Q
    r.timing(n + ".time_s.max", ts.max);
    r.timing(n + ".solve_s.mean", tv.mean);
    r.timing(n + ".solve_s.max", tv.max);
  }
  r.metric(
      methods[o.heuristic].method.name + ".same_selection_as_exact",
      static_cast<double>(same_selections(runs, o.exact, o.heuristic)) / static_cast<double>(o.datasets));
  r.metric(methods[o.exact].method.name + ".proven_optimal",
           static_cast<double>(proven_optimal(runs, o.exact)) / static_cast<double>(o.datasets));

  SweepCurves sw;
  sweep_curves(out.sweep, sw);
  r.series("sweep.p", o.sweep_p);
  for (int m = 0; m < 2; ++m)
    for (int c = 0; c < 3; ++c)
      r.series(fmt::format("sweep.{}.{}", m == 0 ? "ransac" : "pcm_heupatt",
                           c == 0   ? "chi2"
                           : c == 1 ? "tp"
                                    : "fp"),
               sw[m][c]);
  const double sweep_ref_chi2 = runs[o.figure_dataset].methods[o.reference].metrics.normalized_chi2;

  check_table2_2(r, o, sum);
  // Fig. 2.6's claims: PCM-HeuPatt consistent at every threshold, RANSAC inconsistent at every threshold.
  const auto& ransac_chi2 = sw[0][0];
  const auto& pcm_chi2 = sw[1][0];
  bool pcm_ok = true, ransac_ok = true;
  std::string pcm_v, ransac_v;
  for (std::size_t k = 0; k < o.sweep_p.size(); ++k) {
    pcm_ok = pcm_ok && std::abs(pcm_chi2[k] - sweep_ref_chi2) <= o.chi2_rel * sweep_ref_chi2;
    ransac_ok = ransac_ok && ransac_chi2[k] > (1 + o.chi2_rel) * sweep_ref_chi2;
    pcm_v += fmt::format("{}{:g}: {:.4f}", k ? ", " : "", o.sweep_p[k], pcm_chi2[k]);
    ransac_v += fmt::format("{}{:g}: {:.4f}", k ? ", " : "", o.sweep_p[k], ransac_chi2[k]);
  }
  r.check(
      fmt::format("Fig. 2.6: PCM-HeuPatt's merged graph is consistent at every threshold of the sweep (chi2 "
                  "within {:g} % of NO-OUT's)",
                  100 * o.chi2_rel),
      pcm_ok,
      fmt::format("data set {}, NO-OUT chi2 {:.4f}; PCM-HeuPatt chi2 at p = {}", o.figure_dataset,
                  sweep_ref_chi2, pcm_v));
  r.check(fmt::format(
              "Fig. 2.6: RANSAC's merged graph is inconsistent at every threshold of the sweep (chi2 more "
              "than {:g} % above NO-OUT's)",
              100 * o.chi2_rel),
          ransac_ok,
          fmt::format("data set {}, NO-OUT chi2 {:.4f}; RANSAC chi2 at p = {}", o.figure_dataset,
                      sweep_ref_chi2, ransac_v));
}

std::vector<Figure> Substitute3D::figures(const Outcome& out) {
  const Options& o = out.options;
  SweepCurves sw;
  sweep_curves(out.sweep, sw);
  const double ref_chi2 = out.runs[o.figure_dataset].methods[o.reference].metrics.normalized_chi2;
  // Fig. 2.6: χ² and the selection counts of RANSAC (sw[0]) and PCM-HeuPatt (sw[1]) against p.
  Figure f;
  f.file = "_fig2_6.png";
  f.title =
      fmt::format("Fig. 2.6 (substitute): RANSAC and PCM-HeuPatt vs threshold p, sphere2500 data set {}",
                  o.figure_dataset);
  Panel chi2;
  chi2.title = "normalized chi2 of the merged graph";
  chi2.xlabel = "p (gamma = chi2 quantile at 1 - p, 6 dof)";
  chi2.ylabel = "normalized chi2";
  chi2.xscale = "log";
  // From 0, so that differences of 10⁻⁴ (dropped inliers) are not drawn as large as an inconsistent graph.
  double top = 2.0 * ref_chi2;
  for (int m = 0; m < 2; ++m)
    for (double v : sw[m][0]) top = std::max(top, 1.1 * v);
  chi2.ylim = std::make_pair(0.0, top);
  chi2.layers.push_back(repro::line_layer(o.sweep_p, sw[1][0], "PCM-HeuPatt", "navy", "o"));
  chi2.layers.push_back(repro::line_layer(o.sweep_p, sw[0][0], "RANSAC", "red", "s"));
  chi2.layers.push_back(repro::hline_layer(ref_chi2, "NO-OUT", "0.4"));
  Panel counts;
  counts.title = "selected inliers (TP) and outliers (FP)";
  counts.xlabel = chi2.xlabel;
  counts.ylabel = "count";
  counts.xscale = "log";
  counts.layers.push_back(repro::line_layer(o.sweep_p, sw[1][1], "PCM-HeuPatt TP", "navy", "o"));
  counts.layers.push_back(repro::line_layer(o.sweep_p, sw[1][2], "PCM-HeuPatt FP", "navy", "o", "--"));
  counts.layers.push_back(repro::line_layer(o.sweep_p, sw[0][1], "RANSAC TP", "red", "s"));
  counts.layers.push_back(repro::line_layer(o.sweep_p, sw[0][2], "RANSAC FP", "red", "s", "--"));
  f.panels.push_back(chi2);
  f.panels.push_back(counts);
  const char* axis_name[3] = {"x (m)", "y (m)", "z (m)"};
  return {f, merged_maps_figure(out.runs[o.figure_dataset], o.methods, "_fig2_7.png",
                                fmt::format("Fig. 2.7 (substitute): merged sphere2500 maps of data set {}",
                                            o.figure_dataset),
                                o.axis_x, o.axis_y, 0.4, axis_name[o.axis_x], axis_name[o.axis_y])};
}

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
    o.gammas.push_back(pcm::consistency_threshold(o.pair_p[j], 3));
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

// `name` as a series over the realizations plus its .mean, .min and .max.
void record_values(Results& r, const std::string& name, const std::vector<double>& v) {
  const auto st = core::mean_std(v);
  r.series(name, v);
  r.metric(name + ".mean", st.mean);
  r.metric(name + ".min", st.min);
  r.metric(name + ".max", st.max);
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

// ---------------------------------------------------------------------------------------------------------------
// Fig. 2.4

ThresholdSweep::Options ThresholdSweep::Options::read(const core::ConfigTable& p) {
  Options o;
  o.candidates = read_candidate_options(p);
  o.datasets = p.count("datasets");
  o.p_values = p.numbers("p_values");
  o.claim_p_max = p.number("claim_p_max");
  o.claim_tpr_spread = p.number("claim_tpr_spread");
  o.claim_fpr_max = p.number("claim_fpr_max");
  const auto family_table = p.table("family");
  for (const auto& name : p.strings("families")) {
    const auto t = family_table.table(name);
    o.families.push_back({name, t.string("label"), t.string("color"),
                          t.parse("kind", merge::merge_method_kind_from_string),
                          t.parse_or("composition", pcm::composition_from_string, pcm::Composition::joint)});
    const auto kind = o.families.back().kind;
    if (kind == merge::MergeMethodKind::no_outliers || kind == merge::MergeMethodKind::dcs ||
        kind == merge::MergeMethodKind::scgp)
      throw core::ConfigError(t.where("kind") +
                              ": a threshold sweep needs pcm_exact, pcm_heuristic or ransac");
  }
  o.regimes = read_regimes(p, "regimes", "regime");
  o.scenario = ScenarioFiles::read(p);
  for (std::size_t k = 0; k < o.p_values.size(); ++k)
    if (!(o.p_values[k] > 0.0 && o.p_values[k] < 1.0) || (k > 0 && o.p_values[k] <= o.p_values[k - 1]))
      throw core::ConfigError(p.where("p_values") + ": must be increasing and inside (0, 1)");
  const auto family = [&](const char* name) {
    for (std::size_t f = 0; f < o.families.size(); ++f)
      if (o.families[f].name == name) return f;
    throw core::ConfigError(p.where("families") + ": the claims need pcm_exact, pcm_heuristic and ransac");
  };
  o.fe = family("pcm_exact"), o.fh = family("pcm_heuristic"), o.fr = family("ransac");
  return o;
}

ThresholdSweep::Outcome ThresholdSweep::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  auto t0 = core::Clock::now();
  const auto base = load_scenario_2d(o.scenario);
  out.read_time_s = core::seconds_since(t0);
  out.pool = base.pool.size();
  // One method per (family, p); NO-OUT first (the χ² reference of the figure).
  std::vector<merge::MergeMethod> specs = {
      merge::MergeMethod::make("no_out", merge::MergeMethodKind::no_outliers)};
  for (const auto& f : o.families)
    for (double q : o.p_values) {
      specs.push_back(merge::MergeMethod::make(fmt::format("{}@{:g}", f.name, q), f.kind, q, f.composition));
      specs.back().validate();
    }
  const auto spec_index = [&](std::size_t f, std::size_t k) { return 1 + f * o.p_values.size() + k; };
  for (const auto& g : o.regimes) {
    RegimeOutcome& ro = out.regimes.emplace_back();
    const auto scenario = apply_regime(base, g);
    t0 = core::Clock::now();
    const auto local = solve_local_pair(scenario);
    ro.local_time_s = core::seconds_since(t0);
    t0 = core::Clock::now();
    core::Progress progress = context.progress(o.datasets);
    const auto runs = run_merge_datasets(scenario, local, apply_regime(o.candidates, g), specs, context,
                                         o.datasets, o.datasets, &progress);
    progress.finish();
    ro.datasets_time_s = core::seconds_since(t0);
    // Pooled TPR/FPR, mean normalized χ² and mean selection size per (family, p).
    ro.chi2_no_out = summarize_method(runs, 0).mean("chi2");
    ro.curves.resize(o.families.size());
    for (std::size_t f = 0; f < o.families.size(); ++f)
      for (std::size_t k = 0; k < o.p_values.size(); ++k) {
        const auto s = summarize_method(runs, spec_index(f, k));
        ro.curves[f].tpr.push_back(s.pooled.tpr());
        ro.curves[f].fpr.push_back(s.pooled.fpr());
        ro.curves[f].chi2.push_back(s.mean("chi2"));
        ro.curves[f].selected.push_back(s.mean("selected"));
        ro.curves[f].selection_time_s.push_back(s.mean("selection_time_s"));
      }
  }
  return out;
}

void ThresholdSweep::record(Results& r, const Outcome& out) {
  const Options& o = out.options;
  const auto& p_values = o.p_values;
  r.timing("read_and_split", out.read_time_s);
  r.metric("scenario.pool", static_cast<double>(out.pool));
  r.metric("datasets", static_cast<double>(o.datasets));
  r.metric("candidates", o.candidates.total());
  r.series("p", p_values);
  for (std::size_t gi = 0; gi < o.regimes.size(); ++gi) {
    const auto& g = o.regimes[gi];
    const RegimeOutcome& ro = out.regimes[gi];
    const auto& curves = ro.curves;
    r.timing(g.name + ".local_solves", ro.local_time_s);
    r.timing(g.name + ".datasets", ro.datasets_time_s);
    r.metric(g.name + ".no_out.chi2", ro.chi2_no_out);
    for (std::size_t f = 0; f < o.families.size(); ++f) {
      for (std::size_t k = 0; k < p_values.size(); ++k)
        r.timing(fmt::format("{}.{}@{:g}.time_s", g.name, o.families[f].name, p_values[k]),
                 curves[f].selection_time_s[k]);
      const auto n = g.name + "." + o.families[f].name;
      r.series(n + ".tpr", curves[f].tpr);
      r.series(n + ".fpr", curves[f].fpr);
      r.series(n + ".chi2", curves[f].chi2);
      r.series(n + ".selected", curves[f].selected);
      for (std::size_t k = 0; k < p_values.size(); ++k)
        if (p_values[k] == 0.11) {
          r.metric(n + ".tpr@0.11", curves[f].tpr[k]);
          r.metric(n + ".fpr@0.11", curves[f].fpr[k]);
        }
    }

    // The claims of §2.7.2.1 on this regime's curves (they may fail).
    const std::string in = " [" + g.label + "]";
    const std::size_t fe = o.fe, fh = o.fh, fr = o.fr;
    const double chi2_no_out = ro.chi2_no_out;
    double tmin = 1.0, tmax = 0.0, fmax = 0.0;
    std::string at;
    for (std::size_t k = 0; k < p_values.size(); ++k) {
      if (p_values[k] > o.claim_p_max) continue;
      tmin = std::min(tmin, curves[fe].tpr[k]);
      tmax = std::max(tmax, curves[fe].tpr[k]);
      fmax = std::max(fmax, curves[fe].fpr[k]);
      at += fmt::format("{}p={:g}: {:.3f}/{:.4f}", at.empty() ? "" : ", ", p_values[k], curves[fe].tpr[k],
                        curves[fe].fpr[k]);
    }
    const std::string detail = "PCM-Exact TPR/FPR " + at;
    r.check(
        fmt::format("PCM's TPR is relatively unaffected by the threshold for p <= {:g} (spread <= {:g}){}",
                    o.claim_p_max, o.claim_tpr_spread, in),
        tmax - tmin <= o.claim_tpr_spread, detail);
    r.check(fmt::format("PCM's FPR stays <= {:g} for p <= {:g}{}", o.claim_fpr_max, o.claim_p_max, in),
            fmax <= o.claim_fpr_max, detail);
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
        "PCM's merged graphs are consistent at every threshold (normalized chi2 within 10 % of NO-OUT's)" +
            in,
        worst <= 0.1,
        fmt::format("largest relative difference to NO-OUT's {:.4g}: {:.4f}", chi2_no_out, worst));
    r.check("PCM-Heuristic tracks PCM-Exact across the sweep (all but at most one threshold)" + in,
            same + 1 >= p_values.size(),
            fmt::format("identical pooled TPR and FPR at {} of {} thresholds", same, p_values.size()));
  }
}

std::vector<Figure> ThresholdSweep::figures(const Outcome& out) {
  const Options& o = out.options;
  Figure fig;
  fig.file = ".png";
  fig.title = fmt::format(
      "Fig. 2.4: City10000 two-robot data sets ({} sets) against the tail probability p of "
      "γ(p) = F⁻¹χ²(3)(1 − p); larger p = stricter",
      o.datasets);
  fig.cols = 3;
  fig.rows = static_cast<int>(o.regimes.size());
  fig.width = 16.5;
  fig.height = 4.6 * fig.rows;
  // One row of three panels (TPR, FPR, χ²) per regime.
  for (std::size_t gi = 0; gi < o.regimes.size(); ++gi) {
    const auto& curves = out.regimes[gi].curves;
    const char* names[3] = {"TPR", "FPR", "normalized χ²"};
    for (int panel = 0; panel < 3; ++panel) {
      Panel pa;
      pa.title = fmt::format("{} — {}", names[panel], o.regimes[gi].label);
      pa.xlabel = "p";
      pa.ylabel = names[panel];
      pa.xscale = "logit";  // p spans 0.001 … 0.99: both ends matter
      if (panel == 2) pa.yscale = "log";
      pa.legend = panel == 0 ? "" : "none";
      for (std::size_t f = 0; f < o.families.size(); ++f) {
        const auto& y = panel == 0 ? curves[f].tpr : panel == 1 ? curves[f].fpr : curves[f].chi2;
        pa.layers.push_back(repro::line_layer(o.p_values, y, o.families[f].label, o.families[f].color, "o",
                                              o.families[f].name == "pcm_heuristic" ? "--" : ""));
      }
      if (panel == 2) pa.layers.push_back(repro::hline_layer(out.regimes[gi].chi2_no_out, "NO-OUT", "0.3"));
      fig.panels.push_back(pa);
    }
  }
  return {fig};
}

}  // namespace keel::study::ch2
