// The one sparse symmetric positive-definite factorization of keel, L Lᵀ = P A Pᵀ on CHOLMOD: the marginal
// covariances of engine/cov (supernodal factor read directly, multi-column solves on several threads), the
// certified solver of engine/pgo and the shifted PSD proof (psd_proof.hpp) behind the certificates of pgo and
// sos. The symbolic analysis once per sparsity pattern, then numeric factorizations of new values, solves
// with several right-hand sides, and the largest row count of L that the rounding-error bound of the
// certificate needs (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., Thm 10.3: the
// computed factor satisfies L̂ L̂ᵀ = A + ΔA with |ΔA| ≤ γ_{k+1} |L̂| |L̂ᵀ|, where k bounds the number of products
// summed for any entry — at most the largest number of nonzeros in a row of L). cholmod.h is included by the
// .cpp only.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace keel::linalg {

/// Fill-reducing ordering of the factorization.
enum class Ordering {
  automatic,  // CHOLMOD's default: AMD, then METIS as well when AMD fills badly
  amd,
  metis,
  nesdis,   // CHOLMOD's nested dissection
  natural,  // no reordering (for tests; fill can be catastrophic)
};
std::string_view to_string(Ordering o);  // "auto", "amd", "metis", "nesdis", "natural"
/// Inverse of to_string; throws std::invalid_argument naming the valid values.
[[nodiscard]] Ordering ordering_from_string(std::string_view s);

enum class FactorKind {
  automatic,   // CHOLMOD chooses from the flop count
  supernodal,  // always LLᵀ
  simplicial,
};

struct CholeskyOptions {
  Ordering ordering = Ordering::automatic;
  FactorKind kind = FactorKind::automatic;
  // A simplicial factor as LLᵀ, so that factorize() fails on every matrix that is not positive definite in
  // floating point and the error bounds below (about L̂L̂ᵀ) apply; false: CHOLMOD's LDLᵀ, which runs through
  // negative pivots.
  bool ll = true;
};

// The state of one thread's solves (CHOLMOD's common and dense workspaces, reused from solve to solve):
// several threads solve with one factor, each with its own workspace.
class SolveWorkspace {
 public:
  SolveWorkspace();
  ~SolveWorkspace();
  SolveWorkspace(const SolveWorkspace&) = delete;
  SolveWorkspace& operator=(const SolveWorkspace&) = delete;
  // The right-hand sides of the next solve: n × nrhs, column-major (leading dimension n), zeroed.
  [[nodiscard]] double* right_hand_sides(int n, int nrhs);

 private:
  friend class SparseCholesky;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The supernodal factor as CHOLMOD stores it (after a successful factorize() of a supernodal factor):
// supernode s holds the permuted columns super[s] … super[s+1]−1, the rows rows[pi[s] … pi[s+1]) (its own
// columns first) and the values x[px[s] …], nsrow × nscol column-major.
struct Supernodes {
  int count = 0;
  const int *super = nullptr, *pi = nullptr, *px = nullptr, *rows = nullptr;
  const double* x = nullptr;
};

class SparseCholesky {
 public:
  // The pattern of the upper triangle of A in compressed columns (row indices sorted in each column, the
  // diagonal present in every column). Throws std::invalid_argument on an inconsistent pattern and
  // std::runtime_error when CHOLMOD cannot analyse it.
  SparseCholesky(int n, std::vector<int> col_start, std::vector<int> row_index,
                 const CholeskyOptions& options = {});
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  [[nodiscard]] int size() const { return n_; }
  // The values of the upper triangle, in the order of the pattern; set them, then call factorize().
  [[nodiscard]] std::vector<double>& values() { return values_; }
  [[nodiscard]] const std::vector<int>& col_start() const { return col_start_; }
  [[nodiscard]] const std::vector<int>& row_index() const { return row_index_; }
  // Numeric factorization of the current values; false when the matrix is not positive definite in floating
  // point (a pivot was not positive).
  [[nodiscard]] bool factorize();
  // After a failed factorize(): the row of A (not permuted) where the factorization broke down, or −1 when
  // CHOLMOD reported no row.
  [[nodiscard]] int failed_row() const;
  // x = A⁻¹ b for `nrhs` right-hand sides stored column after column (n × nrhs); needs a successful
  // factorize().
  void solve(const double* b, double* x, int nrhs) const;
  // X = A⁻¹ B for the workspace's right-hand sides (SolveWorkspace::right_hand_sides), on the workspace
  // alone, so that threads can solve at once; returns X column-major with its leading dimension in *ld.
  [[nodiscard]] const double* solve(SolveWorkspace& ws, int* ld) const;
  // The permutation: row k of P A Pᵀ is row permutation()[k] of A (n entries).
  [[nodiscard]] const int* permutation() const;
  [[nodiscard]] bool supernodal() const;
  [[nodiscard]] Supernodes supernodes() const;  // throws std::logic_error for a simplicial factor
  // The largest number of nonzeros in a row of L (the diagonal included), from the symbolic factor; for a
  // supernodal factor the stored pattern (explicit zeros of relaxed supernodes included, so an upper bound).
  [[nodiscard]] int max_row_count() const;
  // After a successful factorize(): a rigorous bound on ‖ΔA‖₂ where L̂ L̂ᵀ = P A Pᵀ + ΔA for the computed
  // factor L̂, from the componentwise bound |ΔA_ij| ≤ γ_{m+1} (|L̂||L̂ᵀ|)_ij with m ≤ min(k_i, k_j) the products
  // in entry (i, j) (Higham Thm 10.3; k_i the nonzeros of row i of L̂) and ‖ΔA‖₂ ≤ max_i Σ_j |ΔA_ij| (ΔA is
  // symmetric): max_i γ_{k_i+1} (|L̂| |L̂ᵀ| 1)_i. The evaluation of that vector rounds (non-negative sums of at
  // most 2n terms, relative error below γ_{2n}); callers add a relative safety factor for it.
  [[nodiscard]] double backward_error_bound() const;
  // After a successful factorize(): a rigorous bound on ‖R‖₂, R = P A Pᵀ − L̂ L̂ᵀ, for the values A that were
  // factorized plus `trailing` (the low parts of a double-double A, in the order of the pattern; none: A is
  // exactly the values), from R itself rather than from a worst case. Every entry of L̂ L̂ᵀ − A is accumulated
  // in doubled precision (each product L̂_ik L̂_jk exact by a fused multiply-add, the sum by Ogita–Rump–Oishi's
  // Sum2, whose error is below 2(m + 1)γ_{m+1} u Σ|terms| for m terms), R_ij is bounded by its computed
  // magnitude plus that error, and ‖R‖₂ ≤ max_i Σ_j |R_ij| (rounded upward). Since L̂ L̂ᵀ ⪰ 0 exactly,
  // λ_min(A) ≥ −‖R‖₂. Typically far below backward_error_bound() (which is what Higham's theorem allows, not
  // what happened), at the cost of one more pass of the factorization's flops. L̂ is extracted once per
  // factorization and shared by both bounds.
  [[nodiscard]] double residual_bound(const std::vector<double>* trailing = nullptr) const;
  // The same bound evaluated entry by entry on the simplicial form of the factor (what residual_bound does
  // for a simplicial factor; for a supernodal one it works block by block, vectorized, and this is its
  // reference in the tests).
  [[nodiscard]] double residual_bound_entrywise(const std::vector<double>* trailing = nullptr) const;
  // The same factorization in double-double arithmetic (double_double.hpp) of the values plus `trailing` (the
  // low parts of a double-double A), on the symbolic pattern of the supernodal analysis (throws
  // std::logic_error for a simplicial one): for matrices whose smallest eigenvalue lies below what a double
  // factor resolves. False when a pivot is not positive. Left-looking, about ten times the flops of the
  // double factorization; the accuracy of its square roots and divisions does not matter to the bound below.
  [[nodiscard]] bool factorize_extended(const std::vector<double>& trailing);
  // After a successful factorize_extended(): a rigorous bound on ‖P(A + trailing)Pᵀ − L̂L̂ᵀ‖₂ for the
  // double-double factor L̂ = L_hi + L_lo (every product split into exact parts, summed as in
  // residual_bound), of the order of u² times the entries.
  [[nodiscard]] double extended_residual_bound(const std::vector<double>& trailing) const;
  // After a successful factorize(): the computed factor L̂ of P A Pᵀ (lower triangle in compressed columns,
  // CHOLMOD's simplicial form) and the permutation (row k of P A Pᵀ is row perm[k] of A), so that the tests
  // can check the bounds above against the residual computed exactly.
  void computed_factor(std::vector<int>& col_start, std::vector<int>& row_index, std::vector<double>& values,
                       std::vector<int>& perm) const;
  [[nodiscard]] std::string ordering_name() const;  // the ordering CHOLMOD used: "amd", "metis", ...
  [[nodiscard]] double factor_nonzeros() const;
  [[nodiscard]] double factor_flops() const;  // of the last factorization
  [[nodiscard]] double factor_storage()
      const;  // stored entries of L (a supernodal factor's padding included)

 private:
  struct Impl;
  int n_ = 0;
  std::vector<int> col_start_, row_index_;
  std::vector<double> values_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace keel::linalg
