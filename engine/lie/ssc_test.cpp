// SSC baseline (thesis §5.3): analytic Jacobians, consistency with the group operations,
// and first-order covariance propagation against Monte Carlo.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "kit/test_kit.hpp"
#include "lie/euler.hpp"
#include "lie/gaussian.hpp"
#include "lie/metrics.hpp"
#include "lie/ssc.hpp"

using namespace keel::lie;
namespace testkit = keel::testkit;

namespace {

// Euler parameters (x, y, z, roll, pitch, yaw): positions in [-5, 5], angles in [-π, π], |pitch| <=
// max_pitch.
Vec6 random_x6(keel::core::Rng& rng, double max_pitch = 1.3) {
  Vec6 x;
  for (int i = 0; i < 3; ++i) x(i) = rng.uniform(-5.0, 5.0);
  x(3) = rng.uniform(-kPi, kPi);
  x(4) = rng.uniform(-max_pitch, max_pitch);
  x(5) = rng.uniform(-kPi, kPi);
  return x;
}

// Planar parameters (x, y, θ).
Vec3 random_x3(keel::core::Rng& rng) {
  Vec3 x;
  x(0) = rng.uniform(-5.0, 5.0);
  x(1) = rng.uniform(-5.0, 5.0);
  x(2) = rng.uniform(-kPi, kPi);
  return x;
}

// Differences of SSC vectors with angle components wrapped.
Vec6 diff6(const Vec6& a, const Vec6& b) {
  Vec6 d = a - b;
  for (int i = 3; i < 6; ++i) d(i) = wrap_angle(d(i));
  return d;
}
Vec3 diff3(const Vec3& a, const Vec3& b) {
  Vec3 d = a - b;
  d(2) = wrap_angle(d(2));
  return d;
}

// Central-difference Jacobian of f at x (the shared kit's), with differences taken about f(x) and their
// angles wrapped, so a step that crosses ±π does not produce a 2π jump.
template <int N, class F>
Eigen::Matrix<double, N, N> numeric_jac(F f, const Eigen::Matrix<double, N, 1>& x) {
  using V = Eigen::Matrix<double, N, 1>;
  const V f0 = f(x);
  auto wrapped = [&](const VecX& y) -> VecX {
    if constexpr (N == 6)
      return diff6(f(Vec6(y)), f0);
    else
      return diff3(f(Vec3(y)), f0);
  };
  return testkit::numerical_jacobian(wrapped, VecX(x));
}

}  // namespace

TEST_CASE("SSC 3D operations agree with SE(3) matrix products") {
  keel::core::Rng rng(21);
  for (int i = 0; i < 200; ++i) {
    const Vec6 a = random_x6(rng), b = random_x6(rng);
    const SE3 A = se3_from_ssc(a), B = se3_from_ssc(b);
    CHECK(se3_from_ssc(ssc::head_to_tail(a, b)).is_approx(A * B, 1e-11));
    CHECK(se3_from_ssc(ssc::inverse(a)).is_approx(A.inverse(), 1e-11));
    CHECK(se3_from_ssc(ssc::tail_to_tail(a, b)).is_approx(A.inverse() * B, 1e-11));
    // tail-to-tail = (-a) (+) b (eq. 5.24)
    CHECK(diff6(ssc::tail_to_tail(a, b), ssc::head_to_tail(ssc::inverse(a), b)).norm() < 1e-10);
  }
}

TEST_CASE("SSC 2D operations agree with SE(2) matrix products") {
  keel::core::Rng rng(22);
  for (int i = 0; i < 200; ++i) {
    const Vec3 a = random_x3(rng), b = random_x3(rng);
    const SE2 A = se2_from_ssc(a), B = se2_from_ssc(b);
    CHECK(se2_from_ssc(ssc::head_to_tail(a, b)).is_approx(A * B, 1e-12));
    CHECK(se2_from_ssc(ssc::inverse(a)).is_approx(A.inverse(), 1e-12));
    CHECK(se2_from_ssc(ssc::tail_to_tail(a, b)).is_approx(A.inverse() * B, 1e-12));
    const Vec3 c = ssc::head_to_tail(a, b);
    CHECK(c(2) > -kPi);
    CHECK(c(2) <= kPi);
  }
}

TEST_CASE("SSC 3D analytic Jacobians match central differences") {
  keel::core::Rng rng(23);
  for (int i = 0; i < 100; ++i) {
    const Vec6 a = random_x6(rng), b = random_x6(rng);
    CAPTURE(a.transpose());
    CAPTURE(b.transpose());
    Mat6 J1, J2, Ji;
    ssc::head_to_tail(a, b, &J1, &J2);
    CHECK((J1 - numeric_jac<6>([&](const Vec6& x) { return ssc::head_to_tail(x, b); }, a)).norm() < 1e-6);
    CHECK((J2 - numeric_jac<6>([&](const Vec6& x) { return ssc::head_to_tail(a, x); }, b)).norm() < 1e-6);
    ssc::inverse(a, &Ji);
    CHECK((Ji - numeric_jac<6>([&](const Vec6& x) { return ssc::inverse(x); }, a)).norm() < 1e-6);
    ssc::tail_to_tail(a, b, &J1, &J2);
    CHECK((J1 - numeric_jac<6>([&](const Vec6& x) { return ssc::tail_to_tail(x, b); }, a)).norm() < 1e-6);
    CHECK((J2 - numeric_jac<6>([&](const Vec6& x) { return ssc::tail_to_tail(a, x); }, b)).norm() < 1e-6);
    // Chain rule consistency: J_tail_to_tail = J_(+) * blockdiag(J_(-), I).
    Mat6 Jh1, Jh2;
    ssc::head_to_tail(ssc::inverse(a), b, &Jh1, &Jh2);
    CHECK((J1 - Jh1 * Ji).norm() < 1e-9 * (1.0 + J1.norm()));
    CHECK((J2 - Jh2).norm() < 1e-9 * (1.0 + J2.norm()));
  }
}

TEST_CASE("SSC 2D analytic Jacobians match central differences") {
  keel::core::Rng rng(24);
  for (int i = 0; i < 100; ++i) {
    const Vec3 a = random_x3(rng), b = random_x3(rng);
    Mat3 J1, J2, Ji;
    ssc::head_to_tail(a, b, &J1, &J2);
    CHECK((J1 - numeric_jac<3>([&](const Vec3& x) { return ssc::head_to_tail(x, b); }, a)).norm() < 1e-7);
    CHECK((J2 - numeric_jac<3>([&](const Vec3& x) { return ssc::head_to_tail(a, x); }, b)).norm() < 1e-7);
    ssc::inverse(a, &Ji);
    CHECK((Ji - numeric_jac<3>([&](const Vec3& x) { return ssc::inverse(x); }, a)).norm() < 1e-7);
    ssc::tail_to_tail(a, b, &J1, &J2);
    CHECK((J1 - numeric_jac<3>([&](const Vec3& x) { return ssc::tail_to_tail(x, b); }, a)).norm() < 1e-7);
    CHECK((J2 - numeric_jac<3>([&](const Vec3& x) { return ssc::tail_to_tail(a, x); }, b)).norm() < 1e-7);
  }
}

TEST_CASE("SSC Jacobians throw at gimbal lock") {
  Vec6 a;
  a << 1, 2, 3, 0.1, 0.5 * kPi, 0.2;
  const Vec6 b = Vec6::Zero();
  Mat6 J1;
  bool threw = false;
  try {
    ssc::head_to_tail(a, b, &J1);
  } catch (const std::invalid_argument& e) {
    threw = std::string(e.what()).find("gimbal lock") != std::string::npos;
  }
  CHECK(threw);
  CHECK_NOTHROW(ssc::head_to_tail(a, b));  // the mean itself is fine
}

TEST_CASE("SSC first-order propagation matches Monte Carlo at small noise" *
          doctest::test_suite("monte_carlo")) {
  keel::core::Rng rng(25);
  Vec6 a, b;
  a << 1.0, 0.5, -0.2, 0.2, -0.3, 0.8;
  b << 0.7, -1.0, 0.4, -0.5, 0.1, 1.9;
  // Correlated joint covariance (sigma ~ 1e-3).
  MatX L = testkit::random_matrix(rng, 12, 12, 5e-4);
  Mat12 joint = L * L.transpose() + 1e-7 * Mat12::Identity();
  const GaussianSampler sampler(joint);
  const int M = 100000;
  MatX d_h2t(6, M), d_t2t(6, M), d_inv(6, M);
  const Vec6 m_h2t = ssc::head_to_tail(a, b), m_t2t = ssc::tail_to_tail(a, b), m_inv = ssc::inverse(a);
  for (int m = 0; m < M; ++m) {
    const VecX n = sampler(rng);
    const Vec6 an = a + n.head<6>(), bn = b + n.tail<6>();
    d_h2t.col(m) = diff6(ssc::head_to_tail(an, bn), m_h2t);
    d_t2t.col(m) = diff6(ssc::tail_to_tail(an, bn), m_t2t);
    d_inv.col(m) = diff6(ssc::inverse(an), m_inv);
  }
  const ssc::Estimate3D h2t = ssc::head_to_tail(a, b, joint);
  const ssc::Estimate3D t2t = ssc::tail_to_tail(a, b, joint);
  const ssc::Estimate3D inv = ssc::inverse(ssc::Estimate3D{a, joint.topLeftCorner<6, 6>()});
  CHECK((h2t.mean - m_h2t).norm() == 0.0);
  CHECK(normalized_covariance_error(h2t.cov, sample_covariance_about_zero(d_h2t)) < 0.02);
  CHECK(normalized_covariance_error(t2t.cov, sample_covariance_about_zero(d_t2t)) < 0.02);
  CHECK(normalized_covariance_error(inv.cov, sample_covariance_about_zero(d_inv)) < 0.02);
  // Ignoring the cross-covariance is measurably wrong here.
  Mat12 blockdiag = joint;
  blockdiag.topRightCorner<6, 6>().setZero();
  blockdiag.bottomLeftCorner<6, 6>().setZero();
  CHECK(normalized_covariance_error(ssc::head_to_tail(a, b, blockdiag).cov,
                                    sample_covariance_about_zero(d_h2t)) > 0.1);
}

TEST_CASE("SSC 2D propagation matches Monte Carlo at small noise" * doctest::test_suite("monte_carlo")) {
  keel::core::Rng rng(26);
  const Vec3 a(1.0, 2.0, 0.7), b(-0.5, 1.5, -2.2);
  MatX L = testkit::random_matrix(rng, 6, 6, 5e-4);
  Mat6 joint = L * L.transpose() + 1e-7 * Mat6::Identity();
  const GaussianSampler sampler(joint);
  const int M = 100000;
  MatX d_h2t(3, M), d_t2t(3, M), d_inv(3, M);
  for (int m = 0; m < M; ++m) {
    const VecX n = sampler(rng);
    const Vec3 an = a + n.head<3>(), bn = b + n.tail<3>();
    d_h2t.col(m) = diff3(ssc::head_to_tail(an, bn), ssc::head_to_tail(a, b));
    d_t2t.col(m) = diff3(ssc::tail_to_tail(an, bn), ssc::tail_to_tail(a, b));
    d_inv.col(m) = diff3(ssc::inverse(an), ssc::inverse(a));
  }
  CHECK(normalized_covariance_error(ssc::head_to_tail(a, b, joint).cov, sample_covariance_about_zero(d_h2t)) <
        0.02);
  CHECK(normalized_covariance_error(ssc::tail_to_tail(a, b, joint).cov, sample_covariance_about_zero(d_t2t)) <
        0.02);
  CHECK(normalized_covariance_error(ssc::inverse(ssc::Estimate2D{a, joint.topLeftCorner<3, 3>()}).cov,
                                    sample_covariance_about_zero(d_inv)) < 0.02);
}

TEST_CASE("SSC chain uses the full joint covariance") {
  keel::core::Rng rng(27);
  const int N = 5;
  VecX x(6 * N);
  for (int k = 0; k < N; ++k) {
    Vec6 s;
    s << 1.0, 0.1 * k, -0.05, 0.1, -0.05 * k, 0.3;
    x.segment<6>(6 * k) = s;
  }
  MatX L = testkit::random_matrix(rng, 6 * N, 6 * N, 2e-4);
  const MatX joint = L * L.transpose() + 1e-8 * MatX::Identity(6 * N, 6 * N);
  const ssc::Estimate3D chain = ssc::head_to_tail_chain_3d(x, joint);

  // Two-element chain equals the pairwise helper.
  const ssc::Estimate3D two = ssc::head_to_tail_chain_3d(x.head<12>(), joint.topLeftCorner(12, 12));
  const ssc::Estimate3D pair =
      ssc::head_to_tail(Vec6(x.head<6>()), Vec6(x.segment<6>(6)), Mat12(joint.topLeftCorner(12, 12)));
  CHECK((two.mean - pair.mean).norm() < 1e-14);
  CHECK((two.cov - pair.cov).norm() < 1e-14 * (1.0 + pair.cov.norm()));

  // Monte Carlo.
  const GaussianSampler sampler(joint);
  const int M = 60000;
  MatX d(6, M);
  for (int m = 0; m < M; ++m) {
    const VecX xn = x + sampler(rng);
    Vec6 acc = xn.head<6>();
    for (int k = 1; k < N; ++k) acc = ssc::head_to_tail(acc, Vec6(xn.segment<6>(6 * k)));
    d.col(m) = diff6(acc, chain.mean);
  }
  CHECK(normalized_covariance_error(chain.cov, sample_covariance_about_zero(d)) < 0.03);

  // 2D chain.
  VecX x2(3 * N);
  for (int k = 0; k < N; ++k) x2.segment<3>(3 * k) = Vec3(1.0, 0.2, 0.3 - 0.1 * k);
  MatX L2 = testkit::random_matrix(rng, 3 * N, 3 * N, 5e-4);
  const MatX joint2 = L2 * L2.transpose();
  const ssc::Estimate2D chain2 = ssc::head_to_tail_chain_2d(x2, joint2);
  const GaussianSampler sampler2(joint2);
  MatX d2(3, M);
  for (int m = 0; m < M; ++m) {
    const VecX xn = x2 + sampler2(rng);
    Vec3 acc = xn.head<3>();
    for (int k = 1; k < N; ++k) acc = ssc::head_to_tail(acc, Vec3(xn.segment<3>(3 * k)));
    d2.col(m) = diff3(acc, chain2.mean);
  }
  CHECK(normalized_covariance_error(chain2.cov, sample_covariance_about_zero(d2)) < 0.03);
}

TEST_CASE("SSC helpers reject bad covariances and sizes") {
  const Vec6 a = Vec6::Zero(), b = Vec6::Zero();
  Mat12 bad = Mat12::Identity();
  bad(0, 0) = -1.0;
  CHECK_THROWS_AS(ssc::head_to_tail(a, b, bad), std::invalid_argument);
  Mat12 asym = Mat12::Identity();
  asym(0, 1) = 0.5;
  CHECK_THROWS_AS(ssc::tail_to_tail(a, b, asym), std::invalid_argument);
  CHECK_THROWS_AS(ssc::head_to_tail_chain_3d(VecX::Zero(7), MatX::Identity(7, 7)), std::invalid_argument);
  CHECK_THROWS_AS(ssc::head_to_tail_chain_3d(VecX::Zero(12), MatX::Identity(6, 6)), std::invalid_argument);
  CHECK_THROWS_AS(ssc::head_to_tail_chain_2d(VecX::Zero(6), MatX::Identity(5, 5)), std::invalid_argument);
}
