// keel::cov — joint marginal covariances of sets of poses / landmarks from the sparse information matrix H of
// a pose graph (thesis §5.8.2: the joint Lie-algebra covariance Σ_{1:n} of eq. 5.28 of a jointly correlated
// set of poses, taken from a MAP solution).
//
// H (information.hpp) is factorized once with CHOLMOD (supernodal LLᵀ, fill-reducing ordering chosen by
// CHOLMOD); every query then asks for blocks of Σ = H⁻¹ without ever forming H⁻¹ densely: by default Σ_ab =
// W_aᵀ W_b with W = L⁻¹ P E computed by sparse forward substitutions along the elimination tree, once per
// distinct variable of a batch (Extraction, extraction.hpp). The factorization is keel's one sparse Cholesky
// (linalg::SparseCholesky); CHOLMOD itself stays inside engine/linalg.
//
// Thread-safety: a MarginalCovariance is immutable after construction. joint(), joint_many(), marginal() and
// the pair_marginals queries may be called concurrently from several threads on the same object: every call
// allocates its own workspace (for Extraction::solve, its own linalg::SolveWorkspace), and the factor is only
// read. joint_many(…, threads) itself spreads its column blocks and its queries over `threads` workers in the
// same way.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cov/information.hpp"
#include "linalg/sparse_cholesky.hpp"
#include "lie/types.hpp"

namespace keel::cov {

/// Fill-reducing ordering of the Cholesky factorization: keel's one sparse Cholesky's
/// (linalg/sparse_cholesky.hpp; "auto", "amd", "metis", "nesdis", "natural").
using linalg::Ordering;
using linalg::ordering_from_string;
using linalg::to_string;

/// How the blocks of Σ = H⁻¹ are computed (see marginal_covariance.cpp for the reasoning and the
/// measurements).
enum class Extraction {
  automatic,  // "auto": forward for a supernodal factor, solve for a simplicial one
  forward,    // Σ_ab = W_aᵀ W_b, W = L⁻¹ P E: sparse forward substitutions along the elimination tree
              // (supernodal only)
  solve,      // multi-column solves of H X = E for the distinct variables, keeping the rows needed
};
std::string_view to_string(Extraction e);  // "auto", "forward", "solve"
// The exact names printed by to_string; anything else throws std::invalid_argument naming the valid names.
[[nodiscard]] Extraction extraction_from_string(std::string_view s);

struct CovarianceOptions {
  Ordering ordering = Ordering::automatic;  // fill-reducing ordering handed to CHOLMOD
  bool supernodal = true;                   // supernodal factorization (needed by Extraction::forward)
  Extraction extraction = Extraction::automatic;
  int block_columns = 64;  // right-hand-side columns processed together (≥ 1)
  /// Throws std::invalid_argument naming the violated constraint.
  void validate() const;
};

/// What the factorization did (for reports and benchmarks).
struct FactorSummary {
  std::string ordering;       // ordering CHOLMOD actually used ("amd", "metis", "nesdis", "natural", …)
  bool supernodal = false;    // the factor is supernodal
  std::string extraction;     // the extraction method in use ("forward" or "solve")
  int size = 0;               // rows of H
  std::size_t nnz_h = 0;      // stored entries of the upper triangle of H
  double nnz_l = 0.0;         // nonzeros of L (without supernodal padding), CHOLMOD's lnz
  double factor_flops = 0.0;  // flop count of the factorization, CHOLMOD's fl
  std::size_t num_supernodes = 0;
  std::size_t l_storage = 0;  // doubles stored for L (with supernodal padding)
  double mean_path_fraction =
      0.0;  // supernodal: mean over the columns of the share of L on their path to the root
  double analyze_time_s = 0.0;    // symbolic analysis (ordering) wall time in seconds
  double factorize_time_s = 0.0;  // numeric factorization wall time in seconds
};

class MarginalCovariance;

/// For SE(2) pose graphs: the 6×6 joint covariance [Σ_ii Σ_ij; Σ_ji Σ_jj] of (ξ_i, ξ_j) for every pair,
/// computed like joint_many (the work per distinct pose is shared by all pairs that name it). Throws
/// std::invalid_argument if the poses are not SE(2) or a pair names a landmark.
[[nodiscard]] std::vector<Mat6> pair_marginals_2d(const MarginalCovariance& cov,
                                                  const std::vector<std::pair<int, int>>& pairs,
                                                  unsigned threads = 1);
/// The same for SE(3) pose graphs: 12×12 joint covariances of (ξ_i, ξ_j), ξ = (ρ, φ). Throws
/// std::invalid_argument if the poses are not SE(3) or a pair names a landmark.
[[nodiscard]] std::vector<Mat12> pair_marginals_3d(const MarginalCovariance& cov,
                                                   const std::vector<std::pair<int, int>>& pairs,
                                                   unsigned threads = 1);
/// pair_marginals_2d or pair_marginals_3d by the dimension of the poses: 6×6 or 12×12 blocks (the dispatch of
/// the faces that take 2D and 3D files alike).
[[nodiscard]] std::vector<MatX> pair_marginals(const MarginalCovariance& cov,
                                               const std::vector<std::pair<int, int>>& pairs,
                                               unsigned threads = 1);

/// A linear function y = K ξ = Σ_t C_t ξ_{v_t} of the variables: the variables v_t (repeats allowed) and
/// their coefficient blocks C_t, each rows × dim(v_t) with the same number of rows (the dimension of y, ≥ 1).
struct LinearMap {
  std::vector<int> vars;
  std::vector<MatX> coefficients;
};

/// Cov(y_u, y_v) = K_u Σ K_vᵀ (rows_u × rows_v) for each asked pair (u, v) of indices into `maps`; (u, u)
/// gives y_u's covariance, exactly symmetric. Data snooping, for instance: K = a residual's Jacobian in its
/// edge's two poses, so J Σ Jᵀ of one residual, or of two residuals (u, v), is one query. With
/// Extraction::forward, Z_u = L⁻¹ P K_uᵀ is formed once per map by a forward substitution on the paths of its
/// variables to the root, and each pair is one product Z_uᵀ Z_v over the supernodes common to both: one
/// product per pair of maps where the blocks Σ_ab take one per pair of their variables. The result does not
/// depend on `threads`. Throws std::out_of_range on an unknown variable or map index and
/// std::invalid_argument on coefficient blocks of the wrong size.
[[nodiscard]] std::vector<MatX> linear_map_covariances(
    const MarginalCovariance& cov, const std::vector<LinearMap>& maps,
    const std::vector<std::pair<std::size_t, std::size_t>>& pairs, unsigned threads = 1);

/// Marginal covariances of the variables of a SparseInformation (poses first, then landmarks; see
/// information.hpp), in the Lie algebra of the left perturbation T = exp(ξ^) T̄ (eq. 5.14) for poses and in
/// world coordinates (additive) for landmarks. The pose fixed by a Gauge::fix_pose gauge has zero covariance
/// (and zero cross-covariance).
class MarginalCovariance {
 public:
  /// Factorizes H. Throws std::invalid_argument if H is malformed and std::runtime_error if H is not positive
  /// definite (the message names the first variable at which the factorization broke down — usually a
  /// variable no factor constrains, or a part of the graph that is not connected to the gauge pose).
  explicit MarginalCovariance(const SparseInformation& H, const CovarianceOptions& options = {});
  ~MarginalCovariance();
  MarginalCovariance(MarginalCovariance&&) noexcept;
  MarginalCovariance& operator=(MarginalCovariance&&) noexcept;
  MarginalCovariance(const MarginalCovariance&) = delete;
  MarginalCovariance& operator=(const MarginalCovariance&) = delete;

  /// The joint marginal covariance of `vars` (variable ids, repeats allowed): a (Σ dim) square matrix whose
  /// blocks follow the order asked, block (a, b) = E[ξ_a ξ_bᵀ]. Throws std::out_of_range on an unknown id.
  [[nodiscard]] MatX joint(const std::vector<int>& vars) const;
  /// Marginal covariance of one variable.
  [[nodiscard]] MatX marginal(int var) const;
  /// joint() of many queries at once, sharing the work: the columns of H⁻¹ of every distinct variable are
  /// computed once, in multi-column solves spread over `threads` threads (0 = keel::core::default_threads()).
  /// The result does not depend on `threads`.
  [[nodiscard]] std::vector<MatX> joint_many(const std::vector<std::vector<int>>& queries,
                                             unsigned threads = 1) const;

  const FactorSummary& summary() const;
  int num_poses() const;
  int num_landmarks() const;
  int num_variables() const;
  int variable_dim(int var) const;

  struct Impl;  // CHOLMOD state (marginal_covariance.cpp)

 private:
  std::unique_ptr<Impl> impl_;
  friend std::vector<Mat6> pair_marginals_2d(const MarginalCovariance&,
                                             const std::vector<std::pair<int, int>>&, unsigned);
  friend std::vector<Mat12> pair_marginals_3d(const MarginalCovariance&,
                                              const std::vector<std::pair<int, int>>&, unsigned);
  friend std::vector<MatX> pair_marginals(const MarginalCovariance&, const std::vector<std::pair<int, int>>&,
                                          unsigned);
  friend std::vector<MatX> linear_map_covariances(const MarginalCovariance&, const std::vector<LinearMap>&,
                                                  const std::vector<std::pair<std::size_t, std::size_t>>&,
                                                  unsigned);
};

}  // namespace keel::cov
