// The factorization L Lᵀ = P H Pᵀ of a MarginalCovariance (linalg::SparseCholesky, supernodal by default,
// LDLᵀ when simplicial; the ordering of CovarianceOptions), the choice of extraction, and the supernodal
// elimination tree that Extraction::forward walks.
#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "cov/factor.hpp"
#include "core/blas.hpp"

namespace keel::cov {

namespace {

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

  // H's upper triangle is copied into the factorization; H stays untouched. Simplicial factors stay CHOLMOD's
  // LDLᵀ (Extraction::solve only solves with them).
  auto t0 = std::chrono::steady_clock::now();
  I.factor = std::make_unique<linalg::SparseCholesky>(
      H.size, H.col_start, H.row_index,
      linalg::CholeskyOptions{
          options.ordering,
          options.supernodal ? linalg::FactorKind::supernodal : linalg::FactorKind::simplicial,
          /*ll=*/false});
  I.summary.analyze_time_s = seconds_since(t0);
  linalg::SparseCholesky& F = *I.factor;
  std::copy(H.value.begin(), H.value.end(), F.values().begin());
  t0 = std::chrono::steady_clock::now();
  bool ok = false;
  {
    // One BLAS thread, CHOLMOD's OpenMP teams serialized, as the certified solver (core/blas.hpp).
    const core::SingleThreadedBlas one_blas_thread;
    const core::SerialOpenMp serial_openmp;
    ok = F.factorize();
  }
  I.summary.factorize_time_s = seconds_since(t0);
  if (!ok) {
    std::string msg = "MarginalCovariance: the information matrix is not positive definite";
    if (const int row = F.failed_row(); row >= 0)
      msg += fmt::format(
          " (the factorization broke down at row {}, {}): is every variable constrained and the graph "
          "connected to the gauge pose?",
          row, I.variable_name(I.variable_of_row(row)));
    throw std::runtime_error(msg);
  }

  FactorSummary& s = I.summary;
  s.ordering = F.ordering_name();
  s.supernodal = F.supernodal();
  s.size = H.size;
  s.nnz_h = H.nonzeros();
  s.nnz_l = F.factor_nonzeros();
  s.factor_flops = F.factor_flops();
  const linalg::Supernodes nodes = s.supernodal ? F.supernodes() : linalg::Supernodes{};
  s.num_supernodes = static_cast<std::size_t>(nodes.count);
  s.l_storage = static_cast<std::size_t>(F.factor_storage());

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
  const int* perm = F.permutation();
  for (int k = 0; k < n; ++k) I.iperm[static_cast<std::size_t>(perm[k])] = k;
  if (s.supernodal) {
    I.nsuper = nodes.count;
    I.super = nodes.super;
    I.pi = nodes.pi;
    I.px = nodes.px;
    I.ls = nodes.rows;
    I.lx = nodes.x;
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
