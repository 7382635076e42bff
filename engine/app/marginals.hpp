// keel::app — joint marginal covariances of a user's graph at given poses (thesis §5.8.2: the joint
// Lie-algebra covariance Σ_1:n of eq. 5.28 taken from a MAP solution), 2D and 3D alike, shared by
// `keel marginals` and Python's keel.marginals / keel.MarginalCovariance.
//
// Conventions: left perturbation T = exp(ξ^) T̄ (eq. 5.14), ξ = (ρx, ρy, θ) in 2D and (ρ, φ) in 3D; gauge:
// the graph's gauge_pose k fixed (pose 0 unless a g2o FIX line names another; its covariance and
// cross-covariances are zero). A left perturbation is in the world frame, so a common rigid motion adds one ξ
// to every pose: the gauge-k covariance is that of ξ_v − ξ_k, Σ'_ij = Σ_ij − Σ_ik − Σ_kj + Σ_kk of the
// gauge-0 one, and differences ξ_j − ξ_i (relative poses) have the same covariance in every gauge.
#pragma once

#include <utility>
#include <vector>

#include "app/progress.hpp"
#include "cov/marginal_covariance.hpp"
#include "graph/pose_graph.hpp"
#include "pgo/optimize.hpp"

namespace keel::app {

/// The information matrix of the graph linearized at `at` (2D: poses and landmarks), factorized once
/// (CHOLMOD), the graph's gauge pose fixed. Throws std::invalid_argument when `at` does not match the graph,
/// std::runtime_error when the graph is not connected to the gauge pose (the message names the variable where
/// the factorization broke down).
[[nodiscard]] cov::MarginalCovariance factorize(const graph::PoseGraph2D& g, const pgo::Estimate2D& at,
                                                const cov::CovarianceOptions& options = {});
[[nodiscard]] cov::MarginalCovariance factorize(const graph::PoseGraph3D& g, const pgo::Estimate3D& at,
                                                const cov::CovarianceOptions& options = {});

/// What to extract: exactly one of `pairs` (one 2d × 2d joint [Σ_ii Σ_ij; Σ_ji Σ_jj] per pair) and `ids` (the
/// joint of these variables, blocks in the order given, repeats allowed).
struct MarginalsRequest {
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> ids;
  unsigned threads = 1;               // the pair extraction's workers; the result does not depend on it
  cov::CovarianceOptions covariance;  // ordering and extraction method
};

struct Marginals {
  int dimension = 2;               // of the graph: 2 (blocks 3 × 3 per pose) or 3 (6 × 6)
  std::vector<lie::MatX> pairs;    // one per requested pair (6 × 6 or 12 × 12)
  lie::MatX joint;                 // the joint of `ids` (empty when pairs were asked)
  cov::FactorSummary factor;       // what the factorization did (ordering, sizes, times)
  double extraction_time_s = 0.0;  // wall time of the block extraction
};

/// factorize() and the request's query. Throws std::invalid_argument for a request with neither or both of
/// pairs and ids, or a pair naming a variable that is not a pose; std::out_of_range for an unknown id.
/// `progress` hears the two stages (factorization, extraction) as they start.
[[nodiscard]] Marginals marginals(const graph::PoseGraph2D& g, const pgo::Estimate2D& at,
                                  const MarginalsRequest& request, const Progress& progress = {});
[[nodiscard]] Marginals marginals(const graph::PoseGraph3D& g, const pgo::Estimate3D& at,
                                  const MarginalsRequest& request, const Progress& progress = {});

}  // namespace keel::app
