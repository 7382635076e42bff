// Relative-pose uncertainty of pose pairs extracted from a SLAM solution (thesis §5.9.2, Tables 5.1–5.2,
// Figs. 5.10–5.14): for each pair (i, j) with means T̄_i, T̄_j and the joint Lie-algebra marginal covariance of
// (ξ_i, ξ_j), the relative pose T_ij = T_i⁻¹ T_j is predicted by eq. 5.51 with and without the
// cross-covariance and by SSC tail-to-tail (§5.3.4), and compared with Monte Carlo (eqs. 5.57–5.59).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "lie/se2.hpp"
#include "lie/types.hpp"

namespace keel::core {
class Progress;
}

namespace keel::lie {

struct PairStudySetup {
  std::size_t samples = 10000;  // M, Monte-Carlo samples per pair
  std::uint64_t seed = 0;       // pair k draws from Rng::stream(seed, k)
  unsigned threads = 0;
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

// The SSC (x, y, θ) covariance of poses perturbed on the left, to first order: Σ_x = J Σ_ξ Jᵀ with
// J = ∂ssc(exp(ξ^) T̄)/∂ξ at 0 = [[1, 0, −y], [0, 1, x], [0, 0, 1]] per pose. This is the covariance a solver
// that linearizes in (x, y, θ) coordinates (iSAM's Pose2d) reports at the same solution.
Mat3 ssc_jacobian_of_left_perturbation(const SE2& T);

// Runs the study for every pair; `joint_covs[k]` is the 6×6 covariance of (ξ_i, ξ_j) for pairs[k].
// Deterministic for a seed whatever the thread count; `progress` advances once per pair.
[[nodiscard]] std::vector<PairRecord> run_pair_study_2d(const std::vector<SE2>& poses,
                                                        const std::vector<std::pair<int, int>>& pairs,
                                                        const std::vector<Mat6>& joint_covs,
                                                        const PairStudySetup& setup,
                                                        keel::core::Progress* progress = nullptr);

// Mean and (population) standard deviation of one field over the records, optionally only pairs with j − i =
// offset.
struct PairStatistics {
  std::size_t count = 0;
  double mean = 0, std = 0;
};
[[nodiscard]] PairStatistics pair_statistics(const std::vector<PairRecord>& records,
                                             double PairRecord::* field, int offset = -1);

}  // namespace keel::lie
