// Table 2.2 and Figs. 2.6–2.7 (§2.7.3) on a SUBSTITUTE: robust 3D merging of a two-robot split of sphere2500
// (NCLT and its GICP front end are not available) with DCS, SCGP, RANSAC and PCM — thin driver over
// keel.eval's two-robot study.
import keel.core;
import keel.repro;
import keel.pcm;
import keel.merge;
import keel.eval;

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "common/two_robot.hpp"
#include "common/city_table.hpp"
#include "ch2_table2_2_3d_substitute/report.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace eval = keel::eval;
using keel::experiments::claimed_method;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    const auto copt = eval::read_candidate_options(p);
    const std::size_t datasets = p.count("datasets");
    const auto methods = eval::read_methods(p);
    const std::vector<double> sweep_p = p.numbers("sweep_p"), axes = p.numbers("figure_axes");
    const auto figure_dataset = static_cast<std::size_t>(p.integer("figure_dataset"));
    const auto claims = p.table("claims");
    const std::string reference = claims.string("reference"), heuristic = claims.string("pcm_heuristic");
    const auto ransacs = claims.strings("ransac"), pcm_names = claims.strings("pcm"),
               baselines = claims.strings("baselines");
    const double tp_min_fraction = claims.number("pcm_tp_min_fraction"),
                 dcs_tpr_max = claims.number("dcs_tpr_max"), chi2_rel = claims.number("pcm_chi2_rel");
    const std::size_t i_ref = claimed_method(methods, claims, reference, eval::MergeMethodKind::no_outliers),
                      i_dcs = claimed_method(methods, claims, claims.string("dcs")),
                      i_heu =
                          claimed_method(methods, claims, heuristic, eval::MergeMethodKind::pcm_heuristic),
                      i_exact = claimed_method(methods, claims, claims.string("pcm_exact"));
    auto t0 = core::Clock::now();
    const auto scenario = eval::load_scenario_3d(p);
    ex.params_done();
    if (figure_dataset >= datasets)
      throw core::ConfigError(
          fmt::format("{}: must be < datasets ({})", p.where("figure_dataset"), datasets));
    if (axes.size() != 2 || axes[0] == axes[1] ||
        std::any_of(axes.begin(), axes.end(), [](double a) { return a != 0 && a != 1 && a != 2; }))
      throw core::ConfigError(p.where("figure_axes") +
                              ": expected two different axes of 0 (x), 1 (y), 2 (z)");
    for (const auto& n : ransacs) (void)claimed_method(methods, claims, n, eval::MergeMethodKind::ransac);
    // Fig. 2.6: RANSAC (method 0) and PCM-HeuPatt (method 1) at each p on the figure's data set.
    std::vector<std::vector<eval::MergeMethod>> sweep_methods;
    for (double q : sweep_p) {
      if (!(q > 0 && q < 1)) throw core::ConfigError(p.where("sweep_p") + ": every p must be in (0, 1)");
      sweep_methods.push_back(
          {eval::MergeMethod::make("sweep_ransac", eval::MergeMethodKind::ransac, q),
           eval::MergeMethod::make("sweep_pcm_heupatt", eval::MergeMethodKind::pcm_heuristic, q)});
    }
    auto& r = ex.results();
    r.timing("read_and_split", core::seconds_since(t0));
    const auto local = eval::solve_local_pair(scenario);
    eval::record_local_pair(r, scenario, local);
    r.metric("scenario.dropped_odometry", scenario.dropped_odometry);
    r.metric("scenario.true_anchor.translation_norm", scenario.true_anchor.translation().norm());
    r.metric("datasets", static_cast<double>(datasets));
    r.metric("candidates", copt.total());

    t0 = core::Clock::now();
    core::Progress progress(ex.id(), datasets + sweep_p.size());
    const auto runs = eval::run_merge_datasets(scenario, local, copt, eval::methods_of(methods), ex.seed(),
                                               datasets, ex.threads(), figure_dataset, &progress);
    const auto sweep = eval::run_method_sweep(scenario, local, copt, sweep_methods, ex.seed(), figure_dataset,
                                              ex.threads(), &progress);
    progress.finish();
    r.timing("datasets_and_sweep", core::seconds_since(t0));
    eval::record_dataset_timings(r, runs);

    // Table 2.2: per method, means over the data sets (and data set 0's row: the thesis's table is one data
    // set).
    std::vector<eval::MethodSummary> sum;
    for (std::size_t k = 0; k < methods.size(); ++k) {
      const std::string& n = methods[k].method.name;
      const auto& s = sum.emplace_back(eval::summarize_method(runs, k));
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
        heuristic + ".same_selection_as_exact",
        static_cast<double>(eval::same_selections(runs, i_exact, i_heu)) / static_cast<double>(datasets));
    r.metric(methods[i_exact].method.name + ".proven_optimal",
             static_cast<double>(eval::proven_optimal(runs, i_exact)) / static_cast<double>(datasets));

    // The Fig. 2.6 sweep as series: χ², TP, FP of RANSAC (0) and PCM-HeuPatt (1) against p.
    std::vector<double> sw[2][3];  // [method][chi2, tp, fp]
    for (const auto& d : sweep)
      for (int m = 0; m < 2; ++m) {
        const auto& mm = d.methods[static_cast<std::size_t>(m)].metrics;
        sw[m][0].push_back(mm.normalized_chi2);
        sw[m][1].push_back(mm.classification.tp);
        sw[m][2].push_back(mm.classification.fp);
      }
    r.series("sweep.p", sweep_p);
    for (int m = 0; m < 2; ++m)
      for (int c = 0; c < 3; ++c)
        r.series(fmt::format("sweep.{}.{}", m == 0 ? "ransac" : "pcm_heupatt",
                             c == 0   ? "chi2"
                             : c == 1 ? "tp"
                                      : "fp"),
                 sw[m][c]);
    const double sweep_ref_chi2 = runs[figure_dataset].methods[i_ref].metrics.normalized_chi2;

    const keel::experiments::Table22Claims tc{pcm_names, ransacs,         baselines,       i_ref,
                                              i_dcs,     i_heu,           tp_min_fraction, dcs_tpr_max,
                                              chi2_rel,  copt.num_inliers};
    keel::experiments::check_table2_2(r, methods, sum, tc, claims);
    keel::experiments::check_fig2_6(r, sweep_p, sw[0][0], sw[1][0], sweep_ref_chi2, figure_dataset, chi2_rel);
    r.figure(keel::experiments::fig2_6(ex.id() + "_fig2_6.png", figure_dataset, sweep_p, sw, sweep_ref_chi2));
    const int ax = static_cast<int>(axes[0]), ay = static_cast<int>(axes[1]);
    const char* axis_name[3] = {"x (m)", "y (m)", "z (m)"};
    r.figure(keel::experiments::merged_maps_figure(
        runs[figure_dataset], methods, ex.id() + "_fig2_7.png",
        fmt::format("Fig. 2.7 (substitute): merged sphere2500 maps of data set {}", figure_dataset), ax, ay,
        0.4, axis_name[ax], axis_name[ay]));
  });
}
