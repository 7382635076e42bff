// Barfoot & Furgale (2014) fourth-order compounding of independent SE(3) poses.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "kit/test_kit.hpp"
#include "lie/gaussian.hpp"
#include "lie/metrics.hpp"
#include "lie/uncertain.hpp"

using namespace keel::lie;
namespace testkit = keel::testkit;

namespace {

Mat6 random_spd6(keel::core::Rng& rng, double scale) {
  const Mat6 A = testkit::random_matrix(rng, 6, 6, scale);
  return A * A.transpose() + 0.1 * scale * scale * Mat6::Identity();
}

Mat6 basis_curly(int a) {
  Vec6 e = Vec6::Zero();
  e(a) = 1.0;
  return SE3::curly_hat(e);
}

// Exact Gaussian expectations written as sums over the basis of se(3):
// E[xi^c M xi^c^T] = sum_ab Sigma_ab G_a M G_b^T,  E[xi^c xi^c] = sum_ab Sigma_ab G_a G_b.
Mat6 expected_sandwich(const Mat6& Sigma, const Mat6& M) {
  Mat6 out = Mat6::Zero();
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b) out += Sigma(a, b) * basis_curly(a) * M * basis_curly(b).transpose();
  return out;
}
Mat6 expected_square(const Mat6& Sigma) {
  Mat6 out = Mat6::Zero();
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b) out += Sigma(a, b) * basis_curly(a) * basis_curly(b);
  return out;
}

struct ChainErrors {
  double first = 0, fourth = 0;
};

// Independent chain T_1 ... T_N, T_k = exp(xi_k) T_bar, xi_k ~ N(0, Sigma_k).
ChainErrors chain_vs_monte_carlo(const std::vector<UncertainPose<SE3>>& steps, int M, keel::core::Rng& rng) {
  const UncertainPose<SE3> first = compose_chain(steps);
  const UncertainPose<SE3> fourth = compose_chain_fourth_order(steps);
  CHECK(first.mean.is_approx(fourth.mean, 1e-12));
  std::vector<GaussianSampler> samplers;
  for (const auto& s : steps) samplers.emplace_back(s.cov);
  const SE3 mean_inv = first.mean.inverse();
  MatX xi(6, M);
  for (int m = 0; m < M; ++m) {
    SE3 acc;
    for (std::size_t k = 0; k < steps.size(); ++k)
      acc = acc * SE3::exp(Vec6(samplers[k](rng))) * steps[k].mean;
    xi.col(m) = (acc * mean_inv).log();
  }
  const MatX mc = sample_covariance_about_zero(xi);
  return {normalized_covariance_error(first.cov, mc), normalized_covariance_error(fourth.cov, mc)};
}

}  // namespace

TEST_CASE("<<.>> operators equal the exact Gaussian expectations") {
  keel::core::Rng rng(201);
  for (int trial = 0; trial < 10; ++trial) {
    const Mat6 S1 = random_spd6(rng, 0.3);
    const Mat6 S2 = random_spd6(rng, 0.5);
    CHECK((double_bracket(S1) - expected_square(S1)).norm() < 1e-13);
    CHECK((fourth_order_b_matrix(S1, S2) - expected_sandwich(S1, S2)).norm() < 1e-13);
  }
  // 3x3 identities: E[u^ u^] = <<Sigma>>, E[u^ M u^^T] = <<Sigma, M>> for symmetric M.
  const Mat3 S = random_spd6(rng, 1.0).topLeftCorner<3, 3>();
  Mat3 sq = Mat3::Zero(), sw = Mat3::Zero();
  const Mat3 Mm = random_spd6(rng, 1.0).bottomRightCorner<3, 3>();
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      sq += S(a, b) * SO3::hat(Vec3::Unit(a)) * SO3::hat(Vec3::Unit(b));
      sw += S(a, b) * SO3::hat(Vec3::Unit(a)) * Mm * SO3::hat(Vec3::Unit(b)).transpose();
    }
  CHECK((double_bracket(S) - sq).norm() < 1e-13);
  CHECK((double_bracket(S, Mm) - sw).norm() < 1e-13);
}

TEST_CASE("fourth-order compounding reduces to first order as the noise vanishes") {
  keel::core::Rng rng(202);
  Vec6 xi;
  xi << 1.0, 0.2, -0.3, 0.4, -0.2, 0.7;
  const SE3 A = SE3::exp(xi), B = SE3::exp(-0.5 * xi);
  for (const double s : {1e-2, 1e-3, 1e-4}) {
    const UncertainPose<SE3> a(A, random_spd6(rng, s)), b(B, random_spd6(rng, s));
    const Mat6 d = compose_fourth_order(a, b).cov - compose(a, b).cov;
    // The correction is fourth order in the perturbations: relative size O(s^2).
    CHECK(d.norm() / compose(a, b).cov.norm() < 50.0 * s * s);
  }
}

TEST_CASE("fourth-order compounding vs Monte Carlo (Barfoot-Furgale style chain)" *
          doctest::test_suite("monte_carlo")) {
  keel::core::Rng rng(203);
  // T_bar = [I | (1, 0, 0)] (eq. 5.42); per-step covariance in the spirit of eq. 5.41 but with
  // moderate isotropic rotational noise (sigma_phi ~ 0.1 rad per step).
  Mat4 Tm = Mat4::Identity();
  Tm(0, 3) = 1.0;
  const SE3 Tbar = SE3::from_matrix(Tm);
  const int M = 60000;
  // N = 10 steps T_bar = [I | (1, 0, 0)] (eq. 5.42) with isotropic noise: sigma_rho = 0.1 m,
  // sigma_phi = 0.05 / 0.2 rad per step.  A 10^6-sample study gave normalized errors
  // (first, fourth) = (0.004, 0.002) at sigma_phi = 0.05 and (0.051, 0.003) at 0.2, with a
  // Monte-Carlo noise floor ~0.002; with M = 6e4 the floor is ~0.008.
  for (const double sigma_phi : {0.05, 0.2}) {
    Vec6 d;
    d << 0.01, 0.01, 0.01, sigma_phi * sigma_phi, sigma_phi * sigma_phi, sigma_phi * sigma_phi;
    const std::vector<UncertainPose<SE3>> steps(10, UncertainPose<SE3>(Tbar, d.asDiagonal()));
    const ChainErrors e = chain_vs_monte_carlo(steps, M, rng);
    MESSAGE("N=10, sigma_phi=" << sigma_phi << ": normalized eps first order = " << e.first
                               << ", fourth order = " << e.fourth);
    CHECK(e.fourth < 0.02);
    if (sigma_phi > 0.1) {
      CHECK(e.first > 0.03);
      CHECK(e.fourth < 0.5 * e.first);
    } else {
      CHECK(e.first < 0.02);
    }
  }
  // Single compounding, moderate rotational noise, two generic poses.
  {
    Vec6 x1, x2;
    x1 << 1.0, 0.5, -0.2, 0.3, -0.4, 0.9;
    x2 << 2.0, -1.0, 0.5, -0.6, 0.2, 0.3;
    const UncertainPose<SE3> a(SE3::exp(x1), random_spd6(rng, 0.08));
    const UncertainPose<SE3> b(SE3::exp(x2), random_spd6(rng, 0.08));
    const ChainErrors e = chain_vs_monte_carlo({a, b}, 100000, rng);
    MESSAGE("single compounding, random covariances (sigma ~0.2): first = " << e.first
                                                                            << ", fourth = " << e.fourth);
    CHECK(e.fourth < 0.05);
  }
}
