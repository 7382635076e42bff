#pragma once

#include <string>
#include <vector>

#include "study/ch5/pairs.hpp"

namespace keel::study::ch5 {

// Tables 5.1–5.2 against M: the pair Monte Carlo at each sample size on the same streams (one pass up to the
// largest M, every record as a run at that M alone would give it), and a power
// law mean(M) = a·M^b fitted in log–log giving the M at which ours would meet the thesis's published means.
struct PairSampleSize {
  struct Options {
    PairsSetup pairs;
    std::vector<double> samples;  // the sample sizes M (at least two, whole, >= 2, ascending)
    double match_cov_error_joint = 0, match_norm_cov_error_lie = 0;  // the thesis's means
    static Options read(const core::ConfigTable& p);
  };
  // One row per error: its mean and std over the pairs at each M.
  struct Row {
    repro::KeyPath key;  // e.g. cov_error.joint
    std::string label;
    double PairRecord::* field = nullptr;
    std::vector<double> mean, std;
  };
  struct Outcome {
    Options options;
    SolvedPairs solved;
    std::vector<Row> rows;          // Table 5.1 joint, independent; Table 5.2 proposed, SSC, sampling floor
    double monte_carlo_time_s = 0;  // the one pass behind every M
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch5
