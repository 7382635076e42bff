// The chapter-2 studies on two-robot data sets (§2.7.2–2.7.3), one per experiment: CityTable (Table 2.1 and
// Fig. 2.5 on a split of City10000, with the file's or redrawn measurements), NoiseRegimes (Table 2.1's PCM
// against the noise of redrawn measurements, and the calibration of Q), Substitute3D (Table 2.2 and Figs.
// 2.6–2.7 on a split of sphere2500) and ThresholdSweep (Fig. 2.4: TPR, FPR and χ² against the consistency
// threshold). Each has the study shape of repro/run.hpp; the machinery is two_robot.hpp's and
// merge_eval.hpp's.
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

// Table 2.1 and Fig. 2.5 (§2.7.2): robust merging of the two-robot data sets of a City10000 split with every
// method; `measurements = "dataset"` keeps the file's measurements, `"resampled"` redraws every measurement
// with the noise scaled by `noise_scale` (MeasurementRegime).
struct CityTable {
  struct Options {
    ScenarioFiles scenario;
    MeasurementRegime regime;
    sim::CandidateOptions candidates;  // with the regime's noise scale
    std::size_t datasets = 0, figure_dataset = 0;
    std::vector<StudyMethod> methods;
    // The claims of §2.7.2: which methods they compare (indices into methods) and their thresholds.
    std::vector<std::size_t> pcm, baselines;
    std::size_t reference = 0, dcs = 0, ransac_low = 0, ransac_high = 0, exact = 0, heuristic = 0;
    double tpr_min = 0, fpr_max = 0, dcs_tpr_max = 0, chi2_rel = 0, same_selection_min = 0;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    sim::TwoRobotScenario2 scenario;
    LocalPair<lie::SE2> local;
    std::vector<MergeDataset2> runs;  // data set figure_dataset keeps its merged solutions
    double read_time_s = 0, datasets_time_s = 0;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Table 2.2 and Figs. 2.6–2.7 (§2.7.3) on a SUBSTITUTE for the thesis's 3D data: a two-robot split of
// sphere2500.
struct Substitute3D {
  struct Options {
    ScenarioFiles scenario;
    sim::CandidateOptions candidates;
    std::size_t datasets = 0, figure_dataset = 0;
    std::vector<StudyMethod> methods;
    std::vector<double> sweep_p;  // Fig. 2.6: RANSAC and PCM-HeuPatt at each p on figure_dataset
    int axis_x = 0, axis_y = 2;   // Fig. 2.7's projection (0 = x, 1 = y, 2 = z)
    // The claims of §2.7.3: method names and indices, and their thresholds.
    std::vector<std::string> pcm_names, ransac_names, baseline_names;
    std::vector<std::size_t> pcm, ransac, baselines;
    std::size_t reference = 0, dcs = 0, heuristic = 0, exact = 0;
    double tp_min_fraction = 0, dcs_tpr_max = 0, chi2_rel = 0;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    sim::TwoRobotScenario3 scenario;
    LocalPair<lie::SE3> local;
    std::vector<MergeDataset3> runs;   // data set figure_dataset keeps its merged solutions
    std::vector<MergeDataset3> sweep;  // one per p of sweep_p, on figure_dataset
    double read_time_s = 0, datasets_time_s = 0;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

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

// Fig. 2.4 (§2.7.2.1): pooled TPR, FPR and mean normalized χ² of PCM-Exact, PCM-Heuristic and RANSAC (and,
// beyond the thesis, PCM-Exact composing the local poses as independent) against the threshold p, in one or
// more measurement regimes.
struct ThresholdSweep {
  // One curve family: a selection method swept over p.
  struct Family {
    std::string name, label, color;
    merge::MergeMethodKind kind = merge::MergeMethodKind::pcm_exact;
    pcm::Composition composition = pcm::Composition::joint;
  };
  struct Options {
    ScenarioFiles scenario;
    sim::CandidateOptions candidates;
    std::size_t datasets = 0;
    std::vector<double> p_values;
    std::vector<Family> families;
    std::vector<MeasurementRegime> regimes;
    std::size_t fe = 0, fh = 0, fr = 0;  // the PCM-Exact, PCM-Heuristic and RANSAC families
    double claim_p_max = 0, claim_tpr_spread = 0, claim_fpr_max = 0;
    static Options read(const core::ConfigTable& p);
  };
  // One family's pooled TPR/FPR, mean normalized χ² and mean selection size against p, in one regime.
  struct Curve {
    std::vector<double> tpr, fpr, chi2, selected, selection_time_s;
  };
  struct RegimeOutcome {
    double chi2_no_out = 0;
    std::vector<Curve> curves;  // one per family
    double local_time_s = 0, datasets_time_s = 0;
  };
  struct Outcome {
    Options options;
    std::size_t pool = 0;
    std::vector<RegimeOutcome> regimes;
    double read_time_s = 0;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch2
