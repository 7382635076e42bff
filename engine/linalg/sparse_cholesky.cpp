// linalg::SparseCholesky (sparse_cholesky.hpp): the analysis with its options, factorizations, solves (one
// workspace per thread), the factor's structure and the names of the orderings.
#include "linalg/sparse_cholesky.hpp"

#include <cholmod.h>
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/names.hpp"
#include "linalg/sparse_cholesky_impl.hpp"

namespace keel::linalg {

LowerFactor lower_factor(cholmod_factor* factor, cholmod_common* c) {
  cholmod_factor* copy = cholmod_copy_factor(factor, c);
  if (!copy)
    throw std::runtime_error(
        fmt::format("SparseCholesky: CHOLMOD could not copy the factor (status {})", c->status));
  cholmod_sparse* L = cholmod_factor_to_sparse(copy, c);  // frees copy's values
  cholmod_free_factor(&copy, c);
  if (!L)
    throw std::runtime_error(
        fmt::format("SparseCholesky: CHOLMOD could not convert the factor (status {})", c->status));
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

SparseCholesky::SparseCholesky(int n, std::vector<int> col_start, std::vector<int> row_index,
                               const CholeskyOptions& options)
    : n_(n),
      col_start_(std::move(col_start)),
      row_index_(std::move(row_index)),
      impl_(std::make_unique<Impl>()) {
  if (n <= 0 || static_cast<int>(col_start_.size()) != n + 1 ||
      static_cast<int>(row_index_.size()) != col_start_.back())
    throw std::invalid_argument("SparseCholesky: inconsistent pattern");
  values_.assign(row_index_.size(), 0.0);
  cholmod_common* c = &impl_->c;
  impl_->A =
      cholmod_allocate_sparse(static_cast<std::size_t>(n), static_cast<std::size_t>(n), row_index_.size(),
                              /*sorted=*/1, /*packed=*/1, /*stype=*/1, CHOLMOD_REAL, c);
  if (!impl_->A)
    throw std::runtime_error(
        fmt::format("SparseCholesky: CHOLMOD could not allocate (status {})", c->status));
  std::copy(col_start_.begin(), col_start_.end(), static_cast<int*>(impl_->A->p));
  std::copy(row_index_.begin(), row_index_.end(), static_cast<int*>(impl_->A->i));
  switch (options.kind) {
    case FactorKind::automatic:
      c->supernodal = CHOLMOD_AUTO;
      break;
    case FactorKind::supernodal:
      c->supernodal = CHOLMOD_SUPERNODAL;
      break;
    case FactorKind::simplicial:
      c->supernodal = CHOLMOD_SIMPLICIAL;
      break;
  }
  c->final_ll = options.ll ? 1 : 0;
  switch (options.ordering) {
    case Ordering::automatic:
      c->nmethods = 0;  // CHOLMOD's default: AMD, METIS too if AMD fills badly
      break;
    case Ordering::amd:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_AMD;
      break;
    case Ordering::metis:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_METIS;
      break;
    case Ordering::nesdis:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_NESDIS;
      break;
    case Ordering::natural:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_NATURAL;
      c->postorder = 0;
      break;
  }
  impl_->L = cholmod_analyze(impl_->A, c);
  if (!impl_->L)
    throw std::runtime_error(fmt::format("SparseCholesky: CHOLMOD analysis failed (status {})", c->status));
}

SparseCholesky::~SparseCholesky() = default;

bool SparseCholesky::factorize() {
  cholmod_common* c = &impl_->c;
  std::copy(values_.begin(), values_.end(), static_cast<double*>(impl_->A->x));
  c->quick_return_if_not_posdef = 1;
  impl_->lower_valid = false;
  const int ok = cholmod_factorize(impl_->A, impl_->L, c);
  if (!ok && c->status != CHOLMOD_NOT_POSDEF)
    throw std::runtime_error(
        fmt::format("SparseCholesky: CHOLMOD factorization failed (status {})", c->status));
  return impl_->L->minor >= impl_->L->n && c->status != CHOLMOD_NOT_POSDEF;
}

void SparseCholesky::solve(const double* b, double* x, int nrhs) const {
  cholmod_common* c = &impl_->c;
  cholmod_dense* B = cholmod_allocate_dense(static_cast<std::size_t>(n_), static_cast<std::size_t>(nrhs),
                                            static_cast<std::size_t>(n_), CHOLMOD_REAL, c);
  if (!B)
    throw std::runtime_error(
        fmt::format("SparseCholesky: CHOLMOD could not allocate (status {})", c->status));
  std::copy(b, b + static_cast<std::size_t>(n_) * nrhs, static_cast<double*>(B->x));
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, impl_->L, B, c);
  cholmod_free_dense(&B, c);
  if (!X)
    throw std::runtime_error(fmt::format("SparseCholesky: CHOLMOD solve failed (status {})", c->status));
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

std::string SparseCholesky::ordering_name() const {
  switch (impl_->L->ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_GIVEN:
      return "given";
    case CHOLMOD_AMD:
      return "amd";
    case CHOLMOD_METIS:
      return "metis";
    case CHOLMOD_NESDIS:
      return "nesdis";
    case CHOLMOD_COLAMD:
      return "colamd";
    case CHOLMOD_POSTORDERED:
      return "postordered";
    default:
      return "unknown";
  }
}

double SparseCholesky::factor_nonzeros() const { return impl_->c.lnz; }
double SparseCholesky::factor_flops() const { return impl_->c.fl; }
double SparseCholesky::factor_storage() const {
  const cholmod_factor* L = impl_->L;
  return static_cast<double>(L->is_super ? L->xsize : L->nzmax);
}

int SparseCholesky::failed_row() const {
  const cholmod_factor* L = impl_->L;
  return L->minor < L->n ? static_cast<const int*>(L->Perm)[L->minor] : -1;
}
const int* SparseCholesky::permutation() const { return static_cast<const int*>(impl_->L->Perm); }
bool SparseCholesky::supernodal() const { return impl_->L->is_super != 0; }
Supernodes SparseCholesky::supernodes() const {
  const cholmod_factor* L = impl_->L;
  if (!L->is_super) throw std::logic_error("SparseCholesky::supernodes: the factor is simplicial");
  return {static_cast<int>(L->nsuper),    static_cast<const int*>(L->super),
          static_cast<const int*>(L->pi), static_cast<const int*>(L->px),
          static_cast<const int*>(L->s),  static_cast<const double*>(L->x)};
}

struct SolveWorkspace::Impl {
  cholmod_common c;
  cholmod_dense *B = nullptr, *X = nullptr, *Y = nullptr, *E = nullptr;
  Impl() {
    cholmod_start(&c);
    c.print = 0;
  }
  ~Impl() {
    for (cholmod_dense** d : {&B, &X, &Y, &E})
      if (*d) cholmod_free_dense(d, &c);
    cholmod_finish(&c);
  }
};
SolveWorkspace::SolveWorkspace() : impl_(std::make_unique<Impl>()) {}
SolveWorkspace::~SolveWorkspace() = default;

double* SolveWorkspace::right_hand_sides(int n, int nrhs) {
  Impl& w = *impl_;
  const auto rows = static_cast<std::size_t>(n), cols = static_cast<std::size_t>(nrhs);
  if (!w.B || w.B->nrow != rows || w.B->ncol != cols) {
    if (w.B) cholmod_free_dense(&w.B, &w.c);
    w.B = cholmod_zeros(rows, cols, CHOLMOD_REAL, &w.c);
    if (!w.B)
      throw std::runtime_error(fmt::format(
          "SparseCholesky: CHOLMOD could not allocate the right-hand sides (status {})", w.c.status));
  } else {
    std::fill_n(static_cast<double*>(w.B->x), rows * cols, 0.0);
  }
  return static_cast<double*>(w.B->x);
}

const double* SparseCholesky::solve(SolveWorkspace& ws, int* ld) const {
  SolveWorkspace::Impl& w = *ws.impl_;
  if (!w.B || w.B->nrow != static_cast<std::size_t>(n_))
    throw std::logic_error("SparseCholesky::solve: no right-hand sides of this size in the workspace");
  if (!cholmod_solve2(CHOLMOD_A, impl_->L, w.B, nullptr, &w.X, nullptr, &w.Y, &w.E, &w.c))
    throw std::runtime_error(fmt::format("SparseCholesky: CHOLMOD solve failed (status {})", w.c.status));
  *ld = static_cast<int>(w.X->d);
  return static_cast<const double*>(w.X->x);
}

namespace {
constexpr core::NameTable<Ordering, 5> kOrdering{"linalg::Ordering",
                                                 {{{Ordering::automatic, "auto"},
                                                   {Ordering::amd, "amd"},
                                                   {Ordering::metis, "metis"},
                                                   {Ordering::nesdis, "nesdis"},
                                                   {Ordering::natural, "natural"}}}};
}  // namespace

std::string_view to_string(Ordering o) { return kOrdering.name(o); }
Ordering ordering_from_string(std::string_view s) { return kOrdering.parse(s); }

}  // namespace keel::linalg
