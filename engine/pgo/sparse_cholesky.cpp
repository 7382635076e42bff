#include "pgo/sparse_cholesky.hpp"

#include <cholmod.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace keel::pgo::detail {

namespace {

// L̂ as a packed lower-triangular matrix in compressed columns (the permuted order of the factorization), the
// rows of each column ascending.
struct LowerFactor {
  std::vector<int> p, i;
  std::vector<double> x;
};

LowerFactor lower_factor(cholmod_factor* factor, cholmod_common* c) {
  cholmod_factor* copy = cholmod_copy_factor(factor, c);
  if (!copy)
    throw std::runtime_error(fmt::format("pgo: CHOLMOD could not copy the factor (status {})", c->status));
  cholmod_sparse* L = cholmod_factor_to_sparse(copy, c);  // frees copy's values
  cholmod_free_factor(&copy, c);
  if (!L)
    throw std::runtime_error(fmt::format("pgo: CHOLMOD could not convert the factor (status {})", c->status));
  const auto* p = static_cast<const int*>(L->p);
  const auto* i = static_cast<const int*>(L->i);
  const auto* x = static_cast<const double*>(L->x);
  const auto* nz = L->packed ? nullptr : static_cast<const int*>(L->nz);
  LowerFactor out;
  const std::size_t n = L->ncol;
  out.p.assign(n + 1, 0);
  std::vector<std::pair<int, double>> column;
  for (std::size_t j = 0; j < n; ++j) {
    const int end = nz ? p[j] + nz[j] : p[j + 1];
    column.clear();
    for (int q = p[j]; q < end; ++q) column.emplace_back(i[q], x[q]);
    std::sort(column.begin(), column.end());  // rows ascending: the diagonal first
    for (const auto& [row, value] : column) {
      out.i.push_back(row);
      out.x.push_back(value);
    }
    out.p[j + 1] = static_cast<int>(out.i.size());
  }
  cholmod_free_sparse(&L, c);
  return out;
}

}  // namespace

struct SparseCholesky::Impl {
  cholmod_common c;
  cholmod_sparse* A = nullptr;  // shares nothing: the pattern and values are copied in factorize()
  cholmod_factor* L = nullptr;
  LowerFactor lower;  // L̂ of the last factorization, made on first use
  bool lower_valid = false;
  const LowerFactor& lower_factor() {
    if (!lower_valid) {
      lower = keel::pgo::detail::lower_factor(L, &c);
      lower_valid = true;
    }
    return lower;
  }
  Impl() {
    cholmod_start(&c);
    c.print = 0;  // failures come back through status checks
  }
  ~Impl() {
    if (L) cholmod_free_factor(&L, &c);
    if (A) cholmod_free_sparse(&A, &c);
    cholmod_finish(&c);
  }
};

SparseCholesky::SparseCholesky(int n, std::vector<int> col_start, std::vector<int> row_index,
                               FillOrdering ordering, bool supernodal)
    : n_(n),
      col_start_(std::move(col_start)),
      row_index_(std::move(row_index)),
      impl_(std::make_unique<Impl>()) {
  if (n <= 0 || static_cast<int>(col_start_.size()) != n + 1 ||
      static_cast<int>(row_index_.size()) != col_start_.back())
    throw std::invalid_argument("pgo: SparseCholesky: inconsistent pattern");
  values_.assign(row_index_.size(), 0.0);
  cholmod_common* c = &impl_->c;
  impl_->A =
      cholmod_allocate_sparse(static_cast<std::size_t>(n), static_cast<std::size_t>(n), row_index_.size(),
                              /*sorted=*/1, /*packed=*/1, /*stype=*/1, CHOLMOD_REAL, c);
  if (!impl_->A)
    throw std::runtime_error(fmt::format("pgo: CHOLMOD could not allocate (status {})", c->status));
  std::copy(col_start_.begin(), col_start_.end(), static_cast<int*>(impl_->A->p));
  std::copy(row_index_.begin(), row_index_.end(), static_cast<int*>(impl_->A->i));
  c->supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_AUTO;
  // A simplicial factorization is LDLᵀ by default, which runs through negative pivots: LLᵀ instead, so that
  // factorize() fails on every matrix that is not positive definite in floating point (supernodal ones are
  // always LLᵀ), and both error bounds, which are about L̂L̂ᵀ, apply.
  c->final_ll = 1;
  switch (ordering) {
    case FillOrdering::automatic:
      c->nmethods = 0;
      break;
    case FillOrdering::amd:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_AMD;
      break;
    case FillOrdering::metis:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_METIS;
      break;
  }
  impl_->L = cholmod_analyze(impl_->A, c);
  if (!impl_->L) throw std::runtime_error(fmt::format("pgo: CHOLMOD analysis failed (status {})", c->status));
}

SparseCholesky::~SparseCholesky() = default;

bool SparseCholesky::factorize() {
  cholmod_common* c = &impl_->c;
  std::copy(values_.begin(), values_.end(), static_cast<double*>(impl_->A->x));
  c->quick_return_if_not_posdef = 1;
  impl_->lower_valid = false;
  const int ok = cholmod_factorize(impl_->A, impl_->L, c);
  if (!ok && c->status != CHOLMOD_NOT_POSDEF)
    throw std::runtime_error(fmt::format("pgo: CHOLMOD factorization failed (status {})", c->status));
  return impl_->L->minor >= impl_->L->n && c->status != CHOLMOD_NOT_POSDEF;
}

void SparseCholesky::solve(const double* b, double* x, int nrhs) const {
  cholmod_common* c = &impl_->c;
  cholmod_dense* B = cholmod_allocate_dense(static_cast<std::size_t>(n_), static_cast<std::size_t>(nrhs),
                                            static_cast<std::size_t>(n_), CHOLMOD_REAL, c);
  if (!B) throw std::runtime_error(fmt::format("pgo: CHOLMOD could not allocate (status {})", c->status));
  std::copy(b, b + static_cast<std::size_t>(n_) * nrhs, static_cast<double*>(B->x));
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, impl_->L, B, c);
  cholmod_free_dense(&B, c);
  if (!X) throw std::runtime_error(fmt::format("pgo: CHOLMOD solve failed (status {})", c->status));
  std::copy(static_cast<const double*>(X->x),
            static_cast<const double*>(X->x) + static_cast<std::size_t>(n_) * nrhs, x);
  cholmod_free_dense(&X, c);
}

int SparseCholesky::max_row_count() const {
  const cholmod_factor* L = impl_->L;
  std::vector<int> count(static_cast<std::size_t>(n_), 0);
  if (L->is_super) {
    // Supernode s holds columns super[s] … super[s+1]−1 and the rows ls[pi[s] … pi[s+1]) (its own columns
    // first). Row ls[pi[s] + q] has entries in the columns of s up to itself (q < ncols) or in all of them.
    const auto* super = static_cast<const int*>(L->super);
    const auto* pi = static_cast<const int*>(L->pi);
    const auto* ls = static_cast<const int*>(L->s);
    for (std::size_t s = 0; s < L->nsuper; ++s) {
      const int ncols = super[s + 1] - super[s];
      for (int q = pi[s]; q < pi[s + 1]; ++q)
        count[static_cast<std::size_t>(ls[q])] += std::min(q - pi[s] + 1, ncols);
    }
  } else {
    // Simplicial: after factorize() the pattern is in p/i/nz; before it, fall back to n (always a bound).
    if (!L->p || !L->i || !L->nz || L->xtype == CHOLMOD_PATTERN) return n_;
    const auto* p = static_cast<const int*>(L->p);
    const auto* i = static_cast<const int*>(L->i);
    const auto* nz = static_cast<const int*>(L->nz);
    for (int j = 0; j < n_; ++j)
      for (int q = p[j]; q < p[j] + nz[j]; ++q) ++count[static_cast<std::size_t>(i[q])];
  }
  return *std::max_element(count.begin(), count.end());
}

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

double SparseCholesky::residual_bound(const std::vector<double>* trailing) const {
  if (trailing && trailing->size() != values_.size())
    throw std::invalid_argument("pgo: SparseCholesky::residual_bound: trailing parts of the wrong size");
  const LowerFactor& L = impl_->lower_factor();
  const int n = n_;
  const auto N = static_cast<std::size_t>(n);
  // The rows of L̂: for row j, the positions in L.i / L.x of its entries L̂_jk, k ≤ j (in column k, every
  // later position holds a row i > j, the columns being sorted).
  std::vector<int> rp(N + 1, 0);
  for (const int i : L.i) ++rp[static_cast<std::size_t>(i) + 1];
  for (std::size_t j = 0; j < N; ++j) rp[j + 1] += rp[j];
  std::vector<int> rq(L.i.size()), fill(rp.begin(), rp.end() - 1);
  std::vector<int> col_of(L.i.size());
  for (int k = 0; k < n; ++k)
    for (int q = L.p[static_cast<std::size_t>(k)]; q < L.p[static_cast<std::size_t>(k) + 1]; ++q) {
      rq[static_cast<std::size_t>(fill[static_cast<std::size_t>(L.i[static_cast<std::size_t>(q)])]++)] = q;
      col_of[static_cast<std::size_t>(q)] = k;
    }
  // P A Pᵀ's lower triangle by column, from the stored upper triangle of A (Perm[k] = A's index of row k).
  const auto* perm = static_cast<const int*>(impl_->L->Perm);
  std::vector<int> iperm(N);
  for (int k = 0; k < n; ++k) iperm[static_cast<std::size_t>(perm ? perm[k] : k)] = k;
  std::vector<int> ap(N + 1, 0);
  for (int c = 0; c < n; ++c)
    for (int q = col_start_[static_cast<std::size_t>(c)]; q < col_start_[static_cast<std::size_t>(c) + 1];
         ++q) {
      const int a = iperm[static_cast<std::size_t>(row_index_[static_cast<std::size_t>(q)])];
      const int b = iperm[static_cast<std::size_t>(c)];
      ++ap[static_cast<std::size_t>(std::min(a, b)) + 1];
    }
  for (std::size_t j = 0; j < N; ++j) ap[j + 1] += ap[j];
  std::vector<int> ai(static_cast<std::size_t>(ap[N]));
  std::vector<double> ax(ai.size()), axl(ai.size(), 0.0);
  fill.assign(ap.begin(), ap.end() - 1);
  for (int c = 0; c < n; ++c)
    for (int q = col_start_[static_cast<std::size_t>(c)]; q < col_start_[static_cast<std::size_t>(c) + 1];
         ++q) {
      const int a = iperm[static_cast<std::size_t>(row_index_[static_cast<std::size_t>(q)])];
      const int b = iperm[static_cast<std::size_t>(c)];
      const int at = fill[static_cast<std::size_t>(std::min(a, b))]++;
      ai[static_cast<std::size_t>(at)] = std::max(a, b);
      ax[static_cast<std::size_t>(at)] = values_[static_cast<std::size_t>(q)];
      if (trailing) axl[static_cast<std::size_t>(at)] = (*trailing)[static_cast<std::size_t>(q)];
    }
  // Column j of R's lower triangle in a dense double-double accumulator (hi + lo), with Σ|terms| and the
  // number of terms per entry for the accumulation's error bound.
  std::vector<double> hi(N, 0.0), lo(N, 0.0), mag(N, 0.0), z(N, 0.0);
  std::vector<int> terms(N, 0), touched;
  touched.reserve(N);
  // Σ (ph + pl) as Ogita, Rump and Oishi's Sum2 (SIAM J. Sci. Comput. 2005): hi the floating sum of the ph,
  // lo the floating sum of TwoSum's exact errors and the pl. Each lo term is below u(|partial sum| + |ph|) +
  // |pl| ≤ 2u Σ|terms|, so m terms leave hi + lo within (m + 1) γ_{m+1} · 2u Σ|terms| of the exact sum (the
  // rounding of lo's own sum; the bound below takes that).
  auto add = [&](std::size_t i, double ph, double pl) {
    if (terms[i] == 0) touched.push_back(static_cast<int>(i));
    ++terms[i];
    const double s = hi[i] + ph;
    const double z = s - hi[i];
    lo[i] += ((hi[i] - (s - z)) + (ph - z)) + pl;
    hi[i] = s;
  };
  for (int j = 0; j < n; ++j) {
    const auto J = static_cast<std::size_t>(j);
    for (int r = rp[J]; r < rp[J + 1]; ++r) {
      const int qj = rq[static_cast<std::size_t>(r)];
      const auto k = static_cast<std::size_t>(col_of[static_cast<std::size_t>(qj)]);
      const double ljk = L.x[static_cast<std::size_t>(qj)];
      if (ljk == 0.0) continue;
      for (int q = qj; q < L.p[k + 1]; ++q) {  // rows i ≥ j of column k
        const int i = L.i[static_cast<std::size_t>(q)];
        const double lik = L.x[static_cast<std::size_t>(q)];
        const double ph = lik * ljk;
        const double pl = std::fma(lik, ljk, -ph);  // exact: ph + pl = lik · ljk
        add(static_cast<std::size_t>(i), ph, pl);
        mag[static_cast<std::size_t>(i)] += std::abs(ph);
      }
    }
    for (int q = ap[J]; q < ap[J + 1]; ++q) {
      const auto i = static_cast<std::size_t>(ai[static_cast<std::size_t>(q)]);
      const double a = ax[static_cast<std::size_t>(q)], al = axl[static_cast<std::size_t>(q)];
      add(i, -a, -al);  // (a, al) a normalized double-double: |al| ≤ u|a|
      mag[i] += std::abs(a) + std::abs(al);
    }
    for (const int ti : touched) {
      const auto i = static_cast<std::size_t>(ti);
      // |R_ij| ≤ |hi + lo| + (m + 1) γ_{m+1} 2u Σ|terms|; hi and lo are not normalized (they may nearly
      // cancel), so their sum is rounded once (relative error u, covered by the factor 1 + 2u); the error
      // term is doubled for the rounding of mag itself (a sum of m non-negative terms, low by at most a
      // factor 1 − γ_m).
      const double m1 = terms[i] + 1.0;
      const double rij =
          std::abs(hi[i] + lo[i]) * (1.0 + 2.0 * kU) + 4.0 * m1 * (m1 * kU / (1.0 - m1 * kU)) * kU * mag[i];
      z[i] += rij;
      if (i != J) z[J] += rij;
      hi[i] = lo[i] = mag[i] = 0.0;
      terms[i] = 0;
    }
    touched.clear();
  }
  // Each z_i is a floating sum of at most 2n non-negative terms, each term computed with relative error ≤ 3u:
  // the true row sum is at most z_i (1 + 3u) / (1 − γ_{2n}).
  const double g = 2.0 * n * kU / (1.0 - 2.0 * n * kU);
  return *std::max_element(z.begin(), z.end()) * (1.0 + 4.0 * kU) / (1.0 - g);
}

std::string SparseCholesky::ordering_name() const {
  switch (impl_->L->ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_AMD:
      return "amd";
    case CHOLMOD_METIS:
      return "metis";
    case CHOLMOD_NESDIS:
      return "nesdis";
    case CHOLMOD_COLAMD:
      return "colamd";
    default:
      return "other";
  }
}

double SparseCholesky::factor_nonzeros() const { return impl_->c.lnz; }

}  // namespace keel::pgo::detail
