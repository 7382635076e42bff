// keel::lie — covariance-accuracy and consistency metrics (thesis §5.7.2, §5.9).
#pragma once

#include <vector>

#include "types.hpp"

namespace keel::lie {

/// eq. 5.56: epsilon = sqrt(tr((S - S_mc)^T (S - S_mc))) = ||S - S_mc||_F.
[[nodiscard]] double covariance_error(const MatX& Sigma, const MatX& Sigma_mc);

/// §5.9.2: both covariances divided by ||S_mc||_F before applying eq. 5.56, i.e.
/// ||S - S_mc||_F / ||S_mc||_F.  Throws if S_mc is zero.
[[nodiscard]] double normalized_covariance_error(const MatX& Sigma, const MatX& Sigma_mc);

/// eq. 5.57: (1/M) sum_m xi_m xi_m^T for samples stored as the columns of `samples`.
MatX sample_covariance_about_zero(const MatX& samples);
MatX sample_covariance_about_zero(const std::vector<VecX>& samples);
/// Column mean of the samples.
VecX sample_mean(const MatX& samples);

/// Regularized lower incomplete gamma function P(a, x) (series for x < a + 1, Lentz continued
/// fraction for Q otherwise).  a > 0, x >= 0.
double regularized_gamma_p(double a, double x);
/// Q(a, x) = 1 - P(a, x), computed without cancellation for large x.
double regularized_gamma_q(double a, double x);

/// CDF of the chi-square distribution with `dof` > 0 degrees of freedom: P(dof/2, x/2).
double chi2_cdf(double x, double dof);
/// Inverse of chi2_cdf: x with chi2_cdf(x, dof) = p, p in [0, 1) (p = 1 gives +inf).
/// Bracketing + safeguarded Newton; relative accuracy ~1e-12.
double chi2_quantile(double p, double dof);

/// v^T cov^-1 v via Cholesky; throws std::invalid_argument if cov is not positive definite
/// or the sizes do not match.
double mahalanobis_squared(const VecX& v, const MatX& cov);

/// Fraction of samples (columns of `samples`, or a vector of samples) with
/// mahalanobis_squared(sample, cov) <= chi2_quantile(p, dim): the share that falls inside the
/// p-probability ellipsoid (e.g. the 99.9% test of Figs. 5.8-5.9).
[[nodiscard]] double fraction_inside(const MatX& samples, const MatX& cov, double p);
[[nodiscard]] double fraction_inside(const std::vector<VecX>& samples, const MatX& cov, double p);

}  // namespace keel::lie
