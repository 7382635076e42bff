// A rigorous test of S + η·D ⪰ 0 for a sparse symmetric S given in double-double with a bound on the error of
// its entries, D a 0/1 diagonal: the proof behind the dual certificates of pgo/certified.hpp (SE-Sync's
// problem) and sos/verify.hpp (the thesis's planar problem, eq. 4.6–4.11).
//
// A = W(S + ηD)W − μI is formed in double-double, W a diagonal of exact powers of two close to Jacobi's
// scaling, and factorized: A = L̂L̂ᵀ + R with L̂L̂ᵀ ⪰ 0 exactly, so S + ηD ⪰ 0 once μ ≥ 1.01·(‖R‖₂ + the
// formation error in 2-norm). ‖R‖₂ is bounded first by Higham's Thm 10.3 (|R| ≤ γ_{k+1}|L̂||L̂ᵀ|, cheap), then
// by the residual itself, measured in doubled precision (sparse_cholesky.hpp). With `extended`, the factor is
// computed in double-double (residual of order u²) for shifts below what a double factor resolves. Private to
// engine/pgo and the areas that build on it (sos).
#pragma once

#include <vector>

#include "linalg/sparse_cholesky.hpp"

namespace keel::linalg {

// S on an upper-triangular pattern in compressed columns (rows ascending, the diagonal stored and last in
// every column): S_exact = hi + lo + δ with |δ| ≤ error entrywise (the caller's bound on forming S).
struct DoubleDoubleSymmetric {
  int n = 0;
  std::vector<int> col_start, row_index;
  std::vector<double> hi, lo, error;
};

struct PsdProof {
  bool proven = false;
  bool extended_precision = false;   // the double-double factor was used
  double margin = 0.0;               // μ, in the scaled matrix
  double residual = 0.0;             // the bound on ‖R‖₂ that cleared μ
  double worst_case_residual = 0.0;  // Higham's bound for the same (double) factor; 0 for a double-double one
  double formation_error = 0.0;      // the bound on the error of forming A, in 2-norm (scaled)
};

// The search for the smallest provable shift that both certificates run (shift_search below).
struct ShiftSearch {
  bool proven = false;
  double shift = 0.0;             // the proven η (when proven)
  bool within_tolerance = false;  // proven at η*/33 or η*/2 (the shifts the gap tolerance allows)
  double largest_failed = 0.0;    // the largest shift whose proof failed (0: none)
  int attempts = 0;
  PsdProof proof;  // of the proven shift, or of the last attempt when none was proven
};

class ShiftedPsdProver {
 public:
  // `shifted[k]` = 1 where D has a 1. Analyses the pattern once (CHOLMOD, supernodal).
  ShiftedPsdProver(DoubleDoubleSymmetric S, std::vector<char> shifted);
  // The proof of S + η·D ⪰ 0 (η ≥ 0): a double factor with μ from 32u (lowered once after a breakdown, raised
  // to what the residual needs; at most four factorizations), or with `extended` one double-double factor and
  // μ = 2⁻⁸⁰ plus the formation error.
  [[nodiscard]] PsdProof prove(double eta, bool extended);
  // The decisive shift η* (the largest a gap tolerance allows) is tried at η*/33 (a tighter bound, the shift
  // that holds on most data sets) and η*/2 (so the rounding of the bound stays inside the tolerance), each
  // with a double factor, then both with a double-double one; when all fail, the shift is raised tenfold at a
  // time from `reference` (η_ref·10^k, k = 1 … `escalation`, double factors) to the tightest bound that can
  // still be proven. η* ≤ 0 skips the first part. With `refinements` > 0 the decade found is then bisected in
  // log scale that many times (each a proof attempt; the smallest shift proven is kept), so that the bound is
  // not up to ten times weaker than the shift that holds.
  [[nodiscard]] ShiftSearch shift_search(double eta_star, double reference, int escalation,
                                         int refinements = 0);
  // The factorization (its last values are those of the last attempt), e.g. for inverse iteration.
  [[nodiscard]] SparseCholesky& cholesky() { return chol_; }
  [[nodiscard]] const DoubleDoubleSymmetric& matrix() const { return S_; }
  [[nodiscard]] int diagonal_index(int col) const {
    return S_.col_start[static_cast<std::size_t>(col) + 1] - 1;
  }

 private:
  DoubleDoubleSymmetric S_;
  std::vector<char> shifted_;
  SparseCholesky chol_;
};

}  // namespace keel::linalg
