// linalg::SparseCholesky's rigorous bounds on the residual of its computed factor (Higham's worst case and
// the residual measured in doubled precision), the factor itself for the tests, and the factorization in
// double-double with its residual bound (sparse_cholesky.hpp).
#include <cholmod.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "linalg/double_double.hpp"
#include "linalg/sparse_cholesky_impl.hpp"

namespace keel::linalg {

namespace {
constexpr double kU = std::numeric_limits<double>::epsilon() / 2;
}  // namespace

double SparseCholesky::backward_error_bound() const {
  const LowerFactor& L = impl_->lower_factor();
  const std::size_t n = static_cast<std::size_t>(n_);
  std::vector<double> col_abs(n, 0.0), z(n, 0.0);
  std::vector<int> row_count(n, 0);
  for (std::size_t j = 0; j < n; ++j)
    for (int q = L.p[j]; q < L.p[j + 1]; ++q)
      if (L.x[static_cast<std::size_t>(q)] != 0.0) {  // an exact zero (a relaxed supernode's padding) adds no
                                                      // rounding
        col_abs[j] += std::abs(L.x[static_cast<std::size_t>(q)]);
        ++row_count[static_cast<std::size_t>(L.i[static_cast<std::size_t>(q)])];
      }
  for (std::size_t j = 0; j < n; ++j)
    for (int q = L.p[j]; q < L.p[j + 1]; ++q)
      z[static_cast<std::size_t>(L.i[static_cast<std::size_t>(q)])] +=
          std::abs(L.x[static_cast<std::size_t>(q)]) * col_abs[j];
  double bound = 0.0;
  for (std::size_t r = 0; r < n; ++r) {
    const double k1 = row_count[r] + 1.0;
    bound = std::max(bound, k1 * kU / (1.0 - k1 * kU) * z[r]);
  }
  return bound;
}

namespace {

// P A Pᵀ's lower triangle by column (rows unsorted), from the stored upper triangle of A (Perm[k] = A's
// index of row k), with the trailing parts of a double-double A when given.
struct PermutedLower {
  std::vector<int> p, i;
  std::vector<double> x, xl;
};
PermutedLower permuted_lower(int n, const std::vector<int>& col_start, const std::vector<int>& row_index,
                             const std::vector<double>& values, const std::vector<double>* trailing,
                             const int* perm) {
  const auto N = static_cast<std::size_t>(n);
  std::vector<int> iperm(N);
  for (int k = 0; k < n; ++k) iperm[static_cast<std::size_t>(perm ? perm[k] : k)] = k;
  PermutedLower A;
  A.p.assign(N + 1, 0);
  auto each = [&](auto&& f) {
    for (int c = 0; c < n; ++c)
      for (int q = col_start[static_cast<std::size_t>(c)]; q < col_start[static_cast<std::size_t>(c) + 1];
           ++q)
        f(iperm[static_cast<std::size_t>(row_index[static_cast<std::size_t>(q)])],
          iperm[static_cast<std::size_t>(c)], static_cast<std::size_t>(q));
  };
  each([&](int a, int b, std::size_t) { ++A.p[static_cast<std::size_t>(std::min(a, b)) + 1]; });
  for (std::size_t j = 0; j < N; ++j) A.p[j + 1] += A.p[j];
  A.i.resize(static_cast<std::size_t>(A.p[N]));
  A.x.resize(A.i.size());
  A.xl.assign(A.i.size(), 0.0);
  std::vector<int> fill(A.p.begin(), A.p.end() - 1);
  each([&](int a, int b, std::size_t q) {
    const auto at = static_cast<std::size_t>(fill[static_cast<std::size_t>(std::min(a, b))]++);
    A.i[at] = std::max(a, b);
    A.x[at] = values[q];
    if (trailing) A.xl[at] = (*trailing)[q];
  });
  return A;
}

RowIndex row_index_of(int n, const std::vector<int>& Lp, const std::vector<int>& Li) {
  const auto N = static_cast<std::size_t>(n);
  RowIndex R;
  R.p.assign(N + 1, 0);
  for (const int i : Li) ++R.p[static_cast<std::size_t>(i) + 1];
  for (std::size_t j = 0; j < N; ++j) R.p[j + 1] += R.p[j];
  R.q.resize(Li.size());
  R.col.resize(Li.size());
  std::vector<int> fill(R.p.begin(), R.p.end() - 1);
  for (int k = 0; k < n; ++k)
    for (int q = Lp[static_cast<std::size_t>(k)]; q < Lp[static_cast<std::size_t>(k) + 1]; ++q) {
      const auto at =
          static_cast<std::size_t>(fill[static_cast<std::size_t>(Li[static_cast<std::size_t>(q)])]++);
      R.q[at] = q;
      R.col[at] = k;
    }
  return R;
}

// A rigorous bound on ‖L Lᵀ − A‖₂ for L = x (+ xl, the trailing parts of a double-double factor, when given)
// on the pattern (Lp, Li) and A = A.x + A.xl. Every product is split into exact parts (fma): x_ik x_jk, and
// with xl also x_ik xl_jk and xl_ik x_jk; xl_ik xl_jk (below u²|x_ik x_jk|) is rounded once, inside the error
// term. The parts are summed per entry by Ogita, Rump and Oishi's Sum2 (SIAM J. Sci. Comput. 2005): hi the
// floating sum of the leading parts, lo the floating sum of TwoSum's exact errors and the trailing parts.
// Each lo term is below u(|partial sum| + |part|) + |trailing part| ≤ 2u Σ|terms|, so m parts leave hi + lo
// within (m + 1) γ_{m+1} 2u Σ|terms| of the exact sum; |R_ij| ≤ |hi + lo| plus that (doubled for the rounding
// of Σ|terms| itself), and ‖R‖₂ ≤ max_i Σ_j |R_ij|.
// Extended: xl is given (a double-double factor). A template so that the double case's inner loop stays small
// enough to inline.
template <bool Extended>
double residual_norm_bound(int n, const std::vector<int>& Lp, const std::vector<int>& Li, const double* x,
                           const double* xl, const RowIndex& rows, const PermutedLower& A) {
  constexpr double u = std::numeric_limits<double>::epsilon() / 2;
  const auto N = static_cast<std::size_t>(n);
  std::vector<double> hi(N, 0.0), lo(N, 0.0), mag(N, 0.0), z(N, 0.0);
  std::vector<int> terms(N, 0), touched;
  touched.reserve(N);
  // Double factors: Sum2 (above). Double-double factors, whose residual is of order u², need an accumulation
  // error below that: the sum is kept normalized (dd_add, error below 4u²(|partial sum| + |part|) per
  // addition), and `partial` accumulates those magnitudes for the bound.
  std::vector<double> partial(Extended ? N : 0, 0.0);
  auto add = [&](std::size_t i, double ph, double pl) __attribute__((always_inline)) {
    if (terms[i] == 0) touched.push_back(static_cast<int>(i));
    ++terms[i];
    mag[i] += std::abs(ph);
    if constexpr (Extended) {
      const DD sum = dd_add(DD{hi[i], lo[i]}, DD{ph, pl});
      partial[i] += std::abs(hi[i]) + std::abs(ph);
      hi[i] = sum.hi;
      lo[i] = sum.lo;
      return;
    }
    const double s = hi[i] + ph;
    const double t = s - hi[i];
    lo[i] += ((hi[i] - (s - t)) + (ph - t)) + pl;
    hi[i] = s;
  };
  for (int j = 0; j < n; ++j) {
    const auto J = static_cast<std::size_t>(j);
    for (int r = rows.p[J]; r < rows.p[J + 1]; ++r) {
      const auto qj = static_cast<std::size_t>(rows.q[static_cast<std::size_t>(r)]);
      const auto k = static_cast<std::size_t>(rows.col[static_cast<std::size_t>(r)]);
      const double ljk = x[qj], ljk_lo = Extended ? xl[qj] : 0.0;
      if (ljk == 0.0 && ljk_lo == 0.0) continue;
      for (int q = static_cast<int>(qj); q < Lp[k + 1]; ++q) {  // rows i ≥ j of column k
        const auto i = static_cast<std::size_t>(Li[static_cast<std::size_t>(q)]);
        const double lik = x[static_cast<std::size_t>(q)];
        const DD p = dd_prod(lik, ljk);
        add(i, p.hi, p.lo);
        if constexpr (Extended) {
          const double lik_lo = xl[static_cast<std::size_t>(q)];
          const DD a = dd_prod(lik, ljk_lo), b = dd_prod(lik_lo, ljk);
          add(i, a.hi, a.lo);
          add(i, b.hi, b.lo + lik_lo * ljk_lo);
        }
      }
    }
    for (int q = A.p[J]; q < A.p[J + 1]; ++q) {
      const auto i = static_cast<std::size_t>(A.i[static_cast<std::size_t>(q)]);
      add(i, -A.x[static_cast<std::size_t>(q)], -A.xl[static_cast<std::size_t>(q)]);
    }
    for (const int ti : touched) {
      const auto i = static_cast<std::size_t>(ti);
      // hi and lo are not normalized (they may nearly cancel): their sum is rounded once (relative error u,
      // covered by the factor 1 + 2u).
      const double m1 = terms[i] + 1.0;
      // Sum2: (m + 1)γ_{m+1}·2u·Σ|terms|, doubled; normalized double-double: 4u²·Σ(|partial sum| + |part|),
      // doubled, plus u² of the largest trailing product (x_lo·x_lo, rounded once) per part: below u²·mag.
      const double err = Extended ? 8.0 * u * u * (partial[i] + mag[i]) * (1.0 + m1 * u) + u * u * mag[i]
                                  : 4.0 * m1 * (m1 * u / (1.0 - m1 * u)) * u * mag[i];
      const double rij = std::abs(hi[i] + lo[i]) * (1.0 + 2.0 * u) + err;
      z[i] += rij;
      if (i != J) z[J] += rij;
      hi[i] = lo[i] = mag[i] = 0.0;
      if constexpr (Extended) partial[i] = 0.0;
      terms[i] = 0;
    }
    touched.clear();
  }
  // Each z_i is a floating sum of at most 2n non-negative terms, each computed with relative error ≤ 3u: the
  // true row sum is at most z_i (1 + 4u) / (1 − γ_{2n}).
  const double g = 2.0 * n * u / (1.0 - 2.0 * n * u);
  return *std::max_element(z.begin(), z.end()) * (1.0 + 4.0 * u) / (1.0 - g);
}

}  // namespace

namespace {

// residual_norm_bound<false> on CHOLMOD's supernodal factor itself, block by block: supernode K holds the
// dense nr × nc block V (column-major) of its columns over its rows R (ascending; its own nc columns first),
// and contributes V Vᵀ to the entries (R[a], R[b]), a ≥ b, of L̂L̂ᵀ. Each column of that contribution is a run
// of contiguous products V[a, k]·V[b, k] (exact by fma, summed by Sum2 as above: an inner loop the compiler
// vectorizes), then added once per supernode into a normalized double-double accumulator of the entry. The
// error bound per entry: Sum2's (m + 1)γ_{m+1}2u Σ|terms| within each supernode (m ≤ nc), and 4u²(|partial| +
// |part|) per accumulation. Returns −1 when the factor's row lists are not ascending (then the caller takes
// the simplicial path).
// The inner kernel of the block evaluation: th + tl += col·vbk over rows b … nr−1 (products exact by fma,
// sums by Sum2), tm += |col·vbk|. Without -mfma, std::fma is a call into libm per element; the kernel is
// therefore built twice on x86-64, for processors with FMA (which implies AVX: four products per instruction;
// chosen at load time by feature, not by processor model) and for the baseline. Both compute the same bits
// (fma is exact either way, and the sums are the same operations in the same order).
#if defined(__x86_64__) && (defined(__clang__) || defined(__GNUC__))
__attribute__((target_clones("fma", "default")))
#endif
void column_products(const double* col, double vbk, double* th, double* tl, double* tm, int b, int nr) {
  for (int a = b; a < nr; ++a) {
    const double ph = col[a] * vbk;
    const double pl = std::fma(col[a], vbk, -ph);
    const double sum = th[a] + ph;
    const double z = sum - th[a];
    tl[a] += ((th[a] - (sum - z)) + (ph - z)) + pl;
    th[a] = sum;
    tm[a] += std::abs(ph);
  }
}

double supernodal_residual_norm_bound(int n, const cholmod_factor* F, const PermutedLower& A) {
  constexpr double u = std::numeric_limits<double>::epsilon() / 2;
  const auto N = static_cast<std::size_t>(n);
  const auto* super = static_cast<const int*>(F->super);
  const auto* pi = static_cast<const int*>(F->pi);
  const auto* px = static_cast<const int*>(F->px);
  const auto* ls = static_cast<const int*>(F->s);
  const auto* Lx = static_cast<const double*>(F->x);
  const std::size_t nsuper = F->nsuper;
  std::vector<int> sup_of(N);
  std::vector<std::size_t> base(N + 1, 0);  // entry (row R_J[t], column super[J] + c) at base[j] + t − c
  for (std::size_t K = 0; K < nsuper; ++K) {
    const int nr = pi[K + 1] - pi[K];
    if (!std::is_sorted(ls + pi[K], ls + pi[K + 1])) return -1.0;
    for (int c = 0; c < super[K + 1] - super[K]; ++c) {
      const auto j = static_cast<std::size_t>(super[K] + c);
      sup_of[j] = static_cast<int>(K);
      base[j + 1] = static_cast<std::size_t>(nr - c);
    }
  }
  for (std::size_t j = 0; j < N; ++j) base[j + 1] += base[j];
  const std::size_t nnz = base[N];
  std::vector<double> ghi(nnz, 0.0), glo(nnz, 0.0), gerr(nnz, 0.0), gmag(nnz, 0.0);
  // Adds the part (hi, lo) (lo unnormalized, as Sum2 leaves it) with Σ|terms| mag and m terms.
  auto accumulate = [&](std::size_t q, double hi, double lo, double mag, double m) {
    const double s = hi + lo;  // TwoSum: (hi, lo) → (s, e) exactly
    const double bb = s - hi;
    const double e = (hi - (s - bb)) + (lo - bb);
    const DD sum = dd_add(DD{ghi[q], glo[q]}, DD{s, e});
    gerr[q] += 4.0 * u * u * (std::abs(ghi[q]) + std::abs(s) + std::abs(e)) +
               2.0 * (m + 1.0) * (m + 1.0) * u * u * mag;
    ghi[q] = sum.hi;
    glo[q] = sum.lo;
    gmag[q] += mag;
  };
  std::vector<double> thi, tlo, tmag;
  std::vector<int> rel(N, -1);  // position of a row in the current target supernode's row list
  for (std::size_t K = 0; K < nsuper; ++K) {
    const int nc = super[K + 1] - super[K];
    const int nr = pi[K + 1] - pi[K];
    const int* R = ls + pi[K];
    const double* V = Lx + px[K];
    thi.assign(static_cast<std::size_t>(nr), 0.0);
    tlo.assign(static_cast<std::size_t>(nr), 0.0);
    tmag.assign(static_cast<std::size_t>(nr), 0.0);
    int target = -1;  // the supernode whose row list `rel` holds
    for (int b = 0; b < nr; ++b) {
      // Column R[b] of V Vᵀ, rows a ≥ b: Σ_k V[a, k] V[b, k] over the columns k ≤ b of the block that reach
      // row b (in the diagonal block V[b, k] = 0 for k > b).
      const int kmax = std::min(nc, b + 1);
      for (int k = 0; k < kmax; ++k) {
        const double vbk = V[static_cast<std::size_t>(k) * nr + b];
        if (vbk == 0.0) continue;
        column_products(V + static_cast<std::size_t>(k) * nr, vbk, thi.data(), tlo.data(), tmag.data(), b,
                        nr);
      }
      // Scatter column R[b] into its supernode's entries.
      const auto j = static_cast<std::size_t>(R[b]);
      const int J = sup_of[j];
      const int c = R[b] - super[J];
      if (J != target) {
        if (target >= 0)
          for (int t = pi[target]; t < pi[target + 1]; ++t) rel[static_cast<std::size_t>(ls[t])] = -1;
        target = J;
        for (int t = pi[J]; t < pi[J + 1]; ++t) rel[static_cast<std::size_t>(ls[t])] = t - pi[J];
      }
      for (int a = b; a < nr; ++a) {
        const int t = rel[static_cast<std::size_t>(R[a])];
        if (t < c) throw std::logic_error("SparseCholesky: a row of L̂L̂ᵀ outside the pattern of L");
        accumulate(base[j] + static_cast<std::size_t>(t - c), thi[static_cast<std::size_t>(a)],
                   tlo[static_cast<std::size_t>(a)], tmag[static_cast<std::size_t>(a)], kmax);
        thi[static_cast<std::size_t>(a)] = tlo[static_cast<std::size_t>(a)] =
            tmag[static_cast<std::size_t>(a)] = 0.0;
      }
    }
    if (target >= 0)
      for (int t = pi[target]; t < pi[target + 1]; ++t) rel[static_cast<std::size_t>(ls[t])] = -1;
  }
  // − A, by binary search of each entry's row in its column's row list.
  for (int j = 0; j < n; ++j) {
    const auto J = static_cast<std::size_t>(sup_of[static_cast<std::size_t>(j)]);
    const int c = j - super[J];
    const int* first = ls + pi[J] + c;
    const int* last = ls + pi[J + 1];
    for (int q = A.p[static_cast<std::size_t>(j)]; q < A.p[static_cast<std::size_t>(j) + 1]; ++q) {
      const int i = A.i[static_cast<std::size_t>(q)];
      const int* at = std::lower_bound(first, last, i);
      if (at == last || *at != i)
        throw std::logic_error("SparseCholesky: an entry of A outside the pattern of L");
      const std::size_t g = base[static_cast<std::size_t>(j)] + static_cast<std::size_t>(at - first);
      const double ax = A.x[static_cast<std::size_t>(q)], axl = A.xl[static_cast<std::size_t>(q)];
      accumulate(g, -ax, -axl, std::abs(ax) + std::abs(axl), 1.0);
    }
  }
  // Row sums of |R| (each off-diagonal entry counts in its row and its column).
  std::vector<double> z(N, 0.0);
  for (int j = 0; j < n; ++j) {
    const auto J = static_cast<std::size_t>(sup_of[static_cast<std::size_t>(j)]);
    const int c = j - super[J];
    for (int t = pi[J] + c; t < pi[J + 1]; ++t) {
      const std::size_t g = base[static_cast<std::size_t>(j)] + static_cast<std::size_t>(t - pi[J] - c);
      const double rij = std::abs(ghi[g] + glo[g]) * (1.0 + 2.0 * u) + 2.0 * gerr[g] + u * u * gmag[g];
      const auto i = static_cast<std::size_t>(ls[t]);
      z[i] += rij;
      if (i != static_cast<std::size_t>(j)) z[static_cast<std::size_t>(j)] += rij;
    }
  }
  const double g = 2.0 * n * u / (1.0 - 2.0 * n * u);
  return *std::max_element(z.begin(), z.end()) * (1.0 + 4.0 * u) / (1.0 - g);
}

}  // namespace

double SparseCholesky::residual_bound(const std::vector<double>* trailing) const {
  if (trailing && trailing->size() != values_.size())
    throw std::invalid_argument("SparseCholesky::residual_bound: trailing parts of the wrong size");
  if (impl_->L->is_super && impl_->L->xtype == CHOLMOD_REAL) {
    const PermutedLower A = permuted_lower(n_, col_start_, row_index_, values_, trailing,
                                           static_cast<const int*>(impl_->L->Perm));
    const double r = supernodal_residual_norm_bound(n_, impl_->L, A);
    if (r >= 0.0) return r;
  }
  return residual_bound_entrywise(trailing);
}

void SparseCholesky::computed_factor(std::vector<int>& col_start, std::vector<int>& row_index,
                                     std::vector<double>& values, std::vector<int>& perm) const {
  const LowerFactor& L = impl_->lower_factor();
  col_start = L.p;
  row_index = L.i;
  values = L.x;
  const int* P = static_cast<const int*>(impl_->L->Perm);
  perm.resize(static_cast<std::size_t>(n_));
  for (int k = 0; k < n_; ++k) perm[static_cast<std::size_t>(k)] = P ? P[k] : k;
}

double SparseCholesky::residual_bound_entrywise(const std::vector<double>* trailing) const {
  if (trailing && trailing->size() != values_.size())
    throw std::invalid_argument("SparseCholesky::residual_bound: trailing parts of the wrong size");
  const LowerFactor& L = impl_->lower_factor();
  const RowIndex rows = row_index_of(n_, L.p, L.i);
  const PermutedLower A =
      permuted_lower(n_, col_start_, row_index_, values_, trailing, static_cast<const int*>(impl_->L->Perm));
  return residual_norm_bound<false>(n_, L.p, L.i, L.x.data(), nullptr, rows, A);
}

bool SparseCholesky::factorize_extended(const std::vector<double>& trailing) {
  if (trailing.size() != values_.size())
    throw std::invalid_argument("SparseCholesky::factorize_extended: trailing parts of the wrong size");
  Impl& m = *impl_;
  m.extended_valid = false;
  const cholmod_factor* F = m.L;
  if (!F->is_super) throw std::logic_error("SparseCholesky::factorize_extended needs a supernodal analysis");
  const auto N = static_cast<std::size_t>(n_);
  if (m.ext_p.empty()) {
    // The symbolic pattern of L from the supernodal analysis: supernode s holds columns super[s] …
    // super[s+1]−1 and the rows ls[pi[s] … pi[s+1]); column super[s] + c has the rows from position c on.
    const auto* super = static_cast<const int*>(F->super);
    const auto* pi = static_cast<const int*>(F->pi);
    const auto* ls = static_cast<const int*>(F->s);
    m.ext_p.assign(N + 1, 0);
    for (std::size_t s = 0; s < F->nsuper; ++s)
      for (int c = 0; c < super[s + 1] - super[s]; ++c) {
        const auto j = static_cast<std::size_t>(super[s] + c);
        std::vector<int> column(ls + pi[s] + c, ls + pi[s + 1]);
        std::sort(column.begin(), column.end());
        m.ext_i.insert(m.ext_i.end(), column.begin(), column.end());
        m.ext_p[j + 1] = static_cast<int>(column.size());
      }
    for (std::size_t j = 0; j < N; ++j) m.ext_p[j + 1] += m.ext_p[j];
    // The loop above appended column by column in supernode order, which is column order.
    m.ext_rows = row_index_of(n_, m.ext_p, m.ext_i);
  }
  const PermutedLower A =
      permuted_lower(n_, col_start_, row_index_, values_, &trailing, static_cast<const int*>(F->Perm));
  m.ext_x.assign(m.ext_i.size(), 0.0);
  m.ext_xl.assign(m.ext_i.size(), 0.0);
  // Left-looking: column j = A(:, j) − Σ_k L(:, k) L_jk over the entries L_jk, k < j, of row j; then the
  // square root of the pivot and a division.
  std::vector<DD> acc(N);
  std::vector<char> in_column(N, 0);
  for (int j = 0; j < n_; ++j) {
    const auto J = static_cast<std::size_t>(j);
    for (int q = m.ext_p[J]; q < m.ext_p[J + 1]; ++q) {
      const auto i = static_cast<std::size_t>(m.ext_i[static_cast<std::size_t>(q)]);
      acc[i] = DD{};
      in_column[i] = 1;
    }
    for (int q = A.p[J]; q < A.p[J + 1]; ++q) {
      const auto i = static_cast<std::size_t>(A.i[static_cast<std::size_t>(q)]);
      if (!in_column[i]) throw std::logic_error("SparseCholesky: an entry of A outside the pattern of L");
      acc[i] = dd_add(acc[i], DD{A.x[static_cast<std::size_t>(q)], A.xl[static_cast<std::size_t>(q)]});
    }
    for (int r = m.ext_rows.p[J]; r < m.ext_rows.p[J + 1]; ++r) {
      const auto k = static_cast<std::size_t>(m.ext_rows.col[static_cast<std::size_t>(r)]);
      if (k == J) continue;
      const auto qj = static_cast<std::size_t>(m.ext_rows.q[static_cast<std::size_t>(r)]);
      const DD ljk{m.ext_x[qj], m.ext_xl[qj]};
      if (ljk.hi == 0.0) continue;
      for (int q = static_cast<int>(qj); q < m.ext_p[k + 1]; ++q) {
        const auto i = static_cast<std::size_t>(m.ext_i[static_cast<std::size_t>(q)]);
        const DD p =
            dd_mul(DD{m.ext_x[static_cast<std::size_t>(q)], m.ext_xl[static_cast<std::size_t>(q)]}, ljk);
        acc[i] = dd_add(acc[i], DD{-p.hi, -p.lo});
      }
    }
    const DD pivot = acc[J];
    bool ok = pivot.hi > 0.0 && std::isfinite(pivot.hi);
    const DD ljj = ok ? dd_sqrt(pivot) : DD{};
    for (int q = m.ext_p[J]; q < m.ext_p[J + 1]; ++q) {
      const auto i = static_cast<std::size_t>(m.ext_i[static_cast<std::size_t>(q)]);
      in_column[i] = 0;
      if (!ok) continue;
      const DD v = i == J ? ljj : dd_div(acc[i], ljj);
      m.ext_x[static_cast<std::size_t>(q)] = v.hi;
      m.ext_xl[static_cast<std::size_t>(q)] = v.lo;
    }
    if (!ok) return false;
  }
  m.extended_valid = true;
  return true;
}

double SparseCholesky::extended_residual_bound(const std::vector<double>& trailing) const {
  const Impl& m = *impl_;
  if (!m.extended_valid)
    throw std::logic_error("SparseCholesky::extended_residual_bound needs a successful factorize_extended");
  const PermutedLower A =
      permuted_lower(n_, col_start_, row_index_, values_, &trailing, static_cast<const int*>(m.L->Perm));
  return residual_norm_bound<true>(n_, m.ext_p, m.ext_i, m.ext_x.data(), m.ext_xl.data(), m.ext_rows, A);
}

}  // namespace keel::linalg
