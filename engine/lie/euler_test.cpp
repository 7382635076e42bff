// Euler-angle (SSC, eq. 5.15) parameterisation tests.
#include <doctest/doctest.h>

#include <cmath>

#include "kit/test_kit.hpp"
#include "lie/euler.hpp"

using namespace keel::lie;
namespace testkit = keel::testkit;

TEST_CASE("wrap_angle maps to (-pi, pi]") {
  CHECK(wrap_angle(0.5) == doctest::Approx(0.5));
  CHECK(wrap_angle(kPi) == doctest::Approx(kPi));
  CHECK(wrap_angle(-kPi) == doctest::Approx(kPi));
  CHECK(wrap_angle(3.0 * kPi) == doctest::Approx(kPi));
  CHECK(wrap_angle(-1.5 * kPi) == doctest::Approx(0.5 * kPi));
  CHECK(wrap_angle(2.0 * kPi + 0.25) == doctest::Approx(0.25));
  CHECK(wrap_angle(-7.0) == doctest::Approx(-7.0 + 2.0 * kPi));
  keel::core::Rng rng(11);
  for (int i = 0; i < 1000; ++i) {
    const double a = rng.uniform(-50.0, 50.0);
    const double w = wrap_angle(a);
    CHECK(w > -kPi);
    CHECK(w <= kPi);
    CHECK(std::abs(std::remainder(a - w, 2.0 * kPi)) < 1e-12);
  }
}

TEST_CASE("rotation_from_rpy is Rz(yaw) Ry(pitch) Rx(roll)") {
  const double r = 0.3, p = -0.7, y = 2.1;
  const Mat3 expected =
      SO3::exp(Vec3(0, 0, y)).matrix() * SO3::exp(Vec3(0, p, 0)).matrix() * SO3::exp(Vec3(r, 0, 0)).matrix();
  CHECK((rotation_from_rpy(r, p, y) - expected).norm() < 1e-15);
}

TEST_CASE("SE3 <-> SSC round trip") {
  keel::core::Rng rng(12);
  auto ang = [&] { return rng.uniform(-kPi + 1e-6, kPi); };
  auto pit = [&] { return rng.uniform(-0.5 * kPi + 1e-3, 0.5 * kPi - 1e-3); };
  auto pos = [&] { return rng.uniform(-10.0, 10.0); };
  for (int i = 0; i < 500; ++i) {
    Vec6 x;
    x << pos(), pos(), pos(), ang(), pit(), ang();
    const SE3 T = se3_from_ssc(x);
    CHECK((T.translation() - x.head<3>()).norm() == 0.0);
    CHECK((T.rotation() - rotation_from_rpy(x(3), x(4), x(5))).norm() < 1e-15);
    const Vec6 back = ssc_from_se3(T);
    CHECK((back - x).norm() < 1e-12);
    // Matrix -> SSC -> matrix for arbitrary rotations (outside the principal ranges too).
    const SE3 R = SE3::exp((Vec6() << pos(), pos(), pos(), ang(), ang(), ang()).finished());
    CHECK(se3_from_ssc(ssc_from_se3(R)).is_approx(R, 1e-12));
    const Vec6 xr = ssc_from_se3(R);
    CHECK(std::abs(xr(4)) <= 0.5 * kPi);
    CHECK(xr(3) > -kPi);
    CHECK(xr(5) <= kPi);
  }
}

TEST_CASE("SSC at gimbal lock is deterministic and reproduces the rotation") {
  for (const double pitch : {0.5 * kPi, -0.5 * kPi}) {
    for (const double roll : {0.0, 0.4, -2.0}) {
      Vec6 x;
      x << 1.0, 2.0, 3.0, roll, pitch, 0.9;
      const SE3 T = se3_from_ssc(x);
      const Vec6 back = ssc_from_se3(T);
      CHECK(back(3) == 0.0);  // roll set to 0
      CHECK(std::abs(std::abs(back(4)) - 0.5 * kPi) < 1e-12);
      CHECK(se3_from_ssc(back).is_approx(T, 1e-12));
      CHECK((ssc_from_se3(se3_from_ssc(back)) - back).norm() < 1e-12);
      // yaw -/+ roll is what is observable.
      const double expected_yaw = wrap_angle(pitch > 0 ? 0.9 - roll : 0.9 + roll);
      CHECK(std::abs(wrap_angle(back(5) - expected_yaw)) < 1e-12);
    }
  }
}

TEST_CASE("SE2 <-> SSC round trip with wrapping") {
  const SE2 T = se2_from_ssc(Vec3(1.0, -2.0, 3.0 * kPi + 0.2));
  const Vec3 x = ssc_from_se2(T);
  CHECK(x(0) == doctest::Approx(1.0));
  CHECK(x(1) == doctest::Approx(-2.0));
  CHECK(x(2) == doctest::Approx(-kPi + 0.2));
  CHECK(ssc_from_se2(se2_from_ssc(Vec3(0, 0, -kPi)))(2) == doctest::Approx(kPi));
  CHECK(se2_from_ssc(x).is_approx(T, 1e-12));
}

TEST_CASE("ssc_jacobian_of_left_perturbation matches central differences") {
  const SE2 T(3.0, -2.0, 0.7);
  const Mat3 J = ssc_jacobian_of_left_perturbation(T);
  const MatX num =
      testkit::numerical_jacobian_tangent<SE2>([&](const Vec3& d) { return ssc_from_se2(SE2::exp(d) * T); });
  for (int k = 0; k < 3; ++k) CHECK((num.col(k) - J.col(k)).norm() < 1e-8);
}
