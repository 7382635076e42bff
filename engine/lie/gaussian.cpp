#include "gaussian.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace keel::lie {

void validate_covariance(const Eigen::Ref<const MatX>& cov, std::string_view what, double rel_tol) {
  auto fail = [&](const std::string& why) {
    throw std::invalid_argument(std::string(what) + ": " + why);
  };
  if (cov.rows() != cov.cols()) {
    std::ostringstream os;
    os << "covariance must be square, got " << cov.rows() << "x" << cov.cols();
    fail(os.str());
  }
  if (cov.size() == 0) return;
  if (!cov.allFinite()) fail("covariance has non-finite entries");
  const double scale = cov.cwiseAbs().maxCoeff();
  const double asym = (cov - cov.transpose()).cwiseAbs().maxCoeff();
  if (asym > rel_tol * std::max(scale, 1e-300)) {
    std::ostringstream os;
    os << "covariance is not symmetric (max |C - C^T| = " << asym << ", max |C| = " << scale << ")";
    fail(os.str());
  }
  if (scale == 0.0) return;  // zero covariance (a known pose) is valid
  const MatX sym = 0.5 * (cov + cov.transpose());
  Eigen::SelfAdjointEigenSolver<MatX> es(sym, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) fail("eigen-decomposition of the covariance failed");
  const double lmin = es.eigenvalues().minCoeff();
  const double lmax = es.eigenvalues().cwiseAbs().maxCoeff();
  if (lmin < -rel_tol * lmax) {
    std::ostringstream os;
    os << "covariance is not positive semi-definite (smallest eigenvalue " << lmin << ", largest |eigenvalue| "
       << lmax << ")";
    fail(os.str());
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

VecX GaussianSampler::operator()(std::mt19937_64& rng) const {
  std::normal_distribution<double> n01(0.0, 1.0);
  VecX z(L_.cols());
  for (Eigen::Index i = 0; i < z.size(); ++i) z(i) = n01(rng);
  return L_ * z;
}

MatX GaussianSampler::sample(std::mt19937_64& rng, int n) const {
  std::normal_distribution<double> n01(0.0, 1.0);
  MatX Z(L_.cols(), n);
  for (int j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < Z.rows(); ++i) Z(i, j) = n01(rng);
  return L_ * Z;
}

}  // namespace keel::lie
