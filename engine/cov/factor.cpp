// The factorization L Lᵀ = P H Pᵀ of a MarginalCovariance (CHOLMOD, supernodal by default; the ordering of
// CovarianceOptions), the choice of extraction, and the supernodal elimination tree that Extraction::forward
// walks.
#include <cholmod.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "cov/factor.hpp"

namespace keel::cov {

namespace {

const char* cholmod_ordering_name(int ordering) {
  switch (ordering) {
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
  }
  return "unknown";
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

MarginalCovariance::MarginalCovariance(const SparseInformation& H, const CovarianceOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  H.validate();
  if (H.size == 0)
    throw std::invalid_argument("MarginalCovariance: H is empty (nothing left after the gauge)");
  Impl& I = *impl_;
  I.num_poses = H.num_poses;
  I.num_landmarks = H.num_landmarks;
  I.pose_dof = H.pose_dof;
  I.landmark_dof = H.landmark_dof;
  I.size = H.size;
  I.offset = H.offset;
  I.options = options;
  cholmod_common* c = &I.common.c;

  // H as a CHOLMOD matrix (stype = +1: the upper triangle is used). The arrays are copied, H stays untouched.
  cholmod_sparse* A =
      cholmod_allocate_sparse(static_cast<std::size_t>(H.size), static_cast<std::size_t>(H.size),
                              H.nonzeros(), /*sorted=*/1, /*packed=*/1, /*stype=*/1, CHOLMOD_REAL, c);
  if (!A)
    throw std::runtime_error(
        fmt::format("MarginalCovariance: CHOLMOD could not allocate H (status {})", c->status));
  std::copy(H.col_start.begin(), H.col_start.end(), static_cast<int*>(A->p));
  std::copy(H.row_index.begin(), H.row_index.end(), static_cast<int*>(A->i));
  std::copy(H.value.begin(), H.value.end(), static_cast<double*>(A->x));

  c->supernodal = options.supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  switch (options.ordering) {
    case Ordering::automatic:
      c->nmethods = 0;
      break;  // CHOLMOD default: AMD, METIS too if AMD fills badly
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

  auto t0 = std::chrono::steady_clock::now();
  I.L = cholmod_analyze(A, c);
  I.summary.analyze_time_s = seconds_since(t0);
  if (!I.L) {
    cholmod_free_sparse(&A, c);
    throw std::runtime_error(
        fmt::format("MarginalCovariance: CHOLMOD analysis failed (status {})", c->status));
  }
  t0 = std::chrono::steady_clock::now();
  const int ok = cholmod_factorize(A, I.L, c);
  I.summary.factorize_time_s = seconds_since(t0);
  cholmod_free_sparse(&A, c);
  if (!ok || c->status == CHOLMOD_NOT_POSDEF || I.L->minor < I.L->n) {
    std::string msg = "MarginalCovariance: the information matrix is not positive definite";
    if (I.L->minor < I.L->n) {
      const int row = static_cast<int*>(I.L->Perm)[I.L->minor];
      msg += fmt::format(
          " (the factorization broke down at row {}, {}): is every variable constrained and the graph "
          "connected to the gauge pose?",
          row, I.variable_name(I.variable_of_row(row)));
    } else {
      msg += fmt::format(" (CHOLMOD status {})", c->status);
    }
    throw std::runtime_error(msg);
  }

  FactorSummary& s = I.summary;
  s.ordering = cholmod_ordering_name(I.L->ordering);
  s.supernodal = I.L->is_super != 0;
  s.size = H.size;
  s.nnz_h = H.nonzeros();
  s.nnz_l = c->lnz;
  s.factor_flops = c->fl;
  s.num_supernodes = s.supernodal ? I.L->nsuper : 0;
  s.l_storage = s.supernodal ? I.L->xsize : I.L->nzmax;

  I.extraction = options.extraction == Extraction::automatic
                     ? (s.supernodal ? Extraction::forward : Extraction::solve)
                     : options.extraction;
  if (I.extraction == Extraction::forward && !s.supernodal)
    throw std::runtime_error(
        "MarginalCovariance: CHOLMOD returned a simplicial factor; extraction 'forward' needs a "
        "supernodal one");
  s.extraction = std::string(to_string(I.extraction));

  const int n = H.size;
  I.iperm.assign(static_cast<std::size_t>(n), 0);
  const int* perm = static_cast<const int*>(I.L->Perm);
  for (int k = 0; k < n; ++k) I.iperm[static_cast<std::size_t>(perm[k])] = k;
  if (s.supernodal) {
    I.nsuper = static_cast<int>(I.L->nsuper);
    I.super = static_cast<const int*>(I.L->super);
    I.pi = static_cast<const int*>(I.L->pi);
    I.px = static_cast<const int*>(I.L->px);
    I.ls = static_cast<const int*>(I.L->s);
    I.lx = static_cast<const double*>(I.L->x);
    I.snode_of_col.assign(static_cast<std::size_t>(n), 0);
    I.parent.assign(static_cast<std::size_t>(I.nsuper), -1);
    for (int sn = 0; sn < I.nsuper; ++sn)
      for (int j = I.super[sn]; j < I.super[sn + 1]; ++j) I.snode_of_col[static_cast<std::size_t>(j)] = sn;
    for (int sn = 0; sn < I.nsuper; ++sn)
      if (I.nsrow(sn) > I.nscol(sn)) {
        // The first row below the diagonal block names the parent; every other row lies in an ancestor.
        const int p = I.snode_of_col[static_cast<std::size_t>(I.ls[I.pi[sn] + I.nscol(sn)])];
        if (p <= sn)
          throw std::logic_error("MarginalCovariance: supernodal tree is not topologically ordered");
        I.parent[static_cast<std::size_t>(sn)] = p;
      }
    // share of L on the path of each column: path[s] = own + path[parent], parents come later
    std::vector<double> path(static_cast<std::size_t>(I.nsuper), 0.0);
    double total = 0.0;
    for (int sn = I.nsuper - 1; sn >= 0; --sn) {
      const double own = static_cast<double>(I.nscol(sn)) * I.nsrow(sn);
      total += own;
      const int p = I.parent[static_cast<std::size_t>(sn)];
      path[static_cast<std::size_t>(sn)] = own + (p >= 0 ? path[static_cast<std::size_t>(p)] : 0.0);
    }
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
      sum += path[static_cast<std::size_t>(I.snode_of_col[static_cast<std::size_t>(j)])];
    s.mean_path_fraction = sum / (static_cast<double>(n) * total);
  }
}

MarginalCovariance::~MarginalCovariance() = default;
MarginalCovariance::MarginalCovariance(MarginalCovariance&&) noexcept = default;
MarginalCovariance& MarginalCovariance::operator=(MarginalCovariance&&) noexcept = default;

const FactorSummary& MarginalCovariance::summary() const { return impl_->summary; }
int MarginalCovariance::num_poses() const { return impl_->num_poses; }
int MarginalCovariance::num_landmarks() const { return impl_->num_landmarks; }
int MarginalCovariance::num_variables() const { return impl_->num_variables(); }
int MarginalCovariance::variable_dim(int var) const {
  impl_->check(var);
  return impl_->dim(var);
}

}  // namespace keel::cov
