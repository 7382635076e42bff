// Table 2.1 and Fig. 2.5 (§2.7.2) on a two-robot split of City10000 — the glue shared by ch2_table2_1_city
// (the dataset's own measurements) and ch2_table2_1_thesis_noise (measurements redrawn about the ground truth
// with the noise scaled down, the regime the thesis's χ² values indicate): read [params], run keel::eval's
// two-robot study, record Table 2.1, the claims of §2.7.2 and Fig. 2.5. Include after `import keel.core;
import keel.repro;
// import keel.pcm; import keel.eval;` and "common/two_robot.hpp" (DESIGN rule 4); it imports nothing itself.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace keel::experiments {

// Index of the method [params.claims] names, as a located configuration error when it is unknown or, with
// `kind`, of another kind.
inline std::size_t claimed_method(const std::vector<keel::eval::StudyMethod>& methods,
                                  const keel::core::ConfigTable& claims, const std::string& name,
                                  std::optional<keel::eval::MergeMethodKind> kind = std::nullopt) {
  std::size_t k = 0;
  try {
    k = keel::eval::method_index(methods, name, "[params.claims]");
  } catch (const std::invalid_argument& e) {
    throw keel::core::ConfigError(fmt::format("{}: {}", claims.file(), e.what()));
  }
  if (kind && methods[k].method.kind() != *kind)
    throw keel::core::ConfigError(fmt::format("{}: [params.claims] names '{}' where a {} method is needed",
                                              claims.file(), name, keel::merge::to_string(*kind)));
  return k;
}

// `measurements = "dataset"` keeps the file's measurements; `"resampled"` redraws every measurement with the
// noise scaled by `noise_scale` (keel::eval::MeasurementRegime).
inline void run_city_merge_table(keel::repro::Experiment& ex) {
  namespace core = keel::core;
  namespace repro = keel::repro;
  namespace pcm = keel::pcm;
  namespace eval = keel::eval;
  const auto& p = ex.params();
  const auto regime = eval::read_regime(p, "dataset");
  const auto copt = eval::apply_regime(eval::read_candidate_options(p), regime);
  const std::size_t datasets = p.count("datasets");
  const auto figure_dataset = static_cast<std::size_t>(p.integer("figure_dataset"));
  const auto methods = eval::read_methods(p);
  const auto claims = p.table("claims");
  const auto pcm_names = claims.strings("pcm"), baselines = claims.strings("baselines");
  const double tpr_min = claims.number("pcm_tpr_min"), fpr_max = claims.number("pcm_fpr_max");
  const std::string reference = claims.string("reference"), dcs = claims.string("dcs"),
                    exact = claims.string("pcm_exact"), heuristic = claims.string("pcm_heuristic");
  const std::size_t i_ref = claimed_method(methods, claims, reference, eval::MergeMethodKind::no_outliers),
                    i_dcs = claimed_method(methods, claims, dcs),
                    i_lo = claimed_method(methods, claims, claims.string("ransac_low")),
                    i_hi = claimed_method(methods, claims, claims.string("ransac_high")),
                    i_exact = claimed_method(methods, claims, exact),
                    i_heu = claimed_method(methods, claims, heuristic);
  const double dcs_tpr_max = claims.number("dcs_tpr_max"), chi2_rel = claims.number("pcm_chi2_rel");
  const double same_selection_min = claims.number("heuristic_same_selection_min");
  auto t0 = core::Clock::now();
  const auto scenario = eval::apply_regime(eval::load_scenario_2d(p), regime);
  ex.params_done();
  if (figure_dataset >= datasets)
    throw core::ConfigError(fmt::format("{}: must be < datasets ({})", p.where("figure_dataset"), datasets));
  auto& r = ex.results();
  r.timing("read_and_split", core::seconds_since(t0));
  const auto local = eval::solve_local_pair(scenario);
  eval::record_local_pair(r, scenario, local);
  r.metric("datasets", static_cast<double>(datasets));
  r.metric("candidates", copt.total());

  t0 = core::Clock::now();
  core::Progress progress(ex.id(), datasets);
  const auto runs = eval::run_merge_datasets(scenario, local, copt, eval::methods_of(methods), ex.seed(),
                                             datasets, ex.threads(), figure_dataset, &progress);
  progress.finish();
  r.timing("datasets", core::seconds_since(t0));
  eval::record_dataset_timings(r, runs);

  // Table 2.1: per method over the data sets.
  std::vector<eval::MethodSummary> sum;
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const std::string& n = methods[k].method.name;
    const auto s = sum.emplace_back(eval::summarize_method(runs, k));
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
    if (methods[k].method.kind() != eval::MergeMethodKind::dcs)
      r.metric(n + ".empty_selections", s.empty_selections);
    if (methods[k].method.kind() == eval::MergeMethodKind::densest) {
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
  const std::size_t same = eval::same_selections(runs, i_exact, i_heu);
  const double same_fraction = static_cast<double>(same) / static_cast<double>(datasets);
  r.metric(heuristic + ".same_selection_as_exact", same_fraction);
  r.metric(exact + ".proven_optimal",
           static_cast<double>(eval::proven_optimal(runs, i_exact)) / static_cast<double>(datasets));

  // Claims of §2.7.2, checked on our numbers (they may fail).
  for (const auto& name : pcm_names) {
    const auto& c = sum[claimed_method(methods, claims, name)].pooled;
    r.check(
        fmt::format("{} keeps the true loop closures and rejects the outliers (TPR >= {:g} and FPR <= {:g})",
                    name, tpr_min, fpr_max),
        c.tpr() >= tpr_min && c.fpr() <= fpr_max,
        fmt::format("TPR {:.4f} (thesis 0.997), FPR {:.4f} (thesis 0.001)", c.tpr(), c.fpr()));
  }
  const auto& e = sum[i_exact];
  std::string worst;
  bool lowest_mse = true, lowest_fpr = true;
  for (const auto& name : baselines) {
    const std::size_t k = claimed_method(methods, claims, name);
    lowest_mse = lowest_mse && e.mean("trans_mse") < sum[k].mean("trans_mse");
    if (methods[k].method.kind() != eval::MergeMethodKind::dcs)
      lowest_fpr = lowest_fpr && e.pooled.fpr() <= sum[k].pooled.fpr();
    worst += fmt::format("{}{} MSE {:.4g} FPR {:.4f}", worst.empty() ? "" : "; ", name,
                         sum[k].mean("trans_mse"), sum[k].pooled.fpr());
  }
  r.check("PCM merges with a lower translation MSE than every baseline (DCS, SCGP, RANSAC)", lowest_mse,
          fmt::format("{}: MSE {:.4g}; {}", exact, e.mean("trans_mse"), worst));
  r.check("PCM accepts no more outliers than the selection baselines (SCGP, RANSAC): lowest FPR", lowest_fpr,
          fmt::format("{} FPR {:.4f}; {}", exact, e.pooled.fpr(), worst));
  r.check(
      fmt::format("DCS without an initial alignment turns off (nearly) all inter-robot factors (TPR <= {:g})",
                  dcs_tpr_max),
      sum[i_dcs].pooled.tpr() <= dcs_tpr_max,
      fmt::format("{} TPR {:.4f} FPR {:.4f}", dcs, sum[i_dcs].pooled.tpr(), sum[i_dcs].pooled.fpr()));
  // The looser RANSAC is the one with the larger γ(p) = F⁻¹(1 − p), i.e. the smaller p (pcm/consistency.hpp).
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
              100 * same_selection_min),
          same_fraction >= same_selection_min,
          fmt::format("identical selections in {} of {} data sets", same, datasets));
  r.check(fmt::format(
              "PCM's merged graphs are as consistent as the outlier-free graph (mean normalized chi2 within "
              "{:g} % of NO-OUT's)",
              100 * chi2_rel),
          std::abs(e.mean("chi2") - sum[i_ref].mean("chi2")) <= chi2_rel * sum[i_ref].mean("chi2"),
          fmt::format("mean normalized chi2: {} {:.4f}, {} {:.4f}", exact, e.mean("chi2"), reference,
                      sum[i_ref].mean("chi2")));

  // Fig. 2.5: one data set, the merged maps of every method with accepted / rejected candidates.
  r.figure(merged_maps_figure(runs[figure_dataset], methods, ex.id() + ".png",
                              fmt::format("Fig. 2.5: merged maps of data set {}", figure_dataset), 0, 1,
                              0.6));
}

}  // namespace keel::experiments
