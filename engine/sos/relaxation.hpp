// keel::sos — moment relaxations of the planar SLAM problem of problem.hpp (thesis §4.4–4.5), solved as SDPs.
//
// Sparse-BSOS at d = 1, k = 1 (eq. 4.20) is the order-1 moment relaxation of eq. 4.11/4.12 with the circle
// c_i² + s_i² = 1 as an equality (the pair 0 ≤ 1 − c² − s² ≤ 1, 0 ≤ 2 − c² − s² ≤ 1 of eq. 4.11 leaves the
// disc, whose boundary enters only through a concave constraint, and no interior for an interior-point
// solver). Two structures:
//
// * Structure::dense — one block over [1; c_1, s_1, …, c_{n−1}, s_{n−1}] (Shor's relaxation). Translations
// and
//   landmarks enter the cost quadratically and are unconstrained, so they are eliminated exactly first (Schur
//   complement of their block); the relaxation's value is that of the order-1 relaxation that keeps them. In
//   DSDP's form: min ⟨C, X⟩ s.t. X₀₀ = 1, X_cᵢcᵢ + X_sᵢsᵢ = 1, X ⪰ 0 — n constraints. Every feasible rank-one
//   X has trace n, so bᵀy + n·min(0, λ_min(C − Σ yᵢAᵢ)) is a lower bound on the minimum whatever the solver
//   reports.
//
// * Structure::cliques — the Sparse-BSOS structure (§4.4.2, §4.5.2): the measurement graph over poses and
//   landmarks (pose 0 is a constant) is made chordal by a minimum-degree elimination ordering; each maximal
//   clique I_ℓ gets one moment block over the monomials of degree ≤ `order` in its unknowns [c, s, x, y, …].
//   The moments are the SDP's free variables y_β (DSDP's dual), shared between blocks, so overlapping cliques
//   agree on every common moment and the running intersection property of Assumption 4.4.1 holds by
//   construction. Monomials are reduced modulo sᵢ² = 1 − cᵢ² (basis: no sᵢ²), which imposes the circle
//   exactly at every order and keeps the moment matrices free of the null vectors the unreduced basis would
//   carry. Each cost term lies in one clique (its nodes are adjacent). The SOS side (DSDP's primal X,
//   projected onto the PSD cone) gives the lower bound f₀ − ⟨C, X⟩, corrected by the recomputed equality
//   residuals times a bound on the monomials
//   (|c|, |s| ≤ 1; translations: twice the largest first-order moment, at least 1 — a box, not a proof, so
//   this bound holds only up to that box). Every bound here is numerical: λ_min(S) from Eigen's eigensolver
//   (order 1) and the residual sums (order 2) are evaluated in double with no rounding margin; the proof
//   that survives rounding is sos/verify.hpp's (linalg/psd_proof.hpp).
//   Order 2 is the next level of the hierarchy (the escalation when order 1 is not tight).
//
// Tightness: the relaxation is exact when every moment block has rank one; `rank_ratio` = max over blocks of
// λ₂/λ₁. The estimate is read from the first-order moments (dense: the top eigenvector scaled to a leading
// 1).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <string_view>
#include <vector>

#include "sos/problem.hpp"
#include "convex/sdp.hpp"

namespace keel::sos {

enum class Structure { dense, cliques };
[[nodiscard]] std::string_view to_string(Structure v);
[[nodiscard]] Structure structure_from_string(std::string_view s);

struct RelaxationOptions {
  Structure structure = Structure::dense;
  int order = 1;             // moment order (1 = Sparse-BSOS d = 1, k = 1); Structure::dense supports 1 only
  convex::SdpSettings sdp;   // solver and its tolerances
  long max_moments = 20000;  // cliques: refuse (std::length_error) a relaxation with more moments than this
  void validate() const;     // throws std::invalid_argument naming the field and value
};

struct RelaxationResult {
  Structure structure = Structure::dense;
  int order = 1;
  double lower_bound = 0.0;       // lower bound on min f, original units (see above)
  double value = 0.0;             // the moment side's objective, original units
  double bound_correction = 0.0;  // what the residual/eigenvalue correction took off the lower bound
  Eigen::VectorXd z;              // first-order moments (unknowns as problem.hpp lays them out), not rounded
  double rank_ratio = 0.0;        // max over blocks of λ₂/λ₁ of the moment matrix (0: rank one)
  int blocks = 0, largest_block = 0, constraints = 0;
  long moments = 0;  // cliques: number of distinct moments (the SDP's free variables)
  // Recomputed from the returned matrices (sdp.hpp), in the scaled SDP.
  double primal_residual = 0.0, relative_gap = 0.0, x_min_eigenvalue = 0.0, s_min_eigenvalue = 0.0;
  bool solver_claims_optimal = false;  // kept for the record, never used to decide
  std::string solver_status;
  int iterations = 0;
  double solver_time_s = 0.0, time_s = 0.0;
};

// Builds and solves the relaxation. Throws std::invalid_argument for bad options, std::length_error when the
// clique relaxation would have more than max_moments moments, std::runtime_error when the solver fails.
[[nodiscard]] RelaxationResult relax(const PlanarProblem& p, const RelaxationOptions& options = {});

// The cliques of the chordal extension (node lists, nodes as in problem.hpp), maximal and sorted.
[[nodiscard]] std::vector<std::vector<int>> chordal_cliques(const PlanarProblem& p);

// Number of moments of the clique relaxation at `order` (cheap: no SDP is built).
[[nodiscard]] long moment_count(const PlanarProblem& p, int order);

}  // namespace keel::sos
