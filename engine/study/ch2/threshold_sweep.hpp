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
