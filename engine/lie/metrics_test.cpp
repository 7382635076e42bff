// Metrics (eqs. 5.56-5.57, §5.9), chi-square, Mahalanobis and the Gaussian sampler.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "kit/test_kit.hpp"
#include "lie/gaussian.hpp"
#include "lie/metrics.hpp"

using namespace keel::lie;
namespace testkit = keel::testkit;

TEST_CASE("chi2_quantile against tabulated values") {
  CHECK(chi2_quantile(0.95, 6) == doctest::Approx(12.591587).epsilon(1e-7));
  CHECK(chi2_quantile(0.999, 3) == doctest::Approx(16.266236).epsilon(1e-7));
  CHECK(chi2_quantile(0.95, 1) == doctest::Approx(3.841459).epsilon(1e-7));
  CHECK(chi2_quantile(0.5, 2) == doctest::Approx(2.0 * std::log(2.0)).epsilon(1e-12));
  CHECK(chi2_quantile(0.01, 10) == doctest::Approx(2.558212).epsilon(1e-6));
  CHECK(chi2_quantile(0.999, 6) == doctest::Approx(22.457744).epsilon(1e-7));
  CHECK(chi2_quantile(0.99, 100) == doctest::Approx(135.806723).epsilon(1e-7));
  CHECK(chi2_quantile(0.0, 3) == 0.0);
  CHECK(std::isinf(chi2_quantile(1.0, 3)));
}

TEST_CASE("chi2_cdf closed forms and quantile round trips") {
  for (const double x : {0.01, 0.5, 2.0, 7.5, 30.0, 200.0}) {
    CHECK(chi2_cdf(x, 2.0) == doctest::Approx(1.0 - std::exp(-0.5 * x)).epsilon(1e-13));
    CHECK(chi2_cdf(x, 1.0) == doctest::Approx(std::erf(std::sqrt(0.5 * x))).epsilon(1e-13));
    CHECK(regularized_gamma_p(1.0, x) + regularized_gamma_q(1.0, x) == doctest::Approx(1.0));
  }
  CHECK(regularized_gamma_q(3.0, 200.0) > 0.0);  // tiny, no cancellation to 0 - 0
  CHECK(regularized_gamma_q(3.0, 200.0) < 1e-80);
  for (const double dof : {0.5, 1.0, 2.0, 3.0, 6.0, 12.5, 100.0}) {
    for (const double p : {1e-6, 0.01, 0.3, 0.5, 0.9, 0.999, 1.0 - 1e-9}) {
      CAPTURE(dof);
      CAPTURE(p);
      const double x = chi2_quantile(p, dof);
      if (p > 0.5)
        CHECK(regularized_gamma_q(0.5 * dof, 0.5 * x) == doctest::Approx(1.0 - p).epsilon(1e-9));
      else
        CHECK(chi2_cdf(x, dof) == doctest::Approx(p).epsilon(1e-9));
    }
  }
  CHECK_THROWS_AS(chi2_quantile(1.5, 3), std::invalid_argument);
  CHECK_THROWS_AS(chi2_quantile(0.5, 0), std::invalid_argument);
  CHECK_THROWS_AS(chi2_cdf(1.0, -1), std::invalid_argument);
}

TEST_CASE("covariance errors (eq. 5.56 and its normalized form of §5.9.2)") {
  MatX A(2, 2), B(2, 2);
  A << 2, 1, 1, 3;
  B << 1, 0, 0, 1;
  CHECK(covariance_error(A, B) == doctest::Approx(std::sqrt(1 + 1 + 1 + 4)));
  CHECK(covariance_error(A, B) == doctest::Approx(std::sqrt(((A - B).transpose() * (A - B)).trace())));
  CHECK(normalized_covariance_error(A, B) == doctest::Approx(covariance_error(A, B) / std::sqrt(2.0)));
  CHECK(normalized_covariance_error(1e-6 * A, 1e-6 * B) ==
        doctest::Approx(normalized_covariance_error(A, B)));
  CHECK_THROWS_AS((void)covariance_error(A, MatX::Identity(3, 3)), std::invalid_argument);
  CHECK_THROWS_AS((void)normalized_covariance_error(A, MatX::Zero(2, 2)), std::invalid_argument);
}

TEST_CASE("sample covariance about zero (eq. 5.57)") {
  keel::core::Rng rng(401);
  MatX S(3, 50);
  std::vector<VecX> v;
  for (int j = 0; j < 50; ++j) {
    for (int i = 0; i < 3; ++i) S(i, j) = rng.normal() + 1.0;
    v.push_back(S.col(j));
  }
  const MatX expected = S * S.transpose() / 50.0;
  CHECK((sample_covariance_about_zero(S) - expected).norm() < 1e-12);
  CHECK((sample_covariance_about_zero(v) - expected).norm() < 1e-12);
  CHECK((sample_mean(S) - S.rowwise().mean()).norm() < 1e-15);
}

TEST_CASE("mahalanobis_squared and fraction_inside") {
  MatX cov(2, 2);
  cov << 4, 0, 0, 9;
  VecX v(2);
  v << 2, 3;
  CHECK(mahalanobis_squared(v, cov) == doctest::Approx(2.0));
  MatX sing(2, 2);
  sing << 1, 1, 1, 1;
  CHECK_THROWS_AS(mahalanobis_squared(v, sing), std::invalid_argument);
  CHECK_THROWS_AS(mahalanobis_squared(VecX::Zero(3), cov), std::invalid_argument);

  keel::core::Rng rng(402);
  MatX L = MatX::Zero(4, 4);
  L << 1, 0, 0, 0, 0.5, 2, 0, 0, -0.3, 0.2, 0.1, 0, 0.1, 0.4, 0.3, 1.5;
  const MatX C = L * L.transpose();
  const GaussianSampler sampler(C);
  const int M = 100000;
  const MatX samples = sampler.sample(rng, M);
  CHECK((sample_covariance_about_zero(samples) - C).norm() / C.norm() < 0.02);
  for (const double p : {0.5, 0.95, 0.999}) {
    const double f = fraction_inside(samples, C, p);
    const double sd = std::sqrt(p * (1 - p) / M);
    CHECK(std::abs(f - p) < 4.0 * sd + 1e-12);
  }
  std::vector<VecX> vs;
  for (int k = 0; k < 1000; ++k) vs.push_back(samples.col(k));
  CHECK(fraction_inside(vs, C, 0.9) == fraction_inside(MatX(samples.leftCols(1000)), C, 0.9));
  // An over-confident covariance contains fewer samples.
  CHECK(fraction_inside(samples, 0.25 * C, 0.95) < 0.6);
}

TEST_CASE("GaussianSampler handles rank-deficient PSD covariances and rejects others") {
  keel::core::Rng rng(403);
  MatX C = MatX::Zero(3, 3);
  C(0, 0) = 1.0;
  C(0, 1) = C(1, 0) = 1.0;
  C(1, 1) = 1.0;  // rank 1
  const GaussianSampler s(C);
  const MatX x = s.sample(rng, 20000);
  CHECK((x.row(0) - x.row(1)).norm() < 1e-10);
  CHECK(x.row(2).norm() < 1e-10);
  CHECK((covariance_square_root(C) * covariance_square_root(C).transpose() - C).norm() < 1e-12);
  MatX bad = MatX::Identity(2, 2);
  bad(0, 1) = bad(1, 0) = 2.0;
  CHECK_THROWS_AS(GaussianSampler{bad}, std::invalid_argument);
  CHECK_THROWS_AS(validate_covariance(MatX::Identity(2, 3), "test"), std::invalid_argument);
}
