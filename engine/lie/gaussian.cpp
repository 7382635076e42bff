#include "gaussian.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace keel::lie {

void validate_covariance(const Eigen::Ref<const MatX>& cov, std::string_view what, double rel_tol) {
  auto fail = [&](const std::string& why) { throw std::invalid_argument(fmt::format("{}: {}", what, why)); };
  if (cov.rows() != cov.cols()) {
    fail(fmt::format("covariance must be square, got {}x{}", cov.rows(), cov.cols()));
  }
  if (cov.size() == 0) return;
  if (!cov.allFinite()) fail("covariance has non-finite entries");
  const double scale = cov.cwiseAbs().maxCoeff();
  const double asym = (cov - cov.transpose()).cwiseAbs().maxCoeff();
  if (asym > rel_tol * std::max(scale, 1e-300)) {
    fail(fmt::format("covariance is not symmetric (max |C - C^T| = {:g}, max |C| = {:g})", asym, scale));
  }
  if (scale == 0.0) return;  // zero covariance (a known pose) is valid
  const MatX sym = 0.5 * (cov + cov.transpose());
  Eigen::SelfAdjointEigenSolver<MatX> es(sym, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) fail("eigen-decomposition of the covariance failed");
  const double lmin = es.eigenvalues().minCoeff();
  const double lmax = es.eigenvalues().cwiseAbs().maxCoeff();
  if (lmin < -rel_tol * lmax) {
    fail(fmt::format(
        "covariance is not positive semi-definite (smallest eigenvalue {:g}, largest |eigenvalue| {:g})",
        lmin, lmax));
  }
}

MatX covariance_square_root(const Eigen::Ref<const MatX>& cov) {
  validate_covariance(cov, "covariance_square_root");
  const MatX sym = 0.5 * (cov + cov.transpose());
  Eigen::LLT<MatX> llt(sym);
  if (llt.info() == Eigen::Success) {
    MatX L = llt.matrixL();
    if (L.allFinite()) return L;
  }
  Eigen::SelfAdjointEigenSolver<MatX> es(sym);
  if (es.info() != Eigen::Success)
    throw std::invalid_argument("covariance_square_root: eigen-decomposition failed");
  const VecX s = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return es.eigenvectors() * s.asDiagonal();
}

GaussianSampler::GaussianSampler(const Eigen::Ref<const MatX>& cov) : L_(covariance_square_root(cov)) {}

VecX GaussianSampler::operator()(keel::core::Rng& rng) const {
  VecX z(L_.cols());
  for (Eigen::Index i = 0; i < z.size(); ++i) z(i) = rng.normal();
  return L_ * z;
}

MatX GaussianSampler::sample(keel::core::Rng& rng, int n) const {
  MatX Z(L_.cols(), n);
  for (int j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < Z.rows(); ++i) Z(i, j) = rng.normal();
  return L_ * Z;
}

}  // namespace keel::lie
