// A sparse symmetric positive-definite factorization L Lᵀ = P A Pᵀ on CHOLMOD for the certified solver
// (certified.hpp) and the shifted PSD proof (psd_proof.hpp, which sos/verify.cpp also uses): the symbolic
// analysis once per sparsity pattern, then numeric factorizations of new values, solves with several
// right-hand sides, and the largest row count of L that the rounding-error bound of the certificate needs
// (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., Thm 10.3: the computed factor satisfies
// L̂ L̂ᵀ = A + ΔA with |ΔA| ≤ γ_{k+1} |L̂| |L̂ᵀ|, where k bounds the number of products summed for any entry — at
// most the largest number of nonzeros in a row of L). Private to engine/pgo and the areas that build on its
// proof (sos); cholmod.h is included by the .cpp only.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace keel::pgo::detail {

enum class FillOrdering {
  automatic,  // CHOLMOD's default: AMD, then METIS as well when AMD fills badly
  amd,
  metis,
};

class SparseCholesky {
 public:
  // The pattern of the upper triangle of A in compressed columns (row indices sorted in each column, the
  // diagonal present in every column). `supernodal` forces the supernodal factorization (otherwise CHOLMOD
  // chooses). Throws std::runtime_error when CHOLMOD cannot analyse the pattern.
  SparseCholesky(int n, std::vector<int> col_start, std::vector<int> row_index, FillOrdering ordering,
                 bool supernodal);
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
  // x = A⁻¹ b for `nrhs` right-hand sides stored column after column (n × nrhs); needs a successful
  // factorize().
  void solve(const double* b, double* x, int nrhs) const;
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
  [[nodiscard]] std::string ordering_name() const;
  [[nodiscard]] double factor_nonzeros() const;

 private:
  struct Impl;
  int n_ = 0;
  std::vector<int> col_start_, row_index_;
  std::vector<double> values_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace keel::pgo::detail
