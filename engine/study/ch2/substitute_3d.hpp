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

}  // namespace keel::study::ch2
