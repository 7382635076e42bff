// Robust kernels: DCS ρ, ρ', ρ'' (derived in robust.hpp) checked numerically; ρ' = s² for DCS; Huber and
// Cauchy.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "kit/test_kit.hpp"
#include "pgo/robust.hpp"

using namespace keel;
using namespace keel::pgo;

namespace {

// Central differences of ρ and ρ' at x (away from kinks).
void check_derivatives(RobustKernel kernel, double a, double x) {
  const double h = 1e-5 * std::max(1.0, x);
  const Rho r = robust_rho(kernel, a, x);
  // ρ and ρ' as functions R¹ → R¹ for the shared central-difference Jacobian.
  auto rho = [&](const testkit::VecX& v) {
    return testkit::VecX::Constant(1, robust_rho(kernel, a, v(0)).rho);
  };
  auto d1 = [&](const testkit::VecX& v) {
    return testkit::VecX::Constant(1, robust_rho(kernel, a, v(0)).d1);
  };
  const testkit::VecX at = testkit::VecX::Constant(1, x);
  CAPTURE(x);
  CHECK(testkit::numerical_jacobian(rho, at, h)(0, 0) == doctest::Approx(r.d1).epsilon(1e-7));
  CHECK(testkit::numerical_jacobian(d1, at, h)(0, 0) == doctest::Approx(r.d2).epsilon(1e-6).scale(1e-3));
}

}  // namespace

TEST_CASE("DCS: ρ'(χ²) = s² with s = min(1, 2φ/(φ+χ²)), numerical ρ' and ρ''") {
  for (double phi : {1.0, 5.0, 20.0}) {
    for (double x : {0.0, 0.3 * phi, 0.99 * phi, phi, 1.01 * phi, 2 * phi, 10 * phi, 1e3 * phi, 1e6 * phi}) {
      const Rho r = robust_rho(RobustKernel::dcs, phi, x);
      const double s = dcs_scale(x, phi);
      CHECK(r.d1 == doctest::Approx(s * s).epsilon(1e-14));
      CHECK(r.rho <= x + 1e-12);         // never above the quadratic
      CHECK(r.rho < 3.0 * phi + 1e-12);  // bounded by 3φ
      if (std::abs(x - phi) > 1e-3 * phi && x > 0) check_derivatives(RobustKernel::dcs, phi, x);
    }
    // Continuity of ρ and ρ' at χ² = φ, the closed form beyond it.
    const Rho below = robust_rho(RobustKernel::dcs, phi, phi * (1 - 1e-12));
    const Rho above = robust_rho(RobustKernel::dcs, phi, phi * (1 + 1e-12));
    CHECK(below.rho == doctest::Approx(above.rho).epsilon(1e-10));
    CHECK(below.d1 == doctest::Approx(above.d1).epsilon(1e-10));
    const double x = 7.0 * phi;
    CHECK(robust_rho(RobustKernel::dcs, phi, x).rho == doctest::Approx(phi * (3 * x - phi) / (phi + x)));
    CHECK(robust_rho(RobustKernel::dcs, phi, x).d2 == doctest::Approx(-8 * phi * phi / std::pow(phi + x, 3)));
  }
  // ρ integrates ρ': ρ(x) = ∫₀ˣ s(t)² dt (trapezoid on a fine grid).
  const double phi = 5.0, X = 60.0;
  const int n = 200000;
  double integral = 0.0;
  for (int k = 0; k < n; ++k) {
    const double t0 = X * k / n, t1 = X * (k + 1) / n;
    integral += 0.5 * (t1 - t0) * (std::pow(dcs_scale(t0, phi), 2) + std::pow(dcs_scale(t1, phi), 2));
  }
  CHECK(robust_rho(RobustKernel::dcs, phi, X).rho == doctest::Approx(integral).epsilon(1e-8));
  // A gross outlier is all but switched off; an inlier is untouched.
  CHECK(dcs_scale(1e4, 5.0) < 1e-3);
  CHECK(dcs_scale(4.0, 5.0) == 1.0);
}

TEST_CASE("Huber and Cauchy: values and numerical derivatives; none is the identity") {
  const double a = 2.0;
  for (double x : {0.5, 3.0, 5.0, 40.0, 1e4}) {
    if (std::abs(x - a * a) > 1e-3) check_derivatives(RobustKernel::huber, a, x);
    check_derivatives(RobustKernel::cauchy, a, x);
    const Rho n = robust_rho(RobustKernel::none, a, x);
    CHECK(n.rho == x);
    CHECK(n.d1 == 1.0);
    CHECK(n.d2 == 0.0);
  }
  CHECK(robust_rho(RobustKernel::huber, a, 9.0).rho == doctest::Approx(2 * a * 3.0 - a * a));
  CHECK(robust_rho(RobustKernel::huber, a, 3.0).rho == 3.0);
  CHECK(robust_rho(RobustKernel::cauchy, a, 9.0).rho == doctest::Approx(a * a * std::log(1 + 9.0 / (a * a))));
}
