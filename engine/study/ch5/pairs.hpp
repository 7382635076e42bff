// What the chapter-5 studies of pose pairs of a SLAM solution share (§5.9.2, Manhattan3500): PairCorrelation
// (pair_correlation.hpp: Table 5.1, Figs. 5.10–5.14 a–e), PairsVsSsc (pairs_vs_ssc.hpp: Table 5.2, Figs.
// 5.10–5.14 f–g) and PairSampleSize (pair_sample_size.hpp: both tables' means against the Monte-Carlo sample
// size M). All three solve the data set, extract the joint Lie-algebra
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

// Records what every pair study reports about the solve and the pairs.
void record_solved(repro::Results& r, const SolvedPairs& s);

}  // namespace keel::study::ch5
