#include "metrics.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

namespace keel::lie {

double covariance_error(const MatX& Sigma, const MatX& Sigma_mc) {
  if (Sigma.rows() != Sigma_mc.rows() || Sigma.cols() != Sigma_mc.cols())
    throw std::invalid_argument("covariance_error: covariance sizes differ");
  return (Sigma - Sigma_mc).norm();  // Frobenius = sqrt(tr(D^T D))
}

double normalized_covariance_error(const MatX& Sigma, const MatX& Sigma_mc) {
  const double n = Sigma_mc.norm();
  if (!(n > 0.0)) throw std::invalid_argument("normalized_covariance_error: Monte-Carlo covariance is zero");
  return covariance_error(Sigma / n, Sigma_mc / n);
}

MatX sample_covariance_about_zero(const MatX& samples) {
  if (samples.cols() == 0) throw std::invalid_argument("sample_covariance_about_zero: no samples");
  MatX S = samples * samples.transpose() / static_cast<double>(samples.cols());
  return 0.5 * (S + S.transpose());
}

MatX sample_covariance_about_zero(const std::vector<VecX>& samples) {
  if (samples.empty()) throw std::invalid_argument("sample_covariance_about_zero: no samples");
  const Eigen::Index d = samples.front().size();
  MatX S = MatX::Zero(d, d);
  for (const VecX& s : samples) {
    if (s.size() != d)
      throw std::invalid_argument("sample_covariance_about_zero: samples of different sizes");
    S.selfadjointView<Eigen::Lower>().rankUpdate(s);
  }
  S = S.selfadjointView<Eigen::Lower>();
  return S / static_cast<double>(samples.size());
}

VecX sample_mean(const MatX& samples) {
  if (samples.cols() == 0) throw std::invalid_argument("sample_mean: no samples");
  return samples.rowwise().mean();
}

namespace {

constexpr double kEps = 1e-16;
constexpr int kMaxIter = 100000;

void check_gamma_args(double a, double x, const char* fn) {
  if (!(a > 0.0) || !std::isfinite(a)) throw std::invalid_argument(fmt::format("{}: a must be positive", fn));
  if (!(x >= 0.0)) throw std::invalid_argument(fmt::format("{}: x must be non-negative", fn));
}

// P(a, x) by the series e^{-x} x^a / Gamma(a) sum_n x^n / (a (a+1) ... (a+n)); for x < a + 1.
double gamma_p_series(double a, double x) {
  double ap = a;
  double term = 1.0 / a;
  double sum = term;
  for (int n = 0; n < kMaxIter; ++n) {
    ap += 1.0;
    term *= x / ap;
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEps) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Q(a, x) by the continued fraction (modified Lentz); for x >= a + 1.
double gamma_q_continued_fraction(double a, double x) {
  constexpr double tiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / tiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < kMaxIter; ++i) {
    const double an = -static_cast<double>(i) * (static_cast<double>(i) - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEps) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double regularized_gamma_p(double a, double x) {
  check_gamma_args(a, x, "regularized_gamma_p");
  if (x == 0.0) return 0.0;
  if (std::isinf(x)) return 1.0;
  if (x < a + 1.0) return gamma_p_series(a, x);
  return 1.0 - gamma_q_continued_fraction(a, x);
}

double regularized_gamma_q(double a, double x) {
  check_gamma_args(a, x, "regularized_gamma_q");
  if (x == 0.0) return 1.0;
  if (std::isinf(x)) return 0.0;
  if (x < a + 1.0) return 1.0 - gamma_p_series(a, x);
  return gamma_q_continued_fraction(a, x);
}

double chi2_cdf(double x, double dof) {
  if (!(dof > 0.0)) throw std::invalid_argument("chi2_cdf: degrees of freedom must be positive");
  if (x <= 0.0) return 0.0;
  return regularized_gamma_p(0.5 * dof, 0.5 * x);
}

double chi2_quantile(double p, double dof) {
  if (!(dof > 0.0)) throw std::invalid_argument("chi2_quantile: degrees of freedom must be positive");
  if (!(p >= 0.0 && p <= 1.0)) throw std::invalid_argument("chi2_quantile: p must be in [0, 1]");
  if (p == 0.0) return 0.0;
  if (p == 1.0) return std::numeric_limits<double>::infinity();
  const double a = 0.5 * dof;
  // Residual in the better-conditioned tail: lower tail for p <= 1/2, upper tail otherwise.
  const bool upper = p > 0.5;
  const double target = upper ? 1.0 - p : p;
  auto residual = [&](double x) {  // increasing in x
    return upper ? target - regularized_gamma_q(a, 0.5 * x) : regularized_gamma_p(a, 0.5 * x) - target;
  };
  auto pdf = [&](double x) {
    return std::exp((a - 1.0) * std::log(0.5 * x) - 0.5 * x - std::lgamma(a)) * 0.5;
  };
  // Bracket the root.
  double lo = 0.0;
  double hi = std::max(1.0, dof);
  while (residual(hi) < 0.0) {
    lo = hi;
    hi *= 2.0;
    if (hi > 1e300) return std::numeric_limits<double>::infinity();
  }
  double x = 0.5 * (lo + hi);
  // Relative tolerances only: for small dof and p the root can be many orders of magnitude below 1.
  for (int it = 0; it < 2000; ++it) {
    const double r = residual(x);
    if (r == 0.0) return x;
    if (r < 0.0)
      lo = x;
    else
      hi = x;
    const double dens = pdf(x);
    double next = (dens > 0.0 && std::isfinite(dens)) ? x - r / dens : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // safeguard: bisect
    if (std::abs(next - x) <= 1e-14 * next) return next;
    if (hi - lo <= 1e-15 * hi) return 0.5 * (lo + hi);
    x = next;
  }
  return x;
}

double mahalanobis_squared(const VecX& v, const MatX& cov) {
  if (cov.rows() != cov.cols() || cov.rows() != v.size()) {
    throw std::invalid_argument(fmt::format("mahalanobis_squared: vector of size {} with a {}x{} covariance",
                                            v.size(), cov.rows(), cov.cols()));
  }
  Eigen::LLT<MatX> llt(cov);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("mahalanobis_squared: covariance is not positive definite");
  const VecX w = llt.matrixL().solve(v);
  return w.squaredNorm();
}

namespace {

double fraction_inside_impl(const MatX& cov, double p, Eigen::Index n, Eigen::Index dim,
                            const std::function<VecX(Eigen::Index)>& get) {
  if (n == 0) throw std::invalid_argument("fraction_inside: no samples");
  if (cov.rows() != cov.cols() || cov.rows() != dim)
    throw std::invalid_argument("fraction_inside: sample dimension does not match the covariance");
  Eigen::LLT<MatX> llt(cov);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("fraction_inside: covariance is not positive definite");
  const double thr = chi2_quantile(p, static_cast<double>(dim));
  Eigen::Index inside = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const VecX s = get(k);
    if (s.size() != dim) throw std::invalid_argument("fraction_inside: samples of different sizes");
    if (llt.matrixL().solve(s).squaredNorm() <= thr) ++inside;
  }
  return static_cast<double>(inside) / static_cast<double>(n);
}

}  // namespace

double fraction_inside(const MatX& samples, const MatX& cov, double p) {
  return fraction_inside_impl(cov, p, samples.cols(), samples.rows(),
                              [&](Eigen::Index k) { return VecX(samples.col(k)); });
}

double fraction_inside(const std::vector<VecX>& samples, const MatX& cov, double p) {
  const Eigen::Index dim = samples.empty() ? cov.rows() : samples.front().size();
  return fraction_inside_impl(cov, p, static_cast<Eigen::Index>(samples.size()), dim,
                              [&](Eigen::Index k) { return samples[static_cast<std::size_t>(k)]; });
}

}  // namespace keel::lie
