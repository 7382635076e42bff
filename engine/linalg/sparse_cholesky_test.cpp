// linalg::SparseCholesky's two bounds on the error of a computed factor: the residual accumulated in doubled
// precision (residual_bound) against exact cases, the double-double trailing parts of A, Higham's worst case
// (backward_error_bound) as an upper envelope, and factorize() refusing indefinite matrices.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/random.hpp"
#include "linalg/psd_proof.hpp"
#include "linalg/sparse_cholesky.hpp"

using keel::linalg::CholeskyOptions;
using keel::linalg::FactorKind;
using keel::linalg::Ordering;
using keel::linalg::SparseCholesky;

namespace {

// The upper triangle (compressed columns, rows ascending, diagonal last) of an n × n band of half-width
// `bandwidth`.
struct Pattern {
  std::vector<int> col_start{0}, row_index;
};
Pattern banded(int n, int bandwidth) {
  Pattern p;
  for (int c = 0; c < n; ++c) {
    for (int r = std::max(0, c - bandwidth); r <= c; ++r) p.row_index.push_back(r);
    p.col_start.push_back(static_cast<int>(p.row_index.size()));
  }
  return p;
}

// A = L Lᵀ for a lower-banded L with diagonal 4 and off-diagonal entries in {−1, 0, 1} (diagonally dominant,
// so well conditioned): A's entries are small integers, exact in double.
std::vector<double> integer_product(const Pattern& p, int n, int bandwidth, keel::core::Rng& gen) {
  // −1, 0 or 1, equally likely (keel's generator: std's distributions are implementation-defined).
  const auto entry = [](keel::core::Rng& r) { return std::min(1, static_cast<int>(3 * r.uniform())) - 1; };
  std::vector<std::vector<double>> L(static_cast<std::size_t>(n),
                                     std::vector<double>(static_cast<std::size_t>(n)));
  for (int i = 0; i < n; ++i) {
    L[i][i] = 4.0;
    for (int k = std::max(0, i - bandwidth); k < i; ++k) L[i][k] = entry(gen);
  }
  std::vector<double> values;
  for (int c = 0; c < n; ++c)
    for (int q = p.col_start[c]; q < p.col_start[c + 1]; ++q) {
      const int r = p.row_index[q];
      double a = 0.0;
      for (int k = 0; k <= r; ++k) a += L[r][k] * L[c][k];
      values.push_back(a);
    }
  return values;
}

}  // namespace

TEST_CASE("residual_bound: within Higham's worst case; trailing parts δ raise it by δ") {
  const int n = 60, bw = 2;
  keel::core::Rng gen(3);
  const Pattern p = banded(n, bw);
  for (const bool supernodal : {false, true}) {
    SparseCholesky chol(n, p.col_start, p.row_index,
                        CholeskyOptions{.ordering = Ordering::amd,
                                        .kind = supernodal ? FactorKind::supernodal : FactorKind::automatic});
    chol.values() = integer_product(p, n, bw, gen);
    REQUIRE(chol.factorize());
    // Whatever ordering CHOLMOD picks (it may not keep the factorization exact), the residual is what
    // rounding left, and Higham's bound is its envelope.
    const double r = chol.residual_bound();
    CHECK(r >= 0.0);
    CHECK(r <= chol.backward_error_bound());
    // Trailing parts δ on the diagonal: A + δI differs from the factored A by δ per row, so the bound
    // grows by δ (up to its own rounding), never less.
    const double delta = 1e-20;
    std::vector<double> trailing(chol.values().size(), 0.0);
    for (int c = 0; c < n; ++c) trailing[static_cast<std::size_t>(p.col_start[c + 1] - 1)] = delta;
    const double rt = chol.residual_bound(&trailing);
    CHECK(rt >= delta);
    CHECK(rt <= r + 1.01 * delta + 1e-30);
  }
}

TEST_CASE("residual_bound: an exact factorization leaves no residual") {
  // A diagonal matrix of perfect squares: every ordering factors it exactly.
  const int n = 25;
  Pattern p = banded(n, 0);
  SparseCholesky chol(n, p.col_start, p.row_index, CholeskyOptions{.ordering = Ordering::amd});
  for (int c = 0; c < n; ++c) chol.values()[static_cast<std::size_t>(c)] = (c + 1.0) * (c + 1.0);
  REQUIRE(chol.factorize());
  CHECK(chol.residual_bound() <= 1e-25);
}

TEST_CASE("residual_bound: far below Higham's worst case on a generic matrix, and bounded by it") {
  const int n = 400, bw = 6;
  keel::core::Rng gen(11);
  const auto normal = [](keel::core::Rng& r) { return r.normal(); };
  const Pattern p = banded(n, bw);
  SparseCholesky chol(n, p.col_start, p.row_index,
                      CholeskyOptions{.ordering = Ordering::automatic, .kind = FactorKind::supernodal});
  // Diagonally dominant with random off-diagonal entries, unit-scale diagonal.
  for (int c = 0; c < n; ++c)
    for (int q = p.col_start[c]; q < p.col_start[c + 1]; ++q)
      chol.values()[static_cast<std::size_t>(q)] = p.row_index[q] == c ? 2.0 * bw + 1.0 : normal(gen);
  REQUIRE(chol.factorize());
  const double r = chol.residual_bound(), h = chol.backward_error_bound();
  CHECK(r > 0.0);      // rounding happened
  CHECK(r < 0.1 * h);  // what happened is well below what the theorem allows
  // The supernodal block evaluation against the entry-by-entry one on the same factor: both measure the same
  // residual to about u² (their error terms differ), with and without trailing parts.
  CHECK(r == doctest::Approx(chol.residual_bound_entrywise()).epsilon(1e-6));
  std::vector<double> trailing(chol.values().size());
  for (double& t : trailing) t = 1e-17 * normal(gen);
  CHECK(chol.residual_bound(&trailing) ==
        doctest::Approx(chol.residual_bound_entrywise(&trailing)).epsilon(1e-6));
}

TEST_CASE("factorize refuses an indefinite matrix; a tiny negative eigenvalue is not hidden by the bound") {
  // A = diag(1, …, 1, −1e-14): the factorization must fail; A + 2e-14 I must succeed with a residual far
  // below 1e-14, so a proof at shift 2e-14 − margin holds and one at 0 cannot be made.
  const int n = 30;
  const Pattern p = banded(n, 0);
  SparseCholesky chol(n, p.col_start, p.row_index, CholeskyOptions{.ordering = Ordering::amd});
  for (int c = 0; c < n; ++c) chol.values()[static_cast<std::size_t>(c)] = c + 1 < n ? 1.0 : -1e-14;
  CHECK_FALSE(chol.factorize());
  chol.values()[static_cast<std::size_t>(n - 1)] = 1e-14;
  REQUIRE(chol.factorize());
  CHECK(chol.residual_bound() < 1e-20);
}

TEST_CASE("factorize_extended: proves what a double factor cannot, and never an indefinite matrix") {
  // The Laplacian of a path (singular: its null vector is the constant) with ±δ added to its first diagonal
  // entry through the trailing parts: λ_min ≈ ±δ/n, far below what a double factor resolves.
  const int n = 50;
  Pattern p = banded(n, 1);
  std::vector<double> values;
  for (int c = 0; c < n; ++c) {
    if (c > 0) values.push_back(-1.0);
    values.push_back(c == 0 || c == n - 1 ? 1.0 : 2.0);
  }
  const double delta = 1e-18;
  for (const double sign : {1.0, -1.0}) {
    CAPTURE(sign);
    SparseCholesky chol(n, p.col_start, p.row_index,
                        CholeskyOptions{.ordering = Ordering::amd, .kind = FactorKind::supernodal});
    chol.values() = values;
    std::vector<double> trailing(values.size(), 0.0);
    trailing[0] = sign * delta;
    const bool ok = chol.factorize_extended(trailing);
    if (sign > 0) {
      // Positive definite (λ_min ≈ δ/n = 2e-20): factored, with a residual far below λ_min.
      REQUIRE(ok);
      CHECK(chol.extended_residual_bound(trailing) < 1e-25);
    } else {
      // Indefinite (λ_min ≈ −δ/n): either the factorization breaks down or its residual is at least |λ_min|,
      // so no proof of A ⪰ 0 can come out of it.
      CHECK((!ok || chol.extended_residual_bound(trailing) >= 0.5 * delta / n));
    }
  }
  // extended_residual_bound refuses to run without a factor.
  SparseCholesky fresh(n, p.col_start, p.row_index,
                       CholeskyOptions{.ordering = Ordering::amd, .kind = FactorKind::supernodal});
  CHECK_THROWS_AS((void)fresh.extended_residual_bound(std::vector<double>(values.size(), 0.0)),
                  std::logic_error);
  SparseCholesky simplicial(n, p.col_start, p.row_index, CholeskyOptions{.ordering = Ordering::amd});
  CHECK_THROWS_AS((void)simplicial.factorize_extended(std::vector<double>(values.size(), 0.0)),
                  std::logic_error);
}

namespace {

// A⁻¹b densely (Gaussian elimination on the full matrix of the upper pattern): the reference of the solves.
std::vector<double> dense_solve(const Pattern& p, const std::vector<double>& values, int n,
                                std::vector<double> b) {
  std::vector<std::vector<double>> A(static_cast<std::size_t>(n),
                                     std::vector<double>(static_cast<std::size_t>(n)));
  for (int c = 0; c < n; ++c)
    for (int q = p.col_start[c]; q < p.col_start[c + 1]; ++q)
      A[p.row_index[q]][c] = A[c][p.row_index[q]] = values[static_cast<std::size_t>(q)];
  for (int k = 0; k < n; ++k)
    for (int i = k + 1; i < n; ++i) {
      const double f = A[i][k] / A[k][k];
      for (int j = k; j < n; ++j) A[i][j] -= f * A[k][j];
      b[i] -= f * b[k];
    }
  for (int i = n - 1; i >= 0; --i) {
    for (int j = i + 1; j < n; ++j) b[i] -= A[i][j] * b[j];
    b[i] /= A[i][i];
  }
  return b;
}

}  // namespace

TEST_CASE(
    "orderings, kinds and solves: every ordering and factor kind solves A x = b; a workspace per thread") {
  const int n = 50, bw = 3;
  keel::core::Rng gen(5);
  const Pattern p = banded(n, bw);
  const std::vector<double> values = integer_product(p, n, bw, gen);
  std::vector<double> b(static_cast<std::size_t>(2 * n));
  for (double& x : b) x = gen.uniform() - 0.5;
  const std::vector<double> x0 = dense_solve(p, values, n, {b.begin(), b.begin() + n});
  const std::vector<double> x1 = dense_solve(p, values, n, {b.begin() + n, b.end()});
  for (const Ordering o :
       {Ordering::automatic, Ordering::amd, Ordering::metis, Ordering::nesdis, Ordering::natural})
    for (const FactorKind kind : {FactorKind::automatic, FactorKind::supernodal, FactorKind::simplicial})
      for (const bool ll : {true, false}) {
        CAPTURE(to_string(o));
        SparseCholesky chol(n, p.col_start, p.row_index, {.ordering = o, .kind = kind, .ll = ll});
        chol.values() = values;
        REQUIRE(chol.factorize());
        CHECK(chol.failed_row() == -1);
        if (kind == FactorKind::supernodal) CHECK(chol.supernodal());
        if (kind == FactorKind::simplicial) CHECK_FALSE(chol.supernodal());
        if (o == Ordering::natural) {
          CHECK(chol.ordering_name() == "natural");
          for (int k = 0; k < n; ++k) CHECK(chol.permutation()[k] == k);
        }
        // The permutation is one.
        std::vector<int> seen(static_cast<std::size_t>(n), 0);
        for (int k = 0; k < n; ++k) ++seen[static_cast<std::size_t>(chol.permutation()[k])];
        CHECK(std::count(seen.begin(), seen.end(), 1) == n);
        if (chol.supernodal()) {
          const auto s = chol.supernodes();
          REQUIRE(s.count > 0);
          CHECK(s.super[0] == 0);
          CHECK(s.super[s.count] == n);
        } else {
          CHECK_THROWS_AS((void)chol.supernodes(), std::logic_error);
        }
        std::vector<double> x(static_cast<std::size_t>(2 * n));
        chol.solve(b.data(), x.data(), 2);
        keel::linalg::SolveWorkspace ws;
        for (int round = 0; round < 2; ++round) {  // the workspace is reused
          double* rhs = ws.right_hand_sides(n, 2);
          for (std::size_t k = 0; k < b.size(); ++k) CHECK(rhs[k] == 0.0);
          std::copy(b.begin(), b.end(), rhs);
          int ld = 0;
          const double* y = chol.solve(ws, &ld);
          REQUIRE(ld >= n);
          for (int i = 0; i < n; ++i) {
            CHECK(x[static_cast<std::size_t>(i)] ==
                  doctest::Approx(x0[static_cast<std::size_t>(i)]).epsilon(1e-12));
            CHECK(x[static_cast<std::size_t>(n + i)] ==
                  doctest::Approx(x1[static_cast<std::size_t>(i)]).epsilon(1e-12));
            CHECK(y[i] == doctest::Approx(x0[static_cast<std::size_t>(i)]).epsilon(1e-12));
            CHECK(y[ld + i] == doctest::Approx(x1[static_cast<std::size_t>(i)]).epsilon(1e-12));
          }
        }
      }
}

TEST_CASE(
    "a matrix that is not positive definite: factorize() is false and names the row; names round-trip") {
  const int n = 6;
  Pattern p = banded(n, 0);
  for (const FactorKind kind : {FactorKind::supernodal, FactorKind::simplicial}) {
    SparseCholesky chol(n, p.col_start, p.row_index, {.ordering = Ordering::natural, .kind = kind});
    for (int c = 0; c < n; ++c) chol.values()[static_cast<std::size_t>(c)] = c == 3 ? -1.0 : 2.0;
    CHECK_FALSE(chol.factorize());
    CHECK(chol.failed_row() == 3);
  }
  for (const Ordering o :
       {Ordering::automatic, Ordering::amd, Ordering::metis, Ordering::nesdis, Ordering::natural})
    CHECK(keel::linalg::ordering_from_string(to_string(o)) == o);
  CHECK(to_string(Ordering::automatic) == "auto");
  CHECK_THROWS_WITH_AS((void)keel::linalg::ordering_from_string("colamd"),
                       "unknown linalg::Ordering 'colamd' (valid: auto, amd, metis, nesdis, natural)",
                       std::invalid_argument);
  CHECK_THROWS_AS(SparseCholesky(3, {0, 1, 2}, {0, 1}),
                  std::invalid_argument);  // col_start of the wrong size
  keel::linalg::SolveWorkspace ws;
  SparseCholesky chol(n, p.col_start, p.row_index);
  int ld = 0;
  CHECK_THROWS_AS((void)chol.solve(ws, &ld), std::logic_error);  // no right-hand sides yet
}

namespace {

// S = L − c·I with L the path graph's Laplacian on n vertices (eigenvalues 2 − 2 cos(πk/n), the smallest 0),
// so λ_min(S) = −c exactly: S + η·I ⪰ 0 iff η ≥ c. Entries exact in double (c a power of two times an
// integer).
keel::linalg::DoubleDoubleSymmetric shifted_path(int n, double c) {
  keel::linalg::DoubleDoubleSymmetric S;
  S.n = n;
  S.col_start.push_back(0);
  for (int j = 0; j < n; ++j) {
    if (j > 0) {
      S.row_index.push_back(j - 1);
      S.hi.push_back(-1.0);
    }
    S.row_index.push_back(j);
    S.hi.push_back((j == 0 || j == n - 1 ? 1.0 : 2.0) - c);
    S.col_start.push_back(static_cast<int>(S.row_index.size()));
  }
  S.lo.assign(S.hi.size(), 0.0);
  S.error.assign(S.hi.size(), 0.0);
  return S;
}

}  // namespace

TEST_CASE("shift_search: the decade found is bisected; no shift below λ_min's is ever proven") {
  const int n = 40;
  const std::vector<char> all(static_cast<std::size_t>(n), 1);
  for (const double c : {0.0123046875, 0.3359375, 2.75}) {
    CAPTURE(c);
    const double reference = 1e-4;  // decades 1e-3, 1e-2, …, 10
    keel::linalg::ShiftedPsdProver plain(shifted_path(n, c), all), refined(shifted_path(n, c), all);
    const keel::linalg::ShiftSearch a = plain.shift_search(-1.0, reference, 5);
    const keel::linalg::ShiftSearch b = refined.shift_search(-1.0, reference, 5, 3);
    REQUIRE(a.proven);
    REQUIRE(b.proven);
    CHECK(!b.within_tolerance);
    // Sound: every proven shift is at least −λ_min.
    CHECK(a.shift >= c);
    CHECK(b.shift >= c);
    CHECK(b.largest_failed < b.shift);
    // The decade is bisected three times in log scale: within 10^(1/8) of the smallest provable shift (c, up
    // to the proof's margin), never above the unrefined one, three attempts more.
    CHECK(b.shift <= a.shift);
    CHECK(b.shift <= c * std::pow(10.0, 0.125) * (1 + 1e-6));
    CHECK(b.attempts == a.attempts + 3);
    CHECK(b.proof.proven);
  }
  // Nothing to refine when no decade is proven.
  keel::linalg::ShiftedPsdProver none(shifted_path(n, 1e4), all);
  const keel::linalg::ShiftSearch s = none.shift_search(-1.0, 1e-4, 5, 3);
  CHECK(!s.proven);
  CHECK(s.attempts == 5);
}
