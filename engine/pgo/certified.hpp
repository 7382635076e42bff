// keel::pgo — certified pose-graph optimization in 2D and 3D: a globally optimal solution of the isotropic
// (chordal) model with a dual certificate whose lower bound survives floating-point rounding.
//
// The problem (Rosen, Carlone, Bandeira, Leonard, "SE-Sync", IJRR 2019, Problem 1; the chordal form of the
// thesis's eq. 2.1 with isotropic noise):
//
//     minimize  F(t, R) = Σ_e κ_e ‖R_j − R_i R̃_e‖²_F + τ_e ‖t_j − t_i − R_i t̃_e‖²      over R_i ∈ SO(d), t_i
//     ∈ Rᵈ,
//
// where edge e = (i, j) measures z_e = (R̃_e, t̃_e) ≈ T_i⁻¹ T_j (graph/pose_graph.hpp). κ_e and τ_e come from
// the edge's information Ω (keel's residual order: translation first) as SE-Sync derives them from a g2o file
// (isotropic_weights() below), so the optimum is SE-Sync's on the same file. F is twice the negative
// log-likelihood of the Langevin–Gaussian model with those concentrations; it is not the anisotropic cost of
// pgo::optimize (which keel solve reports without --certify).
//
// Method (certified.cpp):
//  1. Chordal initialization: the rotations by linear least squares over R^{d×d} with R_0 = I, projected onto
//     SO(d), then the translations by linear least squares.
//  2. Local solve on the Burer–Monteiro lift: X = [t_1 … t_n | Y_1 … Y_n] ∈ R^{r×(n+dn)} with Y_i ∈ St(d, r)
//  and
//     F(X) = tr(X M Xᵀ) (M the sparse connection Laplacian of the graph, see certified.cpp). Each Y_i is the
//     first d columns of an orthogonal Q_i ∈ O(r), moved as Q_i exp(B_i) with B_i in the part of so(r) that
//     moves those columns; the translations move freely; pose 0 is the gauge. Newton steps (Gauss–Newton
//     matrix plus the curvature of the retraction, i.e. the Riemannian Hessian) with Levenberg–Marquardt
//     damping, factorized by CHOLMOD — or, when an earlier factor is at hand, solved inexactly by conjugate
//     gradients preconditioned with that factor (a few triangular solves instead of a factorization). Where
//     the damped Hessian is not positive definite, trust-region steps (Steihaug–Toint CG on the exact
//     Hessian, preconditioned by the damped Gauss–Newton factor). Above rank d, a Riemannian trust region
//     whose Hessian is applied without forming it, preconditioned by the factor of the data matrix (SE-Sync's
//     local solver); each trial point's translations are set to their optimum for its rotations before F is
//     evaluated, so the trust region runs on F with the translations minimized out, as SE-Sync's reduced
//     problem does.
//  3. Certificate: Λ_i = sym(Y_iᵀ (X M)_{Y_i}) from the first-order conditions, S = M − diag(0, Λ). For every
//     feasible point (and every point of the semidefinite relaxation) F ≥ tr(Λ) − η·d·n when S + η·D ⪰ 0, D
//     the identity on the rotation coordinates and zero on the translations (translation 0 removed: the
//     gauge). S is formed in double-double arithmetic (error-free products), and S + η·D ⪰ 0 is proven by a
//     Cholesky factorization of A = W(S + η·D)W − μI, with W a power-of-two diagonal scaling (exact): A − L̂L̂ᵀ
//     = R with L̂L̂ᵀ ⪰ 0, so μ must exceed ‖R‖₂, bounded first by Higham's Thm 10.3 (|R| ≤ γ_{k+1}|L̂||L̂ᵀ|,
//     cheap) and, when that is not enough, by R itself, accumulated in doubled precision
//     (sparse_cholesky.hpp). η* is the largest shift the gap tolerance allows:
//         η* = (gap_tolerance · max(F, 1) − (F − tr Λ)) / (d · n);
//     the proof is tried at η*/33, then at η*/2. When both fail, the two are tried again with a
//     double-double factor (residual of order u²): on data sets whose positions span hundreds of metres or
//     more (kitti, ais2klinik) the near-null vectors of S carry the positions, and the shift that 1e-6 asks
//     for lies below what a double factor resolves. When those fail too, the shift is raised tenfold at a
//     time (up to 10⁵·gap_tolerance·max(F, 1)/(dn), double factors) and the tightest bound that can be proven
//     is reported, not certified.
//  4. When the certificate fails at rank r: the Riemannian staircase. A direction of negative curvature of S
//     (inverse iteration on S + σD, σ found by factorizations) lifts X to rank r + 1 with a decrease, and
//     step 2 resumes, up to CertifiedOptions::max_rank.
//  5. Rounding to SO(d)ⁿ (the top-d left singular subspace of Y, the determinant sign of the majority, a
//     projection per block, then optimal translations), a local solve at rank d from there, and the
//     certificate again at the returned point.
//
// "Numerically certified": the lower bound is rigorous for the data as stored (κ, τ, R̃, t̃ in double), with
// every rounding error of the test bounded as above and its last operations rounded toward −∞
// (core::round_down); the upper bound is F at the returned estimate as stored (rotations orthonormal to
// rounding), bounded upward in double-double. The reported Certificate holds only what the proof behind the
// lower bound established (the best proven over the staircase's points and the returned one); failed attempts
// are reported as failed.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/bound.hpp"
#include "graph/pose_graph.hpp"
#include "pgo/optimize.hpp"

namespace keel::pgo {

// κ (rotation) and τ (translation) of one edge, from its information Ω over keel's residual (translation
// first, then the rotation angle in 2D or rotation vector φ in 3D):
//   2D:  τ = 2 / tr(Ω_tt⁻¹),  κ = Ω_θθ;
//   3D:  τ = 3 / tr(Ω_tt⁻¹),  κ = 3 / (2 tr(Ω_qq⁻¹)) with Ω_qq = 4 Ω_φφ, the block of the g2o file over the
//        quaternion's vector part (q_vec ≈ φ/2; graph/g2o.hpp converts Ω_qq to Ω_φφ = Ω_qq / 4 on reading).
// Only the diagonal blocks are used (cross terms are ignored), so blocks of an indefinite Ω are accepted as
// long as κ and τ come out positive and finite. Throws std::invalid_argument otherwise, naming the edge.
struct IsotropicWeights {
  double kappa = 0.0;
  double tau = 0.0;
};
[[nodiscard]] IsotropicWeights isotropic_weights(const graph::Edge2& e);
[[nodiscard]] IsotropicWeights isotropic_weights(const graph::Edge3& e);

// The preconditioner of the trust-region steps above rank d (certified_local.cpp).
//   joint:     the data matrix's inverse on rotations and translations together, projected (Π A⁻¹ Π);
//   reduced:   translations eliminated exactly (SE-Sync's on the rotations, whose problem has none): more
//   work
//              per step, fewer steps where the translations weigh much in the cost;
//   automatic: reduced where Σ_e τ_e ‖t̃_e‖² ≥ F at the start of the rank's solve (the joint form's spread
//              of eigenvalues grows with that ratio), joint elsewhere.
enum class TrustRegionPreconditioner { automatic, joint, reduced };
[[nodiscard]] std::string_view to_string(TrustRegionPreconditioner p);  // "auto", "joint", "reduced"
// Inverse of to_string; throws std::invalid_argument naming the valid values.
[[nodiscard]] TrustRegionPreconditioner trust_region_preconditioner_from_string(std::string_view s);

struct CertifiedOptions {
  double gap_tolerance = 1e-6;  // certified when (F − lower) / max(1, F) ≤ this (> 0)
  int max_rank = 10;            // the staircase stops at this rank (≥ d, ≤ 12)
  int max_iterations = 300;     // Newton iterations per rank (≥ 1)
  // Stop a rank's local solve when ‖Riemannian gradient‖·‖X‖ (a bound on |F − tr Λ|) is at most this ×
  // gap_tolerance × max(F, 1), in (0, 1].
  double stationarity_tolerance = 1e-2;
  bool chordal_initialization = true;  // false: start from the poses as read (or chained odometry)
  // Newton steps by conjugate gradients preconditioned with the factor of an earlier step when that converges
  // (false: a numeric factorization at every step).
  bool inexact_newton = true;
  // Above rank d: a Riemannian trust region whose Steihaug–Toint steps apply the exact Hessian without
  // forming it, preconditioned by the factor of the data matrix (SE-Sync's local solver). false: the damped
  // Newton steps of rank d, with factorized blocks that grow as r² (kept to compare the two in tests).
  bool trust_region_above_d = true;
  TrustRegionPreconditioner preconditioner = TrustRegionPreconditioner::automatic;
  // Above rank d, each rank's local solve first stops once ‖grad‖·‖X‖ ≤ this × max(F, 1) (SE-Sync's staircase
  // stops every rank loosely). At that point the staircase climbs when S has curvature below
  // −(η* + ‖grad‖); otherwise, when the rank-d answer rounded from it and polished costs more than F there by
  // 10 × gap_tolerance (F at any point of the lift bounds the relaxation's optimum, and so every provable
  // lower bound, from above), no solve of that rank could certify the answer and the staircase stops with the
  // bound proven so far; only a point that could certify is solved on to stationarity_tolerance. It trades
  // the tightness of the bound of an answer that cannot be certified (the loose point's multipliers prove
  // less) for time. 0: every rank solved to stationarity_tolerance. In [0, 1).
  double staircase_stationarity = 1e-3;
  // The loose solve of a rank above d also stops at an accepted trust-region step that lowers F by less than
  // this × |F|, ended inside the trust region (its truncated CG converged) and agreed with the model (ρ ≥
  // 0.25): near a rank-deficient minimizer the gradient falls slowly while F has all but stopped moving
  // (SE-Sync stops its levels on the relative decrease alone, at 1e-6). It trades time for the answer and its
  // bound where the relaxation is not exact: at 1e-7, 17 % less time on ext_certified_noise's graphs, but on
  // fresh graphs one answer in 60 rounded from a lower rank and cost 2.8 % more, so it is off by default
  // (docs/measurements/2026-12-07-certified-relative-decrease.md). 0: off. In [0, 1); used only with
  // staircase_stationarity > 0.
  double staircase_relative_decrease = 0.0;
  // Seconds of wall time (0: no limit). At the limit the local solve in progress stops; the point it reached
  // is tested (so the bound holds whatever the point), rounded and tested again, and the result says
  // time_limit. Those two tests run after the limit, so a run can exceed it by their time.
  double time_limit_s = 0.0;
  void validate() const;  // throws std::invalid_argument naming the field
};

// A certificate: the lower bound and the proof behind it. Every field that describes a proof (shift,
// rounding_margin, residual, worst_case_residual, formation_error, extended_precision) belongs to the proof
// of S + η·D ⪰ 0 that produced `bound.lower`, and is zero (false) when no proof succeeded (`proven` false,
// bound.lower = −∞). Attempts that failed are reported only as failed: `failed_shift` and `attempts`.
struct Certificate {
  bool certified = false;     // proven, and the relative gap (rounded up) is within the gap tolerance
  bool proven = false;        // a proof of S + η·D ⪰ 0 stands behind bound.lower
  core::Bound bound;          // lower: proven (rounded down; −∞ when nothing was proven); upper: F at the
                              // returned point, rounded up
  double trace_lambda = 0.0;  // tr(Λ) of the multipliers that the proof is about (of the tested point when
                              // nothing was proven)
  int rank = 0;               // rank of the point whose multipliers Λ were tested (> d: a staircase point)
  double shift = 0.0;  // η proven: S + η·D ⪰ 0 (D the identity on the rotation coordinates); 0 when not
  double tolerance_shift =
      0.0;  // η* = (gap_tolerance · max(F, 1) − (F − tr Λ)) / (d n), the largest the gap allows
  double rounding_margin =
      0.0;  // μ (in the scaled matrix) that the proof's factorization cleared; 0 when not
  // The proof's error terms, in the scaled matrix: the bound on ‖W(S + ηD)W − μI − L̂L̂ᵀ‖₂ that cleared μ
  // (Higham's when it sufficed, else the measured residual's), Higham's worst case for the same factor, and
  // the bound on the rounding of forming W(S + ηD)W in double-double. Zero when nothing was proven.
  double residual = 0.0;
  double worst_case_residual = 0.0;
  double formation_error = 0.0;
  bool extended_precision = false;  // the proof needed the double-double factor (residual of order u²)
  double failed_shift = 0.0;        // the largest η whose proof FAILED at the tested point (0: none failed)
  int attempts = 0;                 // proofs attempted at the tested point (failed ones included)
  int max_row_count = 0;            // largest row count of the symbolic factor (supernodal, padded)
  int size = 0;                     // order of S (translation 0 removed)
  double time_s = 0.0;
  std::string message;  // the proof when proven; otherwise "no lower bound: " and the failure
  std::string failure;  // what failed at the tested point (empty when the tolerance's shifts were proven)
};

// One rank of the staircase.
struct RankRecord {
  int rank = 0;
  int iterations = 0;                // Newton iterations (accepted and rejected)
  int factorizations = 0;            // numeric factorizations of the Newton system among them
  int cg_steps = 0;                  // steps solved by preconditioned CG on an earlier factor instead
  int tcg_iterations = 0;            // Steihaug–Toint CG iterations of the trust-region steps
  double cost = 0.0;                 // F at the end of the rank's local solve
  double gradient_norm = 0.0;        // ‖Riemannian gradient‖₂ there
  bool certified = false;            // whether the certificate held at that point
  double lambda_min_estimate = 0.0;  // when not certified: the Rayleigh quotient of the escape direction
  bool loose =
      false;  // the rank ended at CertifiedOptions::staircase_stationarity (no tighter solve followed)
  double time_s = 0.0;
};

enum class CertifiedTermination {
  certified,      // the returned estimate carries a certificate within the gap tolerance
  rank_limit,     // the staircase reached max_rank without a certificate
  not_certified,  // the rank-d point after rounding could not be certified (the bound is still valid)
  time_limit,     // stopped at CertifiedOptions::time_limit_s (the bound of the points reached is valid)
};
std::string_view to_string(CertifiedTermination t);

struct CertifiedSummary {
  CertifiedTermination termination = CertifiedTermination::not_certified;
  core::SearchStatus status = core::SearchStatus::unproven;  // optimal exactly when certified
  std::string problem;                                       // the problem solved, in words
  std::string message;
  int poses = 0;
  int edges = 0;
  int dimension = 2;
  double initial_cost = 0.0;  // F at the initial estimate
  double final_cost = 0.0;    // F at the returned estimate (rounded to nearest)
  int final_rank = 0;         // rank of the last local solve before rounding
  std::vector<RankRecord> staircase;
  // The proof behind the reported lower bound: the best proven over the points tested (the staircase's and
  // the returned one, `certificate.rank` says which), with the upper end F at the returned point rounded up.
  // When nothing was proven, the returned point's failed test (proven false, lower −∞).
  Certificate certificate;
  // True when `certificate` comes from a point of the staircase (rank > d) rather than the returned estimate;
  // `returned_point` then holds the returned estimate's own test (usually failed, and reported as failed).
  bool bound_from_staircase = false;
  Certificate returned_point;
  std::string ordering;  // CHOLMOD's fill-reducing ordering of the Newton systems
  int iterations = 0;    // Newton iterations over all ranks (and the final rank-d solve)
  int factorizations =
      0;             // numeric factorizations of the Newton systems (certificate and escape not counted)
  int cg_steps = 0;  // Newton steps solved by preconditioned CG on an earlier factor
  int tcg_iterations = 0;  // Steihaug–Toint CG iterations (trust-region steps: indefinite Hessian, ranks > d)
  double initialization_time_s = 0.0;
  double local_time_s = 0.0;
  double certificate_time_s = 0.0;
  double rounding_time_s = 0.0;
  double total_time_s = 0.0;
};

struct CertifiedResult2D {
  CertifiedSummary summary;
  std::vector<lie::SE2> poses;
};
struct CertifiedResult3D {
  CertifiedSummary summary;
  std::vector<lie::SE3> poses;
};

// F (the isotropic cost above) at given poses.
[[nodiscard]] double isotropic_cost(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& poses);
[[nodiscard]] double isotropic_cost(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& poses);

// The certified solve, on one BLAS thread (core::SingleThreadedBlas: a process-wide setting, restored on
// return). The graph must be connected (throws std::invalid_argument naming a pose that no path reaches) and
// free of landmarks (2D). Poses that no edge touches are refused like that too. The returned poses have pose
// 0 at the identity; a graph whose gauge_pose is k ≠ 0 (g2o's FIX k) gets them moved rigidly so that pose k
// is graph.poses[k] exactly (the cost and the certificate do not depend on the gauge).
[[nodiscard]] CertifiedResult2D solve_certified(const graph::PoseGraph2D& graph,
                                                const CertifiedOptions& options = {});
[[nodiscard]] CertifiedResult3D solve_certified(const graph::PoseGraph3D& graph,
                                                const CertifiedOptions& options = {});

// The certified solve as the faces report it: the graph with the certified estimate as its poses, the
// summary, and at that estimate the anisotropic maximum-likelihood cost of eq. 2.1 that optimize() minimizes
// (evaluate(); NaN when some information is not positive definite, graph.indefinite_information > 0). The two
// problems differ; both costs are reported.
template <class Graph>
struct CertifiedSolution {
  Graph graph;
  CertifiedSummary summary;
  double anisotropic_cost = 0.0;
  double solve_time_s = 0.0;  // wall time of solve_certified
};
[[nodiscard]] CertifiedSolution<graph::PoseGraph2D> certified_solution(const graph::PoseGraph2D& graph,
                                                                       const CertifiedOptions& options = {});
[[nodiscard]] CertifiedSolution<graph::PoseGraph3D> certified_solution(const graph::PoseGraph3D& graph,
                                                                       const CertifiedOptions& options = {});

// The certificate at given poses (no solve): what a user runs on a solution found elsewhere.
[[nodiscard]] Certificate certify(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& poses,
                                  double gap_tolerance = 1e-6);
[[nodiscard]] Certificate certify(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& poses,
                                  double gap_tolerance = 1e-6);

}  // namespace keel::pgo
