#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "study/ch2/config.hpp"
#include "study/ch2/merge_eval.hpp"
#include "study/ch2/two_robot.hpp"

namespace keel::study::ch2 {

// Table 2.1 in several noise regimes (beyond the thesis): the file's own measurements, then every measurement
// redrawn at each noise scale s (several realizations each); per regime TPR, FPR and χ² of every method, and
// the calibration of Q on the pool of true loop closures.
struct NoiseRegimes {
  struct Options {
    ScenarioFiles scenario;
    sim::CandidateOptions candidates;
    std::vector<double> scales, pair_p;
    std::uint64_t resample_seed =
        0;  // realization k of a scale redraws from streams (resample_seed + k, 0/1/2)
    std::size_t realizations = 1, datasets = 0;
    std::vector<StudyMethod> methods;
    std::vector<std::string> colors;  // one per method
    std::string
        resample_seed_key;  // where resample_seed was read (for the error naming a clash with the seed)
    // The claims: the method, the regime and bounds of the first; the calibration scale, level and range.
    std::string claim_method;
    double claim_scale = 0, tpr_min = 0, fpr_max = 0, calibration_scale = 0, calibration_p = 0;
    std::pair<double, double> calibration_range;
    // Fixed by the config: γ(p) of the calibration levels, and the indices the claims use.
    std::vector<double> gammas;
    std::vector<std::string> p_tags;
    std::size_t i_claim = 0, i_ref = 0, r_claim = 0, r_cal = 0, j_cal = 0;
    static Options read(const core::ConfigTable& p);
  };
  // One regime of the summary: the file's own measurements, or every measurement redrawn at noise scale s.
  struct Regime {
    std::string name;  // "dataset" or "s<tag>", the metric prefix
    double scale = 1.0;
    std::size_t realizations = 1;
    bool resampled = false;
  };
  // Per regime, one value per realization: TPR, FPR and mean merged χ² per method; calibration per
  // composition and level; mean q; local χ² of both robots and the pool χ² at the truth.
  struct Summary {
    std::vector<std::vector<std::vector<double>>> tpr, fpr, chi2;  // [regime][method][realization]
    std::vector<std::vector<std::vector<std::vector<double>>>>
        fail;                                              // [regime][composition][level][realization]
    std::vector<std::vector<std::vector<double>>> q_mean;  // [regime][composition][realization]
    std::vector<std::vector<double>> local_a, local_b, pool_chi2;  // [regime][realization]
    std::vector<std::vector<double>> selection_time;               // [method], every (realization, data set)
  };
  struct Outcome {
    Options options;
    std::vector<Regime> regimes;
    Summary summary;
    std::size_t pool = 0;
    double read_time_s = 0, local_time_s = 0, datasets_time_s = 0;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch2
