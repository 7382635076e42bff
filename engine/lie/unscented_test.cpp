// Unscented transform and the SSC -> Lie-algebra conversion (thesis §5.8.1, eqs. 5.60-5.62).
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "kit/test_kit.hpp"
#include "lie/euler.hpp"
#include "lie/gaussian.hpp"
#include "lie/metrics.hpp"
#include "lie/unscented.hpp"

using namespace keel::lie;
namespace testkit = keel::testkit;

namespace {

// Linearised (first-order) conversion for comparison: Sigma = J Sigma_hat J^T with J the
// central-difference Jacobian of the stacked l of eq. 5.60 at x_hat.
template <class G>
MatX linearized_conversion(const VecX& x_hat, const MatX& Sigma_hat,
                           const std::function<VecX(const VecX&)>& ell) {
  const MatX J = testkit::numerical_jacobian(ell, x_hat);
  return J * Sigma_hat * J.transpose();
}

}  // namespace

TEST_CASE("sigma points reproduce mean and covariance; weights sum to one") {
  keel::core::Rng rng(301);
  const int n = 5;
  const MatX A = testkit::random_matrix(rng, n, n, 1.0);
  const MatX cov = A * A.transpose();
  const VecX mu = testkit::random_matrix(rng, n, 1, 1.0);
  for (const UtParams p : {UtParams{}, UtParams::julier_uhlmann_heuristic(n), UtParams{1e-3, 2.0, 0.0}}) {
    const SigmaPoints sp = sigma_points(mu, cov, p);
    CHECK(sp.points.cols() == 2 * n + 1);
    CHECK(std::abs(sp.wm.sum() - 1.0) < 1e-9);
    const VecX m = sp.points * sp.wm;
    CHECK((m - mu).norm() < 1e-9 * (1.0 + mu.norm()));
    MatX c = MatX::Zero(n, n);
    for (int k = 0; k < sp.points.cols(); ++k)
      c += sp.wm(k) * (sp.points.col(k) - mu) * (sp.points.col(k) - mu).transpose();
    CHECK((c - cov).norm() < 1e-9 * cov.norm());
  }
}

TEST_CASE("unscented transform is exact for linear maps and for the mean of quadratics") {
  keel::core::Rng rng(302);
  const int n = 4, m = 3;
  const MatX A = testkit::random_matrix(rng, m, n, 1.0);
  const VecX b = testkit::random_matrix(rng, m, 1, 1.0);
  const MatX L = testkit::random_matrix(rng, n, n, 0.5);
  const MatX cov = L * L.transpose();
  const VecX mu = testkit::random_matrix(rng, n, 1, 1.0);
  const UtResult r = unscented_transform(mu, cov, [&](const VecX& x) { return VecX(A * x + b); });
  CHECK((r.mean - (A * mu + b)).norm() < 1e-12);
  CHECK((r.cov - A * cov * A.transpose()).norm() < 1e-12);
  CHECK((r.cross_cov - cov * A.transpose()).norm() < 1e-12);
  // y = x^2 with x ~ N(mu, s^2): E[y] = mu^2 + s^2; Var[y] = 4 mu^2 s^2 + 2 s^4.  Any symmetric
  // sigma set gets the mean; J&U's n + kappa = 3 also gets the variance (Gaussian kurtosis).
  const double mu1 = 1.3, s = 0.7;
  VecX m1(1);
  m1 << mu1;
  MatX c1(1, 1);
  c1 << s * s;
  auto sq = [](const VecX& x) { return VecX(x.array().square()); };
  const UtResult q = unscented_transform(m1, c1, sq, UtParams::julier_uhlmann_heuristic(1));
  CHECK(q.mean(0) == doctest::Approx(mu1 * mu1 + s * s).epsilon(1e-12));
  CHECK(q.cov(0, 0) == doctest::Approx(4 * mu1 * mu1 * s * s + 2 * s * s * s * s).epsilon(1e-12));
  const UtResult q0 = unscented_transform(m1, c1, sq);  // kappa = 0: mean still exact
  CHECK(q0.mean(0) == doctest::Approx(mu1 * mu1 + s * s).epsilon(1e-12));
}

TEST_CASE("SSC -> Lie conversion (eqs. 5.60-5.62) vs Monte Carlo, SE3, moderate noise" *
          doctest::test_suite("monte_carlo")) {
  keel::core::Rng rng(303);
  VecX x_hat(12);
  x_hat << 1.0, 2.0, 0.5, 0.3, -0.4, 1.2, 4.0, -1.0, 0.2, -0.2, 0.3, -2.5;
  // Correlated joint covariance: ~0.2 m translation, ~0.15 rad angles.
  MatX S = MatX::Zero(12, 12);
  Vec6 sd;
  sd << 0.2, 0.2, 0.2, 0.15, 0.15, 0.15;
  const MatX R = testkit::random_matrix(rng, 12, 12, 1.0);
  MatX corr = R * R.transpose();
  const VecX dg = corr.diagonal().cwiseSqrt().cwiseInverse();
  corr = dg.asDiagonal() * corr * dg.asDiagonal();  // random correlation matrix
  VecX sdev(12);
  sdev << sd, sd;
  S = sdev.asDiagonal() * corr * sdev.asDiagonal();

  const JointPoses<SE3> jp = joint_poses_from_ssc(x_hat, S);
  jp.validate();
  CHECK(jp.size() == 2);
  CHECK(jp.means[0].is_approx(se3_from_ssc(x_hat.head<6>()), 1e-15));  // eq. 5.61
  CHECK(jp.means[1].is_approx(se3_from_ssc(x_hat.tail<6>()), 1e-15));

  auto ell = [&](const VecX& x) {
    VecX v(12);
    for (int i = 0; i < 2; ++i)
      v.segment<6>(6 * i) = (se3_from_ssc(x.segment<6>(6 * i)) * jp.means[i].inverse()).log();
    return v;
  };
  const GaussianSampler sampler(S);
  const int M = 100000;
  MatX xi(12, M);
  for (int m = 0; m < M; ++m) xi.col(m) = ell(x_hat + sampler(rng));
  const MatX mc = sample_covariance_about_zero(xi);
  const double e_ut = normalized_covariance_error(jp.cov, mc);
  const double e_lin = normalized_covariance_error(linearized_conversion<SE3>(x_hat, S, ell), mc);
  MESSAGE("SE3 SSC->Lie conversion: normalized eps UT = " << e_ut << ", linearized = " << e_lin);
  CHECK(e_ut < 0.03);
  CHECK(e_lin < 0.03);
  // Which conversion is closer depends on the random correlation matrix at this noise level: over eight
  // instances (seeds 1-7 and 303, M = 3e5) the UT was closer on five and up to 1.6x farther on the others,
  // e.g. 0.0119 vs 0.0107 for this one at M = 1e6. Reported, not required.
  WARN(e_ut < e_lin);
}

TEST_CASE("SSC -> Lie conversion vs Monte Carlo, SE2" * doctest::test_suite("monte_carlo")) {
  keel::core::Rng rng(304);
  VecX x_hat(6);
  x_hat << 1.0, -2.0, 0.8, 3.0, 1.0, -2.9;
  const MatX R = testkit::random_matrix(rng, 6, 6, 0.1);
  const MatX S = R * R.transpose();
  const JointPoses<SE2> jp = joint_poses_from_ssc<SE2>(x_hat, S);
  jp.validate();
  auto ell = [&](const VecX& x) {
    VecX v(6);
    for (int i = 0; i < 2; ++i)
      v.segment<3>(3 * i) = (se2_from_ssc(x.segment<3>(3 * i)) * jp.means[i].inverse()).log();
    return v;
  };
  const GaussianSampler sampler(S);
  const int M = 100000;
  MatX xi(6, M);
  for (int m = 0; m < M; ++m) xi.col(m) = ell(x_hat + sampler(rng));
  const MatX mc = sample_covariance_about_zero(xi);
  const double e_ut = normalized_covariance_error(jp.cov, mc);
  const double e_lin = normalized_covariance_error(linearized_conversion<SE2>(x_hat, S, ell), mc);
  MESSAGE("SE2 SSC->Lie conversion: normalized eps UT = " << e_ut << ", linearized = " << e_lin);
  CHECK(e_ut < 0.03);
}

TEST_CASE("unscented transform rejects bad input") {
  const VecX mu = VecX::Zero(3);
  CHECK_THROWS_AS((void)sigma_points(mu, MatX::Identity(2, 2)), std::invalid_argument);
  MatX neg = MatX::Identity(3, 3);
  neg(1, 1) = -1.0;
  CHECK_THROWS_AS((void)sigma_points(mu, neg), std::invalid_argument);
  CHECK_THROWS_AS((void)sigma_points(mu, MatX::Identity(3, 3), UtParams{1.0, 0.0, -3.0}),
                  std::invalid_argument);
  CHECK_THROWS_AS(joint_poses_from_ssc(VecX::Zero(7), MatX::Identity(7, 7)), std::invalid_argument);
  CHECK_THROWS_AS(joint_poses_from_ssc(VecX::Zero(6), MatX::Identity(5, 5)), std::invalid_argument);
  // A rank-deficient (PSD) covariance is fine.
  MatX psd = MatX::Zero(6, 6);
  psd(0, 0) = 1e-4;
  CHECK_NOTHROW(joint_poses_from_ssc(VecX::Zero(6), psd));
}
