// keel::pgo::certified — the dual certificate at a point: the multipliers Λ, the certificate matrix S − Λ
// formed in double-double, the proof of S + ηD ⪰ 0 with its rounding margin, and the escape direction when it
// fails (certified_internal.hpp).
#include "pgo/certified_internal.hpp"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/blas.hpp"
#include "core/timing.hpp"
#include "linalg/double_double.hpp"
#include "linalg/psd_proof.hpp"
#include "linalg/sparse_cholesky.hpp"

namespace keel::pgo::certified {

// ---------------------------------------------------------------------------------------------------------------
// The certificate matrix S + η D over the columns [pose 0: Y_0 | pose v ≥ 1: t_v, Y_v].
struct CertificateMatrix {
  BlockPattern pattern;
  std::vector<int> pos;  // per edge
  explicit CertificateMatrix(const Problem& P)
      : pattern(
            [&] {
              std::vector<int> s(static_cast<std::size_t>(P.n), P.d + 1);
              s[0] = P.d;
              return s;
            }(),
            [&] {
              std::vector<std::pair<int, int>> pairs;
              for (const auto& e : P.edges) pairs.emplace_back(e.i, e.j);
              return pairs;
            }()) {
    pos.resize(P.edges.size());
    for (std::size_t k = 0; k < P.edges.size(); ++k)
      pos[k] = pattern.position(std::min(P.edges[k].i, P.edges[k].j), std::max(P.edges[k].i, P.edges[k].j));
  }
};

std::vector<Small> multipliers(const Problem& P, const Point& X, const Gradient& G) {
  std::vector<Small> Lam(static_cast<std::size_t>(P.n));
  for (int v = 0; v < P.n; ++v) {
    const Small A = 0.5 * X.Y(v, P.d).transpose() * G.GY[static_cast<std::size_t>(v)];
    Lam[static_cast<std::size_t>(v)] = 0.5 * (A + A.transpose());
  }
  return Lam;
}

double cost_upper(const Problem& P, const Point& X) {
  using core::round_up;
  const int d = P.d, r = X.r;
  constexpr double u2 = kUnitRoundoff * kUnitRoundoff;
  // |exact| ≤ |hi| + |lo| + 8(k + 1)u²·magnitude (exact products of small integers and powers of two).
  auto entry = [&](DD s, double magnitude, int additions) {
    const double err = round_up(8.0 * (additions + 1) * u2 * magnitude);
    const double v = round_up(round_up(std::abs(s.hi) + std::abs(s.lo)) + err);
    return round_up(v * v);
  };
  double f = 0.0;
  for (const auto& e : P.edges) {
    const auto Yi = X.Y(e.i, d);
    const auto Yj = X.Y(e.j, d);
    double rot = 0.0, trans = 0.0;
    for (int a = 0; a < r; ++a) {
      for (int c = 0; c < d; ++c) {
        DD s{Yj(a, c), 0.0};
        double mag = std::abs(Yj(a, c));
        for (int m = 0; m < d; ++m) {
          s = dd_add(s, dd_prod(-Yi(a, m), e.R(m, c)));
          mag = round_up(mag + round_up(std::abs(Yi(a, m) * e.R(m, c))));
        }
        rot = round_up(rot + entry(s, mag, d));
      }
      DD s = dd_add(DD{X.T(a, e.j), 0.0}, DD{-X.T(a, e.i), 0.0});
      double mag = round_up(std::abs(X.T(a, e.j)) + std::abs(X.T(a, e.i)));
      for (int m = 0; m < d; ++m) {
        s = dd_add(s, dd_prod(-Yi(a, m), e.t(m)));
        mag = round_up(mag + round_up(std::abs(Yi(a, m) * e.t(m))));
      }
      trans = round_up(trans + entry(s, mag, d + 1));
    }
    f = round_up(f + round_up(round_up(e.kappa * rot) + round_up(e.tau * trans)));
  }
  return f;
}

Certificate certificate_at(const Problem& P, const Point& X, double gap_tolerance, EscapeDirection* escape) {
  const auto t0 = core::Clock::now();
  const int d = P.d;
  Certificate C;
  const double F = cost(P, X);
  const Gradient G = gradient(P, X);
  const std::vector<Small> Lam = multipliers(P, X, G);
  double trace = 0.0, trace_abs = 0.0;
  for (const auto& L : Lam)
    for (int c = 0; c < d; ++c) {
      trace += L(c, c);
      trace_abs = core::round_up(trace_abs + std::abs(L(c, c)));  // an upper bound on Σ|Λ_cc|
    }
  C.trace_lambda = trace;
  const double dn = static_cast<double>(d) * P.n;
  const double eta = (gap_tolerance * std::max(F, 1.0) - (F - trace)) / dn;
  C.tolerance_shift = eta;
  C.rank = X.r;
  C.bound.upper = cost_upper(P, X);
  CertificateMatrix CM(P);
  const BlockPattern& pat = CM.pattern;
  const int N = pat.dimension();
  C.size = N;
  // S = M − diag(0, Λ) in double-double: its hi parts (S) and lo parts (S_lo); Sabs holds Σ|terms| and
  // S_terms the number of terms of each entry, for the bound on the formation's own error.
  const std::size_t nnz = pat.row_index().size();
  std::vector<double> S(nnz, 0.0), S_lo(nnz, 0.0), Sabs(nnz, 0.0);
  std::vector<int> S_terms(nnz, 0);
  auto accumulate = [&](int idx, DD value, double magnitude) {
    const auto q = static_cast<std::size_t>(idx);
    const DD sum = dd_add(DD{S[q], S_lo[q]}, value);
    S[q] = sum.hi;
    S_lo[q] = sum.lo;
    Sabs[q] = core::round_up(Sabs[q] + magnitude);
    ++S_terms[q];
  };
  for (std::size_t k = 0; k < P.edges.size(); ++k) {
    const int pos = CM.pos[k];
    edge_entries(P.edges[k], d, [&](int a, int b, int row, int col, DD value, double magnitude) {
      int idx = 0;
      if (a == b) {
        if (row > col) return;  // upper triangle only (the lower one is its mirror)
        idx = pat.index(pat.diagonal_position(a), a, row, col);
      } else if (a < b) {
        idx = pat.index(pos, b, row, col);
      } else {
        idx = pat.index(pos, a, col, row);
      }
      accumulate(idx, value, magnitude);
    });
  }
  // − Λ on the rotation blocks (Λ as stored: any symmetric Λ gives a valid bound).
  for (int v = 0; v < P.n; ++v) {
    const int rot = v == 0 ? 0 : 1;
    const int dp = pat.diagonal_position(v);
    for (int c2 = 0; c2 < d; ++c2)
      for (int c = 0; c <= c2; ++c)
        accumulate(pat.index(dp, v, rot + c, rot + c2), DD{-Lam[static_cast<std::size_t>(v)](c, c2), 0.0},
                   std::abs(Lam[static_cast<std::size_t>(v)](c, c2)));
  }
  // Each term of an entry is formed from products of stored numbers with an error below (4d + 7)·u² times the
  // sum of those products' magnitudes (the term's `magnitude`: d exact products added in double-double for
  // R̃R̃ᵀ, 4u² of the partial sums each, then κ· and τ· scalings of 3u² and one addition of 4u²), and each of
  // the entry's m additions errs by at most 4u²·(the partial sums' magnitudes) ≤ 4u²·Σ magnitudes:
  // |error| ≤ (4m + 4d + 8)·u²·Σ magnitudes.
  const std::vector<double> S_unshifted = S;
  auto is_rotation = [&](int col) {
    // Pose 0 occupies columns 0 … d−1 (all rotation); pose v ≥ 1 starts with its translation.
    if (col < d) return true;
    return (col - d) % (d + 1) != 0;
  };
  linalg::DoubleDoubleSymmetric SS;
  SS.n = N;
  SS.col_start = pat.col_start();
  SS.row_index = pat.row_index();
  SS.hi = S;
  SS.lo = S_lo;
  SS.error.resize(nnz);
  for (std::size_t q = 0; q < nnz; ++q)
    SS.error[q] =
        core::round_up((4.0 * S_terms[q] + 4.0 * d + 8.0) * kUnitRoundoff * kUnitRoundoff * Sabs[q]);
  std::vector<char> rotation_columns(static_cast<std::size_t>(N));
  for (int col = 0; col < N; ++col)
    rotation_columns[static_cast<std::size_t>(col)] = is_rotation(col) ? 1 : 0;
  linalg::ShiftedPsdProver prover(std::move(SS), std::move(rotation_columns));
  linalg::SparseCholesky& chol = prover.cholesky();
  C.max_row_count = chol.max_row_count();
  auto diagonal_index = [&](int col) { return prover.diagonal_index(col); };
  // The proof of S + η·D ⪰ 0 at the smallest shift it can reach (psd_proof.hpp): η*/33 or η*/2 certify;
  // otherwise up to 10⁵·gap·max(F, 1)/(dn), the tightest bound that can be proven, outside the tolerance, its
  // decade bisected three times (the shift within a factor 10^(1/8) of the smallest that a proof reaches).
  const linalg::ShiftSearch search = prover.shift_search(eta, gap_tolerance * std::max(F, 1.0) / dn, 5, 3);
  C.attempts = search.attempts;
  C.failed_shift = search.largest_failed;
  C.proven = search.proven;
  // The proof's fields only from the proof that succeeded (search.proof is the last attempt's: a failed one
  // when nothing was proven).
  if (search.proven) {
    C.shift = search.shift;
    C.rounding_margin = search.proof.margin;
    C.residual = search.proof.residual;
    C.worst_case_residual = search.proof.worst_case_residual;
    C.formation_error = search.proof.formation_error;
    C.extended_precision = search.proof.extended_precision;
  }
  // What failed is kept apart from what was proven (C.failure, C.message): a failed attempt is never
  // described beside a proof.
  const std::string all_failed = search.proven
                                     ? std::string()
                                     : fmt::format("; every shift up to η = {:.3g} failed too ({} attempts)",
                                                   C.failed_shift, C.attempts);
  if (!search.within_tolerance)
    C.failure =
        eta > 0.0
            ? fmt::format(
                  "S + η·D ⪰ 0 could not be shown at η*/33 or η*/2 = {:.3g} (η* = {:.3g}): the "
                  "factorization of W(S + η·D)W − μI broke down or its residual exceeded μ{}",
                  0.5 * eta, eta, all_failed)
            : fmt::format("not stationary enough for the gap tolerance: F − tr(Λ) = {:.3g} exceeds {:.3g}{}",
                          F - trace, gap_tolerance * std::max(F, 1.0), all_failed);
  bool certified = false;
  if (search.proven) {
    // The lower bound tr(Λ) − γ_{dn}Σ|Λ_cc| − η d n (γ_{dn}Σ|Λ_cc|: the rounding of the trace's sum), every
    // operation rounded outward: the subtracted terms up, the differences down (core::round_down).
    const double k_u = dn * kUnitRoundoff;  // exact: an integer times a power of two
    const double gamma_up = core::round_up(k_u / core::round_down(1.0 - k_u));
    const double trace_error = core::round_up(gamma_up * trace_abs);
    const double shift_term = core::round_up(C.shift * dn);
    C.bound.lower = core::round_down(core::round_down(trace - trace_error) - shift_term);
    certified = C.bound.relative_gap_up() <= gap_tolerance;
    C.certified = certified;
    C.message = fmt::format("S + {}·D ⪰ 0 proven with rounding margin μ = {:.3g} (scaled){}{}",
                            core::format_upper(C.shift, 3), C.rounding_margin,
                            C.extended_precision ? " by a double-double factor" : "",
                            certified ? "" : ", outside the gap tolerance");
  } else {
    C.message = "no lower bound: " + C.failure;
  }
  if (!certified && escape) {
    // A direction of negative curvature: σ doubled from max(η, tiny) until S + σD factorizes, then inverse
    // iteration v ← (S + σD)⁻¹ D v, whose Rayleigh quotient vᵀSv / vᵀDv tends to the smallest generalized
    // eigenvalue.
    double sigma = std::max(eta, 1e-12 * std::max(1.0, F / dn));
    bool ok = false;
    for (int attempt = 0; attempt < 80 && !ok; ++attempt) {
      auto& A = chol.values();
      A = S_unshifted;
      for (int col = 0; col < N; ++col)
        if (is_rotation(col)) A[static_cast<std::size_t>(diagonal_index(col))] += sigma;
      ok = chol.factorize();
      if (!ok) sigma *= 2.0;
    }
    if (ok) {
      Eigen::VectorXd v(N), Dv(N);
      for (int col = 0; col < N; ++col) v(col) = is_rotation(col) ? std::cos(0.7 * col + 0.3) : 0.0;
      Eigen::VectorXd Sv(N);
      double q = 0.0;
      for (int iter = 0; iter < 60; ++iter) {
        for (int col = 0; col < N; ++col) Dv(col) = is_rotation(col) ? v(col) : 0.0;
        Eigen::VectorXd next(N);
        chol.solve(Dv.data(), next.data(), 1);
        double dnorm = 0.0;
        for (int col = 0; col < N; ++col)
          if (is_rotation(col)) dnorm += next(col) * next(col);
        v = next / std::sqrt(dnorm);
        symmetric_product(pat.col_start(), pat.row_index(), S_unshifted, v, Sv);
        q = v.dot(Sv);  // vᵀDv = 1
        if (iter >= 8 && q < -0.5 * sigma) break;
      }
      escape->v = v;
      escape->rayleigh = q;
      // Below −η* the staircase can descend; in [−η*, 0) the test failed by its rounding margin only, and a
      // lift would not help.
      escape->found = q < -std::max(eta, 0.0);
    }
  }
  C.time_s = core::seconds_since(t0);
  return C;
}

}  // namespace keel::pgo::certified
