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

}  // namespace keel::study::ch2
