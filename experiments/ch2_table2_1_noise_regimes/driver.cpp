// Table 2.1 (§2.7.2), PCM rows, across noise regimes: how PCM-11 %'s outcome on the City10000 two-robot data
// sets depends on the noise level of the measurements and on the realization of the local maps, and how well
// the consistency metric is calibrated in each regime — thin driver over keel.eval's two-robot study.
import keel.core;
import keel.repro;
import keel.lie;
import keel.pcm;
import keel.sim;
import keel.merge;
import keel.eval;

#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "ch2_table2_1_noise_regimes/report.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace pcm = keel::pcm;
namespace eval = keel::eval;
using namespace keel::experiments::noise_regimes;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    const auto copt = eval::read_candidate_options(p);
    const std::vector<double> scales = p.numbers("noise_scales"), pair_p = p.numbers("pair_p_values");
    const auto resample_seed = p.integer("resample_seed");
    const std::size_t realizations = p.count("realizations"), datasets = p.count("datasets");
    const auto methods = eval::read_methods(p);
    std::vector<std::string> colors;
    const auto color = p.table("color");
    for (const auto& m : methods) colors.push_back(color.string(m.method.name));
    const auto claims = p.table("claims");
    const Claims c{claims.string("method"),
                   claims.number("noise_scale"),
                   claims.number("tpr_min"),
                   claims.number("fpr_max"),
                   claims.number("calibration_scale"),
                   claims.number("calibration_p"),
                   eval::read_range(claims, "calibration_range")};
    auto t0 = core::Clock::now();
    const auto base = eval::load_scenario_2d(p);
    ex.params_done();
    const Setup s =
        validate_setup(p, claims, ex.seed(), scales, pair_p, resample_seed, realizations, methods, c);
    auto& r = ex.results();
    r.timing("read_and_split", core::seconds_since(t0));
    r.metric("scenario.pool", static_cast<double>(base.pool.size()));
    r.metric("datasets", static_cast<double>(datasets));
    r.metric("realizations", static_cast<double>(realizations));
    r.metric("candidates", copt.total());
    if (base.pool.size() < 2) throw std::runtime_error("the pool needs at least two true loop closures");

    // Regimes: the file's own measurements (one realization: they are fixed), then each noise scale, whose
    // realization k redraws every measurement from the streams (resample_seed + k, 0/1/2).
    std::vector<eval::MeasurementRegime> realization_regimes;
    std::vector<std::size_t> regime_of;  // per realization
    std::vector<Regime> regimes = {{"dataset", 1.0, 1, false}};
    realization_regimes.push_back({"dataset", "", false, 1.0, 0});
    regime_of.push_back(0);
    for (double x : scales) {
      regimes.push_back({"s" + tag_of(x), x, realizations, true});
      for (std::size_t k = 0; k < realizations; ++k) {
        realization_regimes.push_back({regimes.back().name, "", true, x, s.resample_seed + k});
        regime_of.push_back(regimes.size() - 1);
      }
    }

    // Per realization: the scenario, both local maps solved once, and the calibration of Q on its whole pool;
    // then every data set and method (data set d draws from stream (seed, d): the same index in every
    // realization).
    const std::size_t n = realization_regimes.size();
    std::vector<Realization> reals(n);
    core::Progress progress(ex.id(), n * (1 + datasets));
    t0 = core::Clock::now();
    core::parallel_for(
        n,
        [&](std::size_t i) {
          auto& x = reals[i];
          x.scenario = eval::apply_regime(base, realization_regimes[i]);
          x.pool_chi2 = eval::pool_chi2_at_truth(x.scenario);
          x.local = eval::solve_local_pair(x.scenario);  // one Ceres thread (LocalSolveOptions' default)
          for (auto comp : {pcm::Composition::joint, pcm::Composition::independent})
            x.calibration.push_back(eval::pool_calibration(x.local, x.scenario, comp, s.gammas));
        },
        ex.threads(), &progress);
    r.timing("local_maps_and_calibration", core::seconds_since(t0));
    t0 = core::Clock::now();
    for (std::size_t i = 0; i < n; ++i) {
      const auto runs = eval::run_merge_datasets(
          reals[i].scenario, reals[i].local, eval::apply_regime(copt, realization_regimes[i]),
          eval::methods_of(methods), ex.seed(), datasets, ex.threads(), datasets, &progress);
      for (std::size_t m = 0; m < methods.size(); ++m)
        reals[i].methods.push_back(eval::summarize_method(runs, m));
    }
    progress.finish();
    r.timing("datasets", core::seconds_since(t0));

    const auto summary = summarize(reals, regime_of, regimes, methods, s.gammas.size());
    record(r, summary, regimes, methods, s);
    check_claims(r, summary, s, c);
    r.figure(figure(ex.id() + ".png", summary, regimes, methods, colors, s, realizations, datasets));
  });
}
