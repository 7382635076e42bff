// The chapter-5 studies of pose pairs of a SLAM solution (§5.9.2, Manhattan3500): PairCorrelation (Table 5.1,
// Figs. 5.10–5.14 a–e), PairsVsSsc (Table 5.2, Figs. 5.10–5.14 f–g) and PairSampleSize (both tables' means
// against the Monte-Carlo sample size M). All three solve the data set, extract the joint Lie-algebra
// marginal of every pair (i, i + k) and run the pair Monte Carlo of pair_simulation.hpp.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "lie/se2.hpp"
#include "lie/types.hpp"
#include "pgo/options.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "study/ch5/pair_simulation.hpp"

namespace keel::study::ch5 {

// [params] shared by the pair studies: dataset and file (resolved by keel.datasets), initial_guess of the
// solve, offsets k of the pairs (i, i + k), figure_offsets, pair_stride (every stride-th i).
struct PairsSetup {
  std::string dataset, file;
  pgo::InitialGuess initial_guess = pgo::InitialGuess::odometry;
  std::vector<int> offsets, figure_offsets;
  int pair_stride = 1;
  std::string offsets_key;  // where the offsets were read (for the error naming an offset out of range)
  static PairsSetup read(const core::ConfigTable& p);
};

// The data set solved (one solver thread: result files must not depend on the thread count), its pairs and
// their joint marginals.
struct SolvedPairs {
  std::vector<SE2> poses;                  // the maximum-likelihood solution
  std::vector<std::pair<int, int>> pairs;  // (i, i + k)
  std::vector<Mat6> covariances;           // the joint marginal of (ξ_i, ξ_j), one per pair
  double final_cost = 0, normalized_chi2 = 0;
  std::size_t edges = 0;
  double read_time_s = 0, solve_time_s = 0, marginals_time_s = 0;
};
[[nodiscard]] SolvedPairs solve_pairs(const PairsSetup& setup, const repro::RunContext& context);

// Table 5.1 and Figs. 5.10–5.14 (a–e): ε of eq. 5.56 with and without the cross-covariance of the two poses.
struct PairCorrelation {
  struct Options {
    PairsSetup pairs;
    PairStudySetup simulation;  // samples
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    SolvedPairs solved;
    std::vector<PairRecord> records;  // one per pair
    double monte_carlo_time_s = 0;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Table 5.2 and Figs. 5.10–5.14 (f–g): the normalized error of the proposed relative pose against SSC
// tail-to-tail. The same run as PairCorrelation.
struct PairsVsSsc {
  using Options = PairCorrelation::Options;
  using Outcome = PairCorrelation::Outcome;
  static Outcome run(const Options& options, const repro::RunContext& context) {
    return PairCorrelation::run(options, context);
  }
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Tables 5.1–5.2 against M: the pair Monte Carlo rerun for each sample size on the same streams, and a power
// law mean(M) = a·M^b fitted in log–log giving the M at which ours would meet the thesis's published means.
struct PairSampleSize {
  struct Options {
    PairsSetup pairs;
    std::vector<double> samples;                                     // the sample sizes M (at least two)
    double match_cov_error_joint = 0, match_norm_cov_error_lie = 0;  // the thesis's means
    static Options read(const core::ConfigTable& p);
  };
  // One row per error: its mean and std over the pairs at each M.
  struct Row {
    std::string key, label;
    double PairRecord::* field = nullptr;
    std::vector<double> mean, std;
  };
  struct Outcome {
    Options options;
    SolvedPairs solved;
    std::vector<Row> rows;  // Table 5.1 joint, independent; Table 5.2 proposed, SSC, sampling floor
    std::vector<double> monte_carlo_time_s;  // one per M
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch5
