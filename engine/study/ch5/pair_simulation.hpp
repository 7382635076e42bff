// Relative-pose uncertainty of pose pairs extracted from a SLAM solution (thesis §5.9.2, Tables 5.1–5.2,
// Figs. 5.10–5.14), the Monte Carlo behind the studies of pairs.hpp: for each pair (i, j) with means T̄_i, T̄_j
// and the joint Lie-algebra marginal covariance of (ξ_i, ξ_j), the relative pose T_ij = T_i⁻¹ T_j is
// predicted by eq. 5.51 with and without the cross-covariance and by SSC tail-to-tail (§5.3.4), and compared
// with Monte Carlo (eqs. 5.57–5.59).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "lie/se2.hpp"
#include "lie/types.hpp"
#include "repro/run.hpp"

namespace keel::study::ch5 {

using lie::Mat6;
using lie::SE2;

struct PairStudySetup {
  std::size_t samples = 10000;  // M, Monte-Carlo samples per pair
  void validate() const;
};

struct PairRecord {
  int i = 0, j = 0;
  // Correlation coefficients between ξ_i and ξ_j per dimension (x, y, θ) of the joint marginal
  // (Figs. 5.10–5.14 a–c).
  double corr_x = 0, corr_y = 0, corr_theta = 0;
  // ε of eq. 5.56 against the Monte-Carlo covariance of eq. 5.57 (Table 5.1).
  double error_joint = 0, error_independent = 0;
  // Normalized ε (§5.9.2): both covariances divided by the Frobenius norm of their own Monte-Carlo reference
  // (Table 5.2). The SSC reference is the sample covariance of the same samples' (x, y, θ) parameters.
  double normalized_error_lie = 0, normalized_error_ssc = 0;
  // Diagnostic: SSC against a reference taken from the raw (x, y, θ) parameters with θ in (−π, π] and no
  // wrapping around the mean — what a naive sample covariance of Euler parameters gives when θ crosses ±π.
  double normalized_error_ssc_raw_angles = 0;
  // The normalized error a perfect prediction would show, from sampling alone: for M Gaussian samples the
  // sample covariance about zero S satisfies E‖S − Σ‖²_F = (tr(Σ)² + tr(Σ²)) / M, so the floor is
  // sqrt((tr(Σ)² + tr(Σ²)) / M) / ‖Σ‖_F, evaluated at the joint prediction.
  double normalized_mc_floor = 0;
};

// Runs the study for every pair; `joint_covs[k]` is the 6×6 covariance of (ξ_i, ξ_j) for pairs[k], which
// draws from context.streams().stream(k) (one sharded trial loop). Deterministic whatever the thread count;
// `progress` (may be null) advances once per pair.
[[nodiscard]] std::vector<PairRecord> simulate_pairs_2d(const std::vector<SE2>& poses,
                                                        const std::vector<std::pair<int, int>>& pairs,
                                                        const std::vector<Mat6>& joint_covs,
                                                        const PairStudySetup& setup,
                                                        const repro::RunContext& context,
                                                        core::Progress* progress = nullptr);

// The same study at several sample sizes M in one pass over each pair's stream: `sizes` ascending, each ≥ 2;
// out[s][k] is pairs[k]'s record at M = sizes[s], bit for bit simulate_pairs_2d's with samples = sizes[s]
// (a run at M draws the first M samples of the stream). The work is that of the largest M alone.
[[nodiscard]] std::vector<std::vector<PairRecord>> simulate_pairs_2d_sizes(
    const std::vector<SE2>& poses, const std::vector<std::pair<int, int>>& pairs,
    const std::vector<Mat6>& joint_covs, const std::vector<std::size_t>& sizes,
    const repro::RunContext& context, core::Progress* progress = nullptr);

// Mean and (population) standard deviation of one field over the records, optionally only pairs with j − i =
// offset.
struct PairStatistics {
  std::size_t count = 0;
  double mean = 0, std = 0;
};
[[nodiscard]] PairStatistics pair_statistics(const std::vector<PairRecord>& records,
                                             double PairRecord::* field, int offset = -1);

}  // namespace keel::study::ch5
