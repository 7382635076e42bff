// keel::lie — covariance validation and multivariate-normal sampling helpers.
#pragma once

#include <string_view>

#include "core/random.hpp"
#include "types.hpp"

namespace keel::lie {

/// Relative tolerance used when validating covariances (symmetry and PSD).
inline constexpr double kCovarianceTolerance = 1e-9;

/// Throws std::invalid_argument (message prefixed with `what`) unless `cov` is square,
/// finite, symmetric and positive semi-definite, each up to a tolerance relative to the
/// largest entry / eigenvalue magnitude.
void validate_covariance(const Eigen::Ref<const MatX>& cov, std::string_view what,
                         double rel_tol = kCovarianceTolerance);

/// A matrix L with L L^T = cov.  Uses Cholesky (LLT) when cov is positive definite, and a
/// symmetric eigen-decomposition (negative round-off eigenvalues clamped to 0) when it is
/// only semi-definite.  Validates cov first.
MatX covariance_square_root(const Eigen::Ref<const MatX>& cov);

/// Draws zero-mean samples x = L z, z ~ N(0, I) from keel::core::Rng (identical on every standard library),
/// L = covariance_square_root(cov).
class GaussianSampler {
 public:
  explicit GaussianSampler(const Eigen::Ref<const MatX>& cov);
  int dim() const { return static_cast<int>(L_.rows()); }
  const MatX& factor() const { return L_; }
  VecX operator()(keel::core::Rng& rng) const;
  /// `n` samples as the columns of a dim() x n matrix.
  MatX sample(keel::core::Rng& rng, int n) const;

 private:
  MatX L_;
};

}  // namespace keel::lie
