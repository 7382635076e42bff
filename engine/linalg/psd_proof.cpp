#include "linalg/psd_proof.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "linalg/double_double.hpp"

namespace keel::linalg {

namespace {
constexpr double kU = std::numeric_limits<double>::epsilon() / 2;  // u = 2⁻⁵³
double gamma(double k) { return k * kU / (1.0 - k * kU); }
}  // namespace

ShiftedPsdProver::ShiftedPsdProver(DoubleDoubleSymmetric S, std::vector<char> shifted)
    : S_(std::move(S)),
      shifted_(std::move(shifted)),
      chol_(S_.n, S_.col_start, S_.row_index, {.kind = FactorKind::supernodal}) {
  const auto nnz = S_.row_index.size();
  if (S_.hi.size() != nnz || S_.lo.size() != nnz || S_.error.size() != nnz ||
      shifted_.size() != static_cast<std::size_t>(S_.n))
    throw std::invalid_argument("ShiftedPsdProver: sizes do not match the pattern");
}

PsdProof ShiftedPsdProver::prove(double eta, bool extended) {
  PsdProof out;
  const int N = S_.n;
  const auto nnz = S_.row_index.size();
  // A = W(S + ηD)W − μI in double-double (Ah + Al); CHOLMOD factors Ah, the proof is about A itself.
  std::vector<double> Sh = S_.hi, Sl = S_.lo;
  for (int col = 0; col < N; ++col)
    if (shifted_[static_cast<std::size_t>(col)]) {
      const auto q = static_cast<std::size_t>(diagonal_index(col));
      const DD x = dd_add(DD{Sh[q], Sl[q]}, DD{eta, 0.0});
      Sh[q] = x.hi;
      Sl[q] = x.lo;
    }
  std::vector<double> w(static_cast<std::size_t>(N), 1.0);
  for (int col = 0; col < N; ++col) {
    const double a = Sh[static_cast<std::size_t>(diagonal_index(col))];
    if (!(a > 0.0) || !std::isfinite(a)) return out;  // a non-positive diagonal: not PSD (or not finite)
    // W = 2^−round(log2(a)/2): exact scaling by a power of two, close to Jacobi's.
    w[static_cast<std::size_t>(col)] = std::ldexp(1.0, -static_cast<int>(std::lround(std::log2(a) / 2.0)));
  }
  auto& A = chol_.values();
  std::vector<double> Al(nnz, 0.0), row_form(static_cast<std::size_t>(N), 0.0);
  for (int col = 0; col < N; ++col)
    for (int q = S_.col_start[static_cast<std::size_t>(col)];
         q < S_.col_start[static_cast<std::size_t>(col) + 1]; ++q) {
      const auto Q = static_cast<std::size_t>(q);
      const int row = S_.row_index[Q];
      const double sc = w[static_cast<std::size_t>(row)] * w[static_cast<std::size_t>(col)];
      A[Q] = sc * Sh[Q];
      Al[Q] = sc * Sl[Q];
      // The caller's bound on forming S, plus the additions of η (before scaling) and of μ (after; μ < 1 on
      // the unit diagonal) in double-double, each below 4u²·(|entry| + |added|), doubled.
      const double shift = row == col && shifted_[static_cast<std::size_t>(col)] ? eta : 0.0;
      const double u2 = kU * kU;
      const double form = sc * (S_.error[Q] + 8.0 * u2 * (std::abs(Sh[Q]) + shift)) +
                          (row == col ? 8.0 * u2 * (sc * std::abs(Sh[Q]) + 1.0) : 0.0);
      row_form[static_cast<std::size_t>(row)] += form;
      if (row != col) row_form[static_cast<std::size_t>(col)] += form;
    }
  // What the factorization must clear besides the residual of its factor: the formation's error in 2-norm
  // (its largest row sum, doubled for the rounding of its own evaluation), and a subnormal floor per column
  // for the scaling.
  const double fixed = 2.0 * *std::max_element(row_form.begin(), row_form.end()) +
                       N * std::numeric_limits<double>::denorm_min();
  out.formation_error = fixed;
  // A posteriori: factorize Ah; with the computed factor L̂, A = L̂L̂ᵀ + R with L̂L̂ᵀ ⪰ 0 exactly and ‖R‖₂ ≤ E,
  // so W(S + ηD)W ⪰ (μ − E − fixed)·I ⪰ 0 once 1.01·(E + fixed) ≤ μ (the 1 % covers the rounding of E and of
  // μ's own arithmetic). E is first Higham's worst case for L̂L̂ᵀ − Ah plus Al's row sums
  // (SparseCholesky::backward_error_bound, cheap); when that does not clear μ, the residual itself,
  // accumulated in doubled precision against Ah + Al (SparseCholesky::residual_bound). μ starts above the
  // residuals measured on SE-Sync's benchmark graphs (at most 1.7e-15 ≈ 16u on the unit diagonal:
  // ext_certified_pgo's `*.residual`), is lowered when the factorization breaks down and raised to what the
  // last factor needed; at most four factorizations.
  const std::vector<double> scaled_hi = A, scaled_lo = Al;
  auto subtract_mu = [&](double mu) {
    A = scaled_hi;
    Al = scaled_lo;
    for (int col = 0; col < N; ++col) {
      const auto q = static_cast<std::size_t>(diagonal_index(col));
      const DD x = dd_add(DD{A[q], Al[q]}, DD{-mu, 0.0});
      A[q] = x.hi;
      Al[q] = x.lo;
    }
    out.margin = mu;
  };
  if (extended) {
    // The factor in double-double (SparseCholesky::factorize_extended): its residual is of the order of u² of
    // the unit-diagonal matrix, so μ = 2⁻⁸⁰ (8e-25) plus the formation's error clears it with room.
    const double mu = 1.01 * fixed + std::ldexp(1.0, -80);
    subtract_mu(mu);
    out.extended_precision = true;
    if (!chol_.factorize_extended(Al)) return out;
    out.residual = chol_.extended_residual_bound(Al);
    out.proven = 1.01 * (out.residual + fixed) <= mu;
    return out;
  }
  double mu = 1.01 * fixed + 32.0 * kU;
  double failed_mu =
      std::numeric_limits<double>::infinity();  // the smallest μ whose factorization broke down
  for (int attempt = 0; attempt < 4; ++attempt) {
    subtract_mu(mu);
    if (!chol_.factorize()) {
      // Broke down: once more with a quarter of μ (the residuals measured on the benchmark graphs are
      // at most 16u, so a smaller μ can still clear them), never below the formation's error.
      failed_mu = mu;
      mu = 1.01 * fixed + 0.25 * (mu - 1.01 * fixed);
      if (mu < 1.01 * fixed + 4.0 * kU) return out;
      continue;
    }
    std::vector<double> row_lo(static_cast<std::size_t>(N), 0.0);
    for (int col = 0; col < N; ++col)
      for (int q = S_.col_start[static_cast<std::size_t>(col)];
           q < S_.col_start[static_cast<std::size_t>(col) + 1]; ++q) {
        const int row = S_.row_index[static_cast<std::size_t>(q)];
        row_lo[static_cast<std::size_t>(row)] += std::abs(Al[static_cast<std::size_t>(q)]);
        if (row != col) row_lo[static_cast<std::size_t>(col)] += std::abs(Al[static_cast<std::size_t>(q)]);
      }
    const double lo_norm = *std::max_element(row_lo.begin(), row_lo.end()) * (1.0 + gamma(2.0 * N));
    const double higham = chol_.backward_error_bound() + lo_norm;
    out.worst_case_residual = higham;
    if (1.01 * (higham + fixed) <= mu) {
      out.residual = higham;
      out.proven = true;
      return out;
    }
    const double measured = chol_.residual_bound(&Al);
    if (1.01 * (measured + fixed) <= mu) {
      out.residual = measured;
      out.proven = true;
      return out;
    }
    mu = 1.05 * 1.01 * (measured + fixed);
    if (mu >= failed_mu) return out;  // a larger μ than one that already broke down cannot succeed
  }
  return out;
}

ShiftSearch ShiftedPsdProver::shift_search(double eta_star, double reference, int escalation,
                                           int refinements) {
  ShiftSearch out;
  auto attempt = [&](double eta, bool extended) {
    ++out.attempts;
    out.proof = prove(eta, extended);
    if (!out.proof.proven) {
      out.largest_failed = std::max(out.largest_failed, eta);
      return false;
    }
    out.proven = true;
    out.shift = eta;
    return true;
  };
  if (eta_star > 0.0)
    for (const bool extended : {false, true})
      if (attempt(eta_star / 33.0, extended) || attempt(0.5 * eta_star, extended)) {
        out.within_tolerance = true;
        return out;
      }
  double eta = reference;
  for (int k = 1; k <= escalation; ++k) {
    eta *= 10.0;
    if (attempt(eta, false)) {
      // Bisection in log scale between the largest shift that failed (or `reference`, when none did) and the
      // one proven: each halving of the interval's log width that proves keeps its shift and proof.
      double lo = std::max(out.largest_failed, reference), hi = eta;
      PsdProof best = out.proof;
      for (int r = 0; r < refinements && lo > 0.0 && lo < hi; ++r) {
        const double mid = std::sqrt(lo * hi);
        if (!(mid > lo && mid < hi)) break;
        if (attempt(mid, false)) {
          hi = mid;
          best = out.proof;
        } else {
          lo = mid;
        }
      }
      out.proven = true;
      out.shift = hi;
      out.proof = best;
      return out;
    }
  }
  return out;
}

}  // namespace keel::linalg
