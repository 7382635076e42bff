#include "pgo/sparse_cholesky.hpp"

#include <cholmod.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace keel::pgo::detail {

struct SparseCholesky::Impl {
  cholmod_common c;
  cholmod_sparse* A = nullptr;  // shares nothing: the pattern and values are copied in factorize()
  cholmod_factor* L = nullptr;
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

double SparseCholesky::backward_error_bound() const {
  cholmod_common* c = &impl_->c;
  cholmod_factor* copy = cholmod_copy_factor(impl_->L, c);
  if (!copy)
    throw std::runtime_error(fmt::format("pgo: CHOLMOD could not copy the factor (status {})", c->status));
  cholmod_sparse* L =
      cholmod_factor_to_sparse(copy, c);  // L̂ as a lower-triangular sparse matrix (frees copy's values)
  cholmod_free_factor(&copy, c);
  if (!L)
    throw std::runtime_error(fmt::format("pgo: CHOLMOD could not convert the factor (status {})", c->status));
  const auto* p = static_cast<const int*>(L->p);
  const auto* i = static_cast<const int*>(L->i);
  const auto* x = static_cast<const double*>(L->x);
  const auto* nz = L->packed ? nullptr : static_cast<const int*>(L->nz);
  const std::size_t n = L->ncol;
  std::vector<double> col_abs(n, 0.0), z(n, 0.0);
  std::vector<int> row_count(n, 0);
  for (std::size_t j = 0; j < n; ++j) {
    const int end = nz ? p[j] + nz[j] : p[j + 1];
    for (int q = p[j]; q < end; ++q)
      if (x[q] != 0.0) {  // an exact zero (a relaxed supernode's padding) adds no rounding
        col_abs[j] += std::abs(x[q]);
        ++row_count[static_cast<std::size_t>(i[q])];
      }
  }
  for (std::size_t j = 0; j < n; ++j) {
    const int end = nz ? p[j] + nz[j] : p[j + 1];
    for (int q = p[j]; q < end; ++q) z[static_cast<std::size_t>(i[q])] += std::abs(x[q]) * col_abs[j];
  }
  cholmod_free_sparse(&L, c);
  constexpr double u = std::numeric_limits<double>::epsilon() / 2;
  double bound = 0.0;
  for (std::size_t r = 0; r < n; ++r) {
    const double k1 = row_count[r] + 1.0;
    bound = std::max(bound, k1 * u / (1.0 - k1 * u) * z[r]);
  }
  return bound;
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
