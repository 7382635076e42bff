// linalg::SparseCholesky::residual_bound (the measured residual behind every certificate of psd_proof.hpp)
// against the residual computed EXACTLY: for small random and adversarial matrices A = hi + lo (a
// double-double A, as the prover forms it) and the computed factor L̂, every entry of P A Pᵀ − L̂L̂ᵀ is
// summed without rounding as a floating-point expansion (Shewchuk, "Adaptive precision floating-point
// arithmetic and fast robust geometric predicates", DCG 1997: TwoSum and the fused multiply-add's exact
// product make each partial sum an exact nonoverlapping expansion; no value here comes near underflow or
// overflow). The bound must be at least the exact max_i Σ_j |R_ij| ≥ ‖R‖₂, compared exactly too.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"
#include "pgo/certified.hpp"
#include "linalg/sparse_cholesky.hpp"

using keel::linalg::CholeskyOptions;
using keel::linalg::FactorKind;
using keel::linalg::Ordering;
using keel::linalg::SparseCholesky;

namespace {

// An exact sum of doubles: components nonoverlapping, in increasing magnitude, zeros removed.
using Expansion = std::vector<double>;

// Shewchuk's Grow-Expansion: e + b exactly (TwoSum is exact in round-to-nearest).
Expansion grow(const Expansion& e, double b) {
  Expansion h;
  h.reserve(e.size() + 1);
  double q = b;
  for (const double x : e) {
    const double s = q + x;
    const double bv = s - q;
    const double err = (q - (s - bv)) + (x - bv);
    if (err != 0.0) h.push_back(err);
    q = s;
  }
  if (q != 0.0 || h.empty()) h.push_back(q);
  return h;
}
Expansion add(Expansion a, const Expansion& b) {
  for (const double x : b) a = grow(a, x);
  return a;
}
Expansion add_product(const Expansion& e, double a, double b) {  // e + a·b exactly
  const double p = a * b;
  return grow(grow(e, p), std::fma(a, b, -p));
}
// The sign of a nonoverlapping expansion is the sign of its largest component.
int sign(const Expansion& e) {
  for (auto it = e.rbegin(); it != e.rend(); ++it)
    if (*it != 0.0) return *it > 0.0 ? 1 : -1;
  return 0;
}
Expansion negate(Expansion e) {
  for (double& x : e) x = -x;
  return e;
}
Expansion abs(const Expansion& e) { return sign(e) < 0 ? negate(e) : e; }
// e·b exactly.
Expansion scale(const Expansion& e, double b) {
  Expansion out{0.0};
  for (const double x : e) out = add_product(out, x, b);
  return out;
}
Expansion square(const Expansion& e) {
  Expansion out{0.0};
  for (const double x : e) out = add(out, scale(e, x));
  return out;
}
// a ≥ b exactly.
bool at_least(const Expansion& a, const Expansion& b) { return sign(add(a, negate(b))) >= 0; }

struct Matrix {
  int n = 0;
  std::vector<int> col_start{0}, row_index;  // upper triangle, rows ascending, diagonal last
  std::vector<double> hi, lo;
};

// A dense or random sparse pattern of order n (diagonal always present).
Matrix pattern(int n, double density, keel::core::Rng& gen) {
  const auto u = [](keel::core::Rng& r) { return r.uniform(); };
  Matrix m;
  m.n = n;
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < c; ++r)
      if (u(gen) < density) m.row_index.push_back(r);
    m.row_index.push_back(c);
    m.col_start.push_back(static_cast<int>(m.row_index.size()));
  }
  return m;
}

// Entry (r, c) of the dense symmetric matrix `a` into the pattern, its trailing part `lo` (|lo| ≤ u|hi|
// for a double-double A, or zero).
void fill(Matrix& m, const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& lo) {
  m.hi.clear();
  m.lo.clear();
  for (int c = 0; c < m.n; ++c)
    for (int q = m.col_start[static_cast<std::size_t>(c)]; q < m.col_start[static_cast<std::size_t>(c) + 1];
         ++q) {
      const int r = m.row_index[static_cast<std::size_t>(q)];
      m.hi.push_back(a[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)]);
      m.lo.push_back(lo[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)]);
    }
}

// The exact max_i Σ_j |(P A Pᵀ − L̂L̂ᵀ)_ij| with A = hi + lo (lo ignored when `with_lo` is false).
Expansion exact_residual_row_sum(const Matrix& m, const SparseCholesky& chol, bool with_lo) {
  std::vector<int> lp, li, perm;
  std::vector<double> lx;
  chol.computed_factor(lp, li, lx, perm);
  const auto n = static_cast<std::size_t>(m.n);
  // Dense copies (the matrices are small): A in original indices, L̂ in permuted ones.
  std::vector<std::vector<double>> A(n, std::vector<double>(n, 0.0)), Alo = A, L = A;
  for (int c = 0; c < m.n; ++c)
    for (int q = m.col_start[static_cast<std::size_t>(c)]; q < m.col_start[static_cast<std::size_t>(c) + 1];
         ++q) {
      const auto r = static_cast<std::size_t>(m.row_index[static_cast<std::size_t>(q)]);
      const auto cc = static_cast<std::size_t>(c);
      A[r][cc] = A[cc][r] = m.hi[static_cast<std::size_t>(q)];
      if (with_lo) Alo[r][cc] = Alo[cc][r] = m.lo[static_cast<std::size_t>(q)];
    }
  for (std::size_t j = 0; j < n; ++j)
    for (int q = lp[j]; q < lp[j + 1]; ++q)
      L[static_cast<std::size_t>(li[static_cast<std::size_t>(q)])][j] = lx[static_cast<std::size_t>(q)];
  Expansion best{0.0};
  for (std::size_t i = 0; i < n; ++i) {
    Expansion row{0.0};
    for (std::size_t j = 0; j < n; ++j) {
      const auto pi = static_cast<std::size_t>(perm[i]), pj = static_cast<std::size_t>(perm[j]);
      Expansion r = grow(grow(Expansion{0.0}, A[pi][pj]), Alo[pi][pj]);
      for (std::size_t k = 0; k < n; ++k)
        if (L[i][k] != 0.0 && L[j][k] != 0.0) r = add_product(r, -L[i][k], L[j][k]);
      row = add(row, abs(r));
    }
    if (at_least(row, best)) best = row;
  }
  return best;
}

using Dense = std::vector<std::vector<double>>;

// The random and adversarial families: well and badly conditioned, badly scaled, near singular.
// keel's generator throughout: std's distributions are implementation-defined.
Dense family(int kind, int n, keel::core::Rng& gen) {
  const auto z = [](keel::core::Rng& r) { return r.normal(); };
  const auto ex = [](keel::core::Rng& r) { return std::min(20, static_cast<int>(41 * r.uniform()) - 20); };
  const auto N = static_cast<std::size_t>(n);
  Dense a(N, std::vector<double>(N, 0.0));
  Dense b(N, std::vector<double>(N, 0.0));
  for (auto& row : b)
    for (double& x : row) x = z(gen);
  auto gram = [&](double shift) {
    for (std::size_t i = 0; i < N; ++i)
      for (std::size_t j = 0; j < N; ++j) {
        double s = 0.0;
        for (std::size_t k = 0; k < N; ++k) s += b[i][k] * b[j][k];
        a[i][j] = s;
      }
    for (std::size_t i = 0; i < N; ++i) a[i][i] += shift;
  };
  switch (kind) {
    case 0:  // B Bᵀ + I: well conditioned
      gram(1.0);
      break;
    case 1:  // B Bᵀ with a tiny shift: eigenvalues down to ~1e-12 relative, pivots near breakdown
      for (std::size_t j = 0; j < N; ++j) b[N - 1][j] = b[0][j] * (1.0 + 1e-9);
      gram(1e-12);
      break;
    case 2: {  // Hilbert matrix: condition number ~1e10 at n = 8
      for (std::size_t i = 0; i < N; ++i)
        for (std::size_t j = 0; j < N; ++j) a[i][j] = 1.0 / static_cast<double>(i + j + 1);
      for (std::size_t i = 0; i < N; ++i) a[i][i] += 1e-14;
      break;
    }
    case 3: {  // B Bᵀ + I scaled by random powers of two (1e±6): the scaling does not hide the residual
      gram(1.0);
      std::vector<double> d(N);
      for (double& x : d) x = std::ldexp(1.0, ex(gen));
      for (std::size_t i = 0; i < N; ++i)
        for (std::size_t j = 0; j < N; ++j) a[i][j] *= d[i] * d[j];
      break;
    }
    case 4: {  // a graph Laplacian plus a tiny diagonal (like the certificate's S + ηD): entries cancel
      const auto w = [](keel::core::Rng& r) { return r.uniform(0.1, 10.0); };
      for (std::size_t i = 0; i + 1 < N; ++i) {
        for (std::size_t j = i + 1; j < N; ++j)
          if (j == i + 1 || z(gen) > 0.5) {
            const double x = w(gen);
            a[i][j] -= x, a[j][i] -= x, a[i][i] += x, a[j][j] += x;
          }
      }
      for (std::size_t i = 0; i < N; ++i) a[i][i] += 1e-9 * (1.0 + static_cast<double>(i));
      break;
    }
    default: {  // large entries with huge cancellation: 1e8·vvᵀ + B Bᵀ·1e-4 + 1e-6 I
      std::vector<double> v(N);
      for (double& x : v) x = z(gen);
      gram(0.0);
      for (std::size_t i = 0; i < N; ++i)
        for (std::size_t j = 0; j < N; ++j) a[i][j] = 1e8 * v[i] * v[j] + 1e-4 * a[i][j];
      for (std::size_t i = 0; i < N; ++i) a[i][i] += 1e-6;
      break;
    }
  }
  // Symmetric to the last bit (the formulas above are, but make sure).
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < i; ++j) a[i][j] = a[j][i];
  return a;
}

}  // namespace

TEST_CASE(
    "residual_bound is at least the exactly computed residual norm on small random and adversarial "
    "matrices") {
  keel::core::Rng gen(20190101);
  const auto order = [](keel::core::Rng& r) { return std::min(9, 2 + static_cast<int>(8 * r.uniform())); };
  const auto unit = [](keel::core::Rng& r) { return r.uniform(-1.0, 1.0); };
  constexpr double u = 0x1p-53;
  int checked = 0, with_residual = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const int kind = trial % 6;
    const int n = order(gen);
    const bool supernodal = trial % 2 == 0;
    const double density = (trial / 2) % 3 == 0 ? 1.0 : 0.5;
    Matrix m = pattern(n, density, gen);
    const Dense a = family(kind, n, gen);
    // Entries outside the pattern are dropped (the matrix is then another symmetric one, maybe indefinite:
    // factorize() decides); trailing parts |lo| ≤ u|hi| as a double-double A has.
    Dense lo(a.size(), std::vector<double>(a.size(), 0.0));
    for (std::size_t i = 0; i < a.size(); ++i)
      for (std::size_t j = i; j < a.size(); ++j) lo[i][j] = lo[j][i] = unit(gen) * u * std::abs(a[i][j]);
    fill(m, a, lo);
    SparseCholesky chol(n, m.col_start, m.row_index,
                        CholeskyOptions{.ordering = Ordering::automatic,
                                        .kind = supernodal ? FactorKind::supernodal : FactorKind::automatic});
    chol.values() = m.hi;
    if (!chol.factorize()) continue;
    for (const bool with_lo : {false, true}) {
      const double bound = with_lo ? chol.residual_bound(&m.lo) : chol.residual_bound();
      const double entrywise =
          with_lo ? chol.residual_bound_entrywise(&m.lo) : chol.residual_bound_entrywise();
      const Expansion exact = exact_residual_row_sum(m, chol, with_lo);
      INFO("trial " << trial << " (family " << kind << ", n = " << n << ", supernodal " << supernodal
                    << ", trailing " << with_lo << "): bound " << bound << ", entrywise " << entrywise
                    << ", exact ‖R‖∞ ≈ " << exact.back());
      CHECK(at_least(Expansion{bound}, exact));
      CHECK(at_least(Expansion{entrywise}, exact));
      ++checked;
      if (sign(exact) > 0) ++with_residual;
    }
  }
  // Most cases factorize, and most leave a non-zero residual (the test is not vacuous).
  CHECK(checked >= 600);
  CHECK(with_residual >= checked / 2);
}

TEST_CASE(
    "the exact residual of the test is exact: an exactly representable factor leaves none, a perturbed "
    "A leaves exactly the perturbation") {
  // A diagonal of squares: the computed factor is exact whatever the ordering, so the exact residual is 0 …
  Matrix m;
  m.n = 3;
  m.col_start = {0, 1, 3, 6};
  m.row_index = {0, 0, 1, 0, 1, 2};
  const Dense a = {{4, 2, -2}, {2, 10, 5}, {-2, 5, 18}};  // a factor with irrational entries
  const Dense exact_a = {{4, 0, 0}, {0, 9, 0}, {0, 0, 16}};
  const Dense zero(3, std::vector<double>(3, 0.0));
  fill(m, exact_a, zero);
  SparseCholesky chol(3, m.col_start, m.row_index, CholeskyOptions{.ordering = Ordering::automatic});
  chol.values() = m.hi;
  REQUIRE(chol.factorize());
  CHECK(sign(exact_residual_row_sum(m, chol, false)) == 0);
  // … and a trailing part δ on one diagonal entry leaves exactly |δ| in that row.
  Dense lo = zero;
  lo[2][2] = 0x1p-60;
  fill(m, exact_a, lo);
  const Expansion r = exact_residual_row_sum(m, chol, true);
  CHECK(at_least(r, Expansion{0x1p-60}));
  CHECK(at_least(Expansion{0x1p-60}, r));
  CHECK(chol.residual_bound(&m.lo) >= 0x1p-60);
  // A matrix whose factor is irrational has a non-zero exact residual, which the bound covers.
  fill(m, a, zero);
  chol.values() = m.hi;
  REQUIRE(chol.factorize());
  const Expansion ra = exact_residual_row_sum(m, chol, false);
  CHECK(sign(ra) >= 0);
  CHECK(at_least(Expansion{chol.residual_bound()}, ra));
}

namespace {

// The isotropic cost F (pgo/certified.hpp) of planar poses, exactly: every residual entry, its square and the
// weighted sum as expansions. Pose 0 must be the identity, so that the certificate's gauge (pose 0's frame)
// is applied without rounding.
Expansion exact_isotropic_cost(const keel::graph::PoseGraph2D& g, const std::vector<keel::lie::SE2>& x) {
  Expansion f{0.0};
  for (const auto& e : g.edges) {
    const keel::pgo::IsotropicWeights w = keel::pgo::isotropic_weights(e);
    const auto Ri = x[static_cast<std::size_t>(e.i)].rotation(),
               Rj = x[static_cast<std::size_t>(e.j)].rotation();
    const auto ti = x[static_cast<std::size_t>(e.i)].translation(),
               tj = x[static_cast<std::size_t>(e.j)].translation();
    const auto Rm = e.measurement.rotation();
    const auto tm = e.measurement.translation();
    Expansion rot{0.0}, trans{0.0};
    for (int a = 0; a < 2; ++a) {
      for (int c = 0; c < 2; ++c) {
        Expansion r = grow(Expansion{0.0}, Rj(a, c));
        for (int m = 0; m < 2; ++m) r = add_product(r, -Ri(a, m), Rm(m, c));
        rot = add(rot, square(r));
      }
      Expansion t = grow(grow(Expansion{0.0}, tj(a)), -ti(a));
      for (int m = 0; m < 2; ++m) t = add_product(t, -Ri(a, m), tm(m));
      trans = add(trans, square(t));
    }
    f = add(f, add(scale(rot, w.kappa), scale(trans, w.tau)));
  }
  return f;
}

}  // namespace

TEST_CASE("the certificate's upper end is at least F computed exactly, also where the residuals cancel") {
  keel::core::Rng gen(5);
  const auto u = [](keel::core::Rng& r) { return r.uniform(-1.0, 1.0); };
  int below = 0;  // cases where F rounded to nearest lies below the exact F (the upper end must not)
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 4 + trial % 5;
    const double noise = trial % 3 == 0 ? 0.0 : trial % 3 == 1 ? 1e-9 : 0.05;
    std::vector<keel::lie::SE2> truth{keel::lie::SE2::identity()};
    for (int i = 1; i < n; ++i) truth.push_back(keel::lie::SE2(5.0 * u(gen), 5.0 * u(gen), 3.0 * u(gen)));
    keel::graph::PoseGraph2D g;
    g.poses = truth;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        if (j != i + 1 && u(gen) < 0.0) continue;
        const keel::lie::SE2 z =
            truth[static_cast<std::size_t>(i)].inverse() * truth[static_cast<std::size_t>(j)];
        keel::graph::Edge2 e;
        e.i = i, e.j = j;
        e.measurement = keel::lie::SE2(z.translation().x() + noise * u(gen),
                                       z.translation().y() + noise * u(gen), z.angle() + noise * u(gen));
        e.information =
            keel::lie::Mat3(Eigen::Vector3d(1.0 + u(gen) * u(gen), 2.0, 3.0 + u(gen)).asDiagonal());
        g.edges.push_back(e);
      }
    // At the truth (the residuals of the noise-free graphs are rounding: F ~ 1e-30) and at the solution.
    std::vector<std::vector<keel::lie::SE2>> points{truth};
    if (noise > 0.0) {
      auto solved = keel::pgo::solve_certified(g).poses;
      const keel::lie::SE2 inv0 = solved[0].inverse();
      for (auto& p : solved) p = inv0 * p;
      solved[0] = keel::lie::SE2::identity();
      points.push_back(solved);
    }
    for (const auto& x : points) {
      const keel::pgo::Certificate c = keel::pgo::certify(g, x, 1e-6);
      const Expansion exact = exact_isotropic_cost(g, x);
      INFO("trial " << trial << ", noise " << noise << ": upper " << c.bound.upper << ", exact ≈ "
                    << exact.back() << ", nearest " << keel::pgo::isotropic_cost(g, x));
      CHECK(at_least(Expansion{c.bound.upper}, exact));
      // Not loose: within 1e-12 relative, or the residuals' rounding where F is of that order.
      CHECK(c.bound.upper <= exact.back() * (1.0 + 1e-12) + 1e-28);
      if (!at_least(Expansion{keel::pgo::isotropic_cost(g, x)}, exact)) ++below;
    }
  }
  MESSAGE("F rounded to nearest was below the exact F in " << below << " cases");
}
