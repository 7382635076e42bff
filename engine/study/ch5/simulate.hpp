// The Monte-Carlo machinery of the chapter-5 studies (§5.5.2, §5.7.2, §5.9.1): correlated odometry composed
// end to end and scored against every prediction, two correlated poses and their relative pose, and the
// planar shadows of predicted regions that the figures draw. The studies (composition.hpp and its siblings)
// run these on their RunContext's streams: trajectory (sample) i draws from context.streams().stream(i).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "lie/se3.hpp"
#include "lie/types.hpp"
#include "repro/run.hpp"

namespace keel::study::ch5 {

using lie::Mat6;
using lie::SE3;

// ---------------------------------------------------------------------------------------------------------------
// Compounding correlated odometry (§5.5.2, eqs. 5.40–5.42; §5.9.1).
//
// Each of the N steps is T_k = exp(ξ_k^) T̄ with T̄ = [I | (1,0,0)] (eq. 5.42) and marginal covariance
// Σ = diag(0.001σt, 1e-5σt, 1e-5, 1e-5, 1e-5, 0.003σr) (eq. 5.41, ξ = [ρ; φ]). The thesis only says
// consecutive perturbations are correlated with coefficient ρ; we use a stationary AR(1) sequence
//     ξ_1 = L w_1,   ξ_k = ρ ξ_{k-1} + sqrt(1-ρ²) L w_k,   w_k ~ N(0, I),  L Lᵀ = Σ,
// so every ξ_k ~ N(0, Σ) and Cov(ξ_j, ξ_k) = ρ^|j-k| Σ. The trajectory end pose is T_1 T_2 … T_N.
struct CompositionSetup {
  int steps = 10;        // N
  double sigma_t = 5.0;  // translation noise scale σt
  double sigma_r = 5.0;  // rotation noise scale σr
  double rho = 0.4;      // correlation of consecutive perturbations
  std::size_t trajectories = 10000;
  std::vector<double> levels = {0.95};  // probability levels p for the "inside" fractions
  bool keep_samples = false;            // keep the sampled end poses (for figures)
  // Beyond the thesis: the fourth-order joint chain (fourth_order_joint.hpp, exact to fourth order for the
  // whole chain) is evaluated when steps <= this limit; its cost grows like N⁴ (0.05 s at N = 10, 46 s
  // and 2.5 GB at 50).
  int joint_fourth_order_max_steps = 25;
  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

// One predicted distribution of the end pose and how many samples fell inside its p-ellipsoids.
struct CompositionPrediction {
  SE3 mean;  // predicted mean (for SSC: the Euler-parameter mean converted to SE(3))
  Mat6 cov;  // Lie-algebra covariance, or for SSC the Euler-parameter covariance (eq. 5.15 order)
  std::vector<double> inside;  // fraction of samples inside the p-ellipsoid, one per setup level
};

struct CompositionOutcome {
  CompositionPrediction ssc;  // SSC head-to-tail (§5.3.2) on UT-converted Euler parameters, with the
                              // cross-covariances of the stochastic map (eq. 5.16)
  CompositionPrediction ssc_independent;  // the same, steps treated as independent (block-diagonal input)
  CompositionPrediction lie_independent;  // Barfoot & Furgale first order (eq. 5.39 without the cross terms)
  CompositionPrediction lie_joint;        // proposed, eq. 5.39 with cross-covariances carried along the chain
  CompositionPrediction lie_fourth_order;        // Barfoot & Furgale (2014) fourth order, independent steps
  bool has_joint_fourth_order = false;           // steps <= joint_fourth_order_max_steps
  CompositionPrediction lie_joint_fourth_order;  // fourth order with correlation (Isserlis), exact chain
  std::vector<SE3> samples;                      // end poses, when keep_samples
};

// Samples `trajectories` chains (trajectory i from context.streams().stream(i), on context's threads, one
// sharded trial loop) and scores every prediction. Deterministic whatever the thread count. `progress` (may
// be null) advances once per trajectory.
[[nodiscard]] CompositionOutcome simulate_composition(const CompositionSetup& setup,
                                                      const repro::RunContext& context,
                                                      core::Progress* progress = nullptr);

// The per-step covariance of eq. 5.41 (variances on the diagonal).
[[nodiscard]] Mat6 composition_step_covariance(double sigma_t, double sigma_r);

// Fig. 5.7 (§5.8.1, eqs. 5.60–5.62): a composition study's SSC head-to-tail prediction converted to the Lie
// algebra by the unscented transform (joint_poses_from_ssc, Julier & Uhlmann 1997 weights with κ = 0), scored
// against the study's sampled end poses (CompositionSetup::keep_samples). "True" is the samples' own spread
// about the converted mean f(x̂), E[ξ ξᵀ] with ξ_m = log(T_m f(x̂)⁻¹).
struct SscConversion {
  CompositionPrediction unscented;  // mean f(x̂) (eq. 5.61), covariance of eq. 5.62, inside fractions
  Mat6 cov_samples;                 // the samples' spread about f(x̂)
  // Ratios of p-ellipsoid volumes, sqrt(det A / det B): above 1, A's region is the larger.
  double volume_vs_samples = 0;  // the converted region against the samples' spread (> 1: over-approximates)
  double volume_vs_joint = 0;    // the converted region against the proposed joint prediction's
  double joint_volume_vs_samples = 0;  // the joint prediction against the samples' spread about its own mean
};
[[nodiscard]] SscConversion convert_ssc_prediction(const CompositionOutcome& outcome,
                                                   const std::vector<double>& levels);

// ---------------------------------------------------------------------------------------------------------------
// Relative pose of two correlated poses (§5.7.2, eqs. 5.52–5.59).
struct RelativePoseSetup {
  SE3 T_g1, T_g2;               // means (eqs. 5.52–5.53)
  Mat6 cov_g1, cov_g2;          // marginal covariances (eq. 5.54)
  Mat6 cov_g1_g2;               // cross-covariance (eq. 5.55)
  std::size_t samples = 10000;  // M
  bool keep_samples = false;
  void validate() const;
};

struct RelativePoseOutcome {
  SE3 mean;                                       // T̄_12 = T̄_g1⁻¹ T̄_g2 (eq. 5.48)
  Mat6 cov_mc;                                    // eq. 5.57 from ξ_m = log(T_m T̄_12⁻¹) (eqs. 5.58–5.59)
  Mat6 cov_joint;                                 // eq. 5.51, all four terms
  Mat6 cov_independent;                           // eq. 5.51, first two terms
  double error_joint = 0, error_independent = 0;  // ε of eq. 5.56 against cov_mc
  std::vector<SE3> samples;                       // T_m, when keep_samples
};

// The setup of eqs. 5.52–5.55 from plain numbers: both means rotated by `yaw` (radians) about z with
// translations t_g1, t_g2; Σ_g1 = Σ_g2 = α·diag(marginal_diag); Σ_g1,g2 = α·diag(cross_diag). Throws if the
// joint covariance is not positive semi-definite.
[[nodiscard]] RelativePoseSetup relative_pose_setup(double yaw, const std::vector<double>& t_g1,
                                                    const std::vector<double>& t_g2,
                                                    const std::vector<double>& marginal_diag,
                                                    const std::vector<double>& cross_diag, double alpha);

// Sample i from context.streams().stream(i), one sharded trial loop.
[[nodiscard]] RelativePoseOutcome simulate_relative_pose(const RelativePoseSetup& setup,
                                                         const repro::RunContext& context,
                                                         core::Progress* progress = nullptr);

// Points on the boundary of the p-probability region of a planar-projected Lie-algebra distribution: the (ρx,
// ρy, φz) marginal ellipsoid at the χ²₃(p) radius, pushed through exp(ξ^) T̄ and projected to (x, y).
// Deterministic (Fibonacci sphere with `count` points). Used for the "flattened ellipsoid" of Fig. 5.4.
void planar_lie_region(const SE3& mean, const Mat6& cov, double p, int count, std::vector<double>& x,
                       std::vector<double>& y);
void planar_lie_region(const CompositionPrediction& prediction, double p, int count, std::vector<double>& x,
                       std::vector<double>& y);

// The (x, y) ellipse of the SSC prediction: the shadow on the plane of its (x, y, yaw) p-ellipsoid, i.e. the
// (x, y) marginal at the χ²₃(p) radius — the same convention as planar_lie_region, so the two are comparable.
void planar_ssc_ellipse(const CompositionPrediction& ssc, double p, int count, std::vector<double>& x,
                        std::vector<double>& y);

// Translations (x, y) of poses, for scatter plots.
void planar_positions(const std::vector<SE3>& poses, std::vector<double>& x, std::vector<double>& y);

}  // namespace keel::study::ch5
