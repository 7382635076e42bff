// Selecting a set of measurements from the matrix Q of pairwise consistency measures (thesis §2.5, §2.7).
//
// Every method here starts from the same n×n matrix Q (q_uv = squared Mahalanobis distance of the loop error
// of candidates u and v, eq. 2.4; building Q is not part of the selection and is not timed):
//
//   PCM     (eq. 2.5, §2.5) the maximum clique of the consistency graph: edge {u, v} iff q_uv <= γ and q_vu
//   <= γ.
//           Every pair of the returned set is consistent (eq. 2.3).
//   RANSAC  (§2.7) exhaustive single-sample consensus: for every candidate u the support is
//           {u} ∪ {v : q_uv <= γ}; the largest support wins (ties: smallest u). Members of the support are
//           each consistent with u, but not necessarily with each other.
//   SCGP    (Olson, Walter, Teller, Leonard, "Single-cluster spectral graph partitioning for robotics
//   applications",
//           RSS 2005; thesis §2.7 computes the eigenvectors with an off-the-shelf solver instead of the power
//           method, as done here with Spectra's Lanczos solver for the two leading eigenpairs, Eigen's
//           SelfAdjointEigenSolver where it does not converge). See ScgpOptions for the exact definition
//           used.
#pragma once

#include <tuple>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pcm/clique.hpp"
#include "pcm/consistency.hpp"
#include "pcm/densest.hpp"
#include "core/fields.hpp"

namespace keel::pcm {

struct Selection {
  std::vector<int> selected;  // sorted candidate indices
  double time_s = 0.0;        // wall time of the selection itself (excludes building Q)
  // PCM: the maximum-clique search behind the selection — its bound (exact: branch and bound; heuristic: the
  // degeneracy bound max core + 1), status and ties (CliqueOptions::report_ties); empty for RANSAC and SCGP.
  std::optional<CliqueResult> search;
  // Densest subgraph: the raw rounding before its repair to a clique, and its inconsistent pairs (0 for the
  // other selectors).
  int raw_size = 0;
  long long violations = 0;
  bool proven_optimal() const { return search && search->proven_optimal(); }
  // The clique search's gap (CliqueResult::gap; 0 without a search).
  int gap() const { return search ? search->gap() : 0; }
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(selected, time_s, search, raw_size, violations)
};

// Throws std::invalid_argument with a message naming the problem when Q is not usable: n <= 0, q.size() !=
// n·n, a NaN entry, or a negative off-diagonal entry (a squared distance is >= 0). +inf is allowed (never
// consistent). The diagonal is otherwise ignored (a measurement is always consistent with itself).
void validate_consistency_matrix(const ConsistencyMatrix& Q, const char* who);

// Throws std::invalid_argument "<who>: the consistency threshold gamma must be > 0 and finite (got γ)"
// otherwise.
void validate_gamma(double gamma, const char* who);

// PCM (eq. 2.5, §2.5): maximum clique of ConsistencyGraph::from_threshold(Q, γ). γ > 0 and finite, else
// std::invalid_argument. time_s includes thresholding Q into the graph.
[[nodiscard]] Selection select_pcm(const ConsistencyMatrix& Q, double gamma, CliqueAlgorithm algorithm,
                                   const CliqueOptions& options = {});

// The densest-subgraph selector (pcm/densest.hpp, CLIPPER's relaxation) on
// ConsistencyGraph::from_threshold(Q, γ): the affinity of a consistent pair is exp(−max(q_uv, q_vu) /
// affinity_scale), or 1 when affinity_scale is 0 (binary: the relaxation of the maximum clique). `selected`
// is the rounding repaired to a maximal clique; raw_size and violations describe the rounding before the
// repair. γ > 0 and finite.
struct DensestSelectOptions {
  double affinity_scale = 0.0;  // 0 (binary) or > 0 and finite
  DensestOptions solver;
  void validate() const;  // throws std::invalid_argument naming the field
};
[[nodiscard]] Selection select_densest(const ConsistencyMatrix& Q, double gamma,
                                       const DensestSelectOptions& options = {});

// RANSAC as in thesis §2.7 (see the header comment). γ > 0 and finite.
[[nodiscard]] Selection select_ransac(const ConsistencyMatrix& Q, double gamma);

// How SCGP turns the continuous dominant eigenvector v₁ into a discrete indicator vector. Both consider only
// the n "threshold" sets S_k = the k candidates with the largest entries of v₁ (k = 1..n; ties in v₁ broken
// by lower index).
enum class ScgpDiscretization {
  dot_product,  // Olson et al. (2005): the S_k whose normalised indicator w_k/‖w_k‖ has the largest dot
                // product with v₁ (‖v₁‖ = 1), i.e. maximise (Σ_{i∈S_k} v₁ᵢ)/√k — the discrete vector closest
                // in angle to v₁
  rayleigh,  // the S_k with the largest λ(w_k) = w_kᵀ A w_k / w_kᵀ w_k (the average affinity SCGP maximises)
};
std::string_view to_string(ScgpDiscretization d);
ScgpDiscretization scgp_discretization_from_string(std::string_view s);  // "dot_product" | "rayleigh"

// SCGP (Olson et al. 2005): the pairwise affinity matrix
//
//     A_uv = exp(−max(q_uv, q_vu) / affinity_scale),   A_uu = 1,
//
// i.e. with the default scale 2 the Gaussian likelihood kernel exp(−d²/2) of the squared Mahalanobis distance
// (the symmetric max is the conservative choice of §2.5 when q_uv ≠ q_vu). SCGP seeks the indicator vector v
// maximising the average pairwise consistency λ(v) = vᵀAv / vᵀv; relaxed to real v the maximiser is the
// dominant eigenvector v₁ of A (Rayleigh quotient), which is then discretised (ScgpDiscretization). Olson's
// confidence test compares the two largest eigenvalues: the cluster is unambiguous when λ₁/λ₂ is large. With
// min_eigen_ratio > 0 a selection whose λ₁/λ₂ is below it is rejected (empty set); 0 (the default) always
// returns the cluster, as SCGP is used as a selector in the thesis's comparisons (Olson 2009 uses λ₁/λ₂ > 2
// for "locally unambiguous").
struct ScgpOptions {
  double affinity_scale = 2.0;  // s in A_uv = exp(−q_uv / s); > 0 and finite
  ScgpDiscretization discretization = ScgpDiscretization::dot_product;  // Olson et al.'s rule
  double min_eigen_ratio = 0.0;  // λ₁/λ₂ confidence test; 0 = off; otherwise >= 1 and finite
  void validate() const;         // throws std::invalid_argument naming the field
};

// SCGP with its diagnostics.
struct ScgpResult {
  Selection selection;
  std::vector<double> eigenvector;  // v₁, unit norm, sign chosen so that its sum is >= 0
  double lambda1 = 0.0;             // largest eigenvalue of A
  double lambda2 = 0.0;             // second largest (0 when n = 1)
  double eigen_ratio = 0.0;         // λ₁/λ₂ (+inf when λ₂ <= 0)
  bool confident = true;            // eigen_ratio >= min_eigen_ratio (always true when the test is off)
  int cluster_size = 0;             // size of the discretised cluster before the confidence test
  double objective = 0.0;           // λ(w) = wᵀAw / wᵀw of the discretised cluster
};
[[nodiscard]] ScgpResult scgp(const ConsistencyMatrix& Q, const ScgpOptions& options = {});

// SCGP's selection only (scgp(Q, options).selection).
[[nodiscard]] Selection select_scgp(const ConsistencyMatrix& Q, const ScgpOptions& options = {});

}  // namespace keel::pcm
