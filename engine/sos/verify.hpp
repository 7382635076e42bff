// keel::sos — a dual certificate of global optimality for a given planar solution (beyond the thesis).
//
// The thesis certifies by solving the order-1 relaxation (relaxation.hpp), an SDP that only small problems
// afford. The same relaxation can certify a candidate solution of a whole data set without solving it: the
// duality-based verification of Carlone et al. (2016, "Planar pose graph optimization: duality, optimal
// solutions, and verification") and Rosen et al. (SE-Sync, 2019). Here it is applied to the thesis's cost
// f(z) = ‖A z + r‖² (eq. 4.6–4.11, problem.hpp; chordal rotation term, pose 0 the gauge):
//
//   v = [1; z],  Q = [rᵀr, rᵀA; Aᵀr, AᵀA]  (so f(z) = vᵀQv; sparse, (N + 1) × (N + 1)).
//   Constraints: v₀² = 1 (multiplier λ₀) and c_i² + s_i² = 1 (eq. 4.4, multiplier λ_i).
//   First-order conditions Q v = Λ v, Λ = diag(λ₀; λ_i at c_i and s_i; 0 at translations and landmarks):
//   λ₀ = (Qv)₀ and λ_i = c_i (Qv)_{c_i} + s_i (Qv)_{s_i} (least squares on each 2-vector).
//   S = Q − Λ. If S v = 0 and S ⪰ 0, then for every feasible v' (v'₀ = 1, circles satisfied)
//   f(v') = v'ᵀ S v' + λ₀ + Σ λ_i ≥ λ₀ + Σ λ_i = f(z): z is a global minimizer of eq. 4.11/4.12 (and the
//   order-1 relaxation is tight at it, its dual optimum being λ).
//
// Positive semidefiniteness of S + η D, D = diag(1 on v₀ and the rotations, 0 on translations and landmarks),
// is proven by linalg/psd_proof.hpp's test (the one behind pgo::solve_certified): S formed in double-double
// from B = [r | A] with exact products, a Cholesky factorization of W(S + ηD)W − μI with W exact powers of
// two, and μ clearing a rigorous bound on the factor's residual (Higham's, or the residual measured in
// doubled precision; a double-double factor when a double one cannot resolve the shift). Success proves v'ᵀ S
// v' ≥ −η v'ᵀ D v' = −η · poses for every feasible v', hence min f ≥ Σλ − η · poses (a bound that needs no
// bound on the translations; S's translation block AᵀA is positive definite for a connected graph). S has an
// exact zero eigenvalue at v, so η > 0. The decisive shift is the largest the gap tolerance allows,
//     η* = (gap_tolerance · max(f(z), 1) − (f(z) − Σλ)) / poses,
// and the proof is tried at η*/33 and η*/2; the verdict is "numerically certified" iff the proven gap (f(z) −
// (Σλ − η_proven · poses)) / max(f(z), 1), with Σλ's rounding, is at most gap_tolerance. When it is not,
// larger shifts η*·10^k (k ≤ bound_factorizations) measure how far S is from PSD. Stationarity (‖S v‖∞
// relative) is reported, not required: the bound holds for any multipliers, and a point that is not
// stationary cannot reach a small gap.
//
// The candidate must be a stationary point of f itself — keel.pgo minimizes the geodesic χ², whose
// minimizer differs from f's by O(θ⁴) — so solutions from keel.pgo are refined on f first
// (refine_solution below).
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <string>
#include <vector>

#include "core/bound.hpp"
#include "graph/pose_graph.hpp"
#include "pgo/options.hpp"
#include "sos/problem.hpp"

namespace keel::sos {

struct GlobalCertificateOptions {
  double stationarity_tolerance =
      1e-8;                     // `stationary` is reported when ‖S v‖∞ / (max_k Q_kk ‖v‖∞) ≤ this (> 0)
  double gap_tolerance = 1e-6;  // certified iff (f(z) − lower_bound) / max(f(z), 1) ≤ this, in (0, 1)
  int bound_factorizations =
      6;                  // when η*/2 cannot be proven: shifts 10^k · gap·max(f, 1)/poses, k ≤ this (≥ 0)
  void validate() const;  // throws std::invalid_argument naming the field and value
};

struct GlobalCertificate {
  // optimal: the proven relative gap is within gap_tolerance; else unproven.
  core::SearchStatus status = core::SearchStatus::unproven;
  // upper: f(z) = vᵀQv, original units; lower: the proven bound on min f, Σλ − (smallest proven shift) ·
  // poses, rounded down (−inf when no shift was proven).
  core::Bound bound{0.0, 0.0};
  bool stationary = false;      // stationarity ≤ stationarity_tolerance (reported, not required)
  bool psd = false;             // S + η·D ⪰ 0 proven at η*/33 or η*/2
  double multiplier_sum = 0.0;  // λ₀ + Σ λ_i (= f(z) − vᵀSv; equals cost at a stationary point)
  double stationarity = 0.0;    // ‖S v‖∞ / (scale ‖v‖∞)
  double scale = 0.0;           // max_k Q_kk
  double eta = 0.0;  // η*, the decisive shift of the gap tolerance (≤ 0: f − Σλ already exceeds it)
  double lambda_min_bound = 0.0;    // proven: S + |lambda_min_bound| D ⪰ 0 (−smallest proven shift; −inf when
                                    // none was)
  double failed_shift = 0.0;        // the largest shift whose proof failed (0: none): λ_min(S) ≲ −it
  double rounding_margin = 0.0;     // μ of the accepted proof (scaled matrix)
  double residual = 0.0;            // the bound on the factor's residual that μ cleared
  bool extended_precision = false;  // the accepted proof needed a double-double factor
  double min_rotation_multiplier = 0.0;  // min_i λ_i (0 without free poses), for the record
  int factorizations = 0;                // proofs attempted
  long factor_nonzeros = 0;              // nonzeros of the Cholesky factor (CHOLMOD, supernodal)
  double factor_time_s = 0.0, time_s = 0.0;
  [[nodiscard]] bool certified() const { return status == core::SearchStatus::optimal; }
  [[nodiscard]] double cost() const { return bound.upper; }
  // (f(z) − lower) / max(f(z), 1) (core/bound.hpp); +inf without a bound.
  [[nodiscard]] double relative_gap() const { return bound.relative_gap(); }
};

// Certifies z (unknowns as problem.hpp lays them out; rotations must lie on their circles to 1e-9,
// translations in units of length_scale). Throws std::invalid_argument for bad options, a z of the wrong size
// or with non-finite entries, or rotations off the circle.
[[nodiscard]] GlobalCertificate certify_solution(const PlanarProblem& p, const Eigen::VectorXd& z,
                                                 const GlobalCertificateOptions& options = {});

// Newton's method on f over (θ_i, translations, landmarks) from z, with backtracking, until its gradient is
// small enough for a certificate: ‖∇f‖∞ / max_k Q_kk ≤ gradient_tolerance (θ and scaled translations), no
// step lowers the cost, or max_iterations steps were taken. The Hessian is problem.hpp's Gauss–Newton
// matrix plus the multiplier term −2 diag(λ_i) of the circle (Gauss–Newton where that is not positive
// definite): refine() converges only linearly on non-zero-residual data sets (46 steps, 8.6 s on
// Manhattan3500 from keel.pgo's answer), too slowly for whole data sets.
struct RefineOptions {
  int max_iterations = 200;           // Newton (or Gauss–Newton) steps in all (≥ 1)
  double gradient_tolerance = 1e-10;  // stop when ‖∇f‖∞ / max_k Q_kk is at most this (> 0)
  void validate() const;
};
struct RefineReport {
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;
  double gradient = 0.0;  // ‖∇f‖∞ / max_k Q_kk at the end
  double time_s = 0.0;
};
[[nodiscard]] RefineReport refine_solution(const PlanarProblem& p, Eigen::VectorXd& z,
                                           const RefineOptions& options = {});

}  // namespace keel::sos
