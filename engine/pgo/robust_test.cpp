// Robust kernels: DCS ρ, ρ', ρ'' (derived in robust.hpp) checked numerically; ρ' = s² for DCS; Huber and
// Cauchy; the TLS surrogate of GNC and its weight.
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

TEST_CASE("TLS GNC: the weight is dρ_μ/dχ², ρ_μ is continuous, μ₀ weighs every residual, TLS as μ grows") {
  const double c2 = 11.34;  // χ²(3) at 0.99
  for (const double mu : {0.01, 0.3, 1.0, 1.4, 20.0, 1e4}) {
    CAPTURE(mu);
    const double lo = mu / (mu + 1.0) * c2, hi = (mu + 1.0) / mu * c2;
    // Continuity at both ends of the middle piece.
    for (const double x : {lo, hi}) {
      CHECK(tls_surrogate(x * (1 - 1e-12), mu, c2) ==
            doctest::Approx(tls_surrogate(x * (1 + 1e-12), mu, c2)));
      CHECK(tls_gnc_weight(x * (1 - 1e-12), mu, c2) ==
            doctest::Approx(tls_gnc_weight(x * (1 + 1e-12), mu, c2)).epsilon(1e-5));
    }
    // w = dρ_μ/dχ² by central differences, inside each piece; w in [0, 1] and not increasing.
    double previous = 1.0;
    for (int k = 1; k < 200; ++k) {
      const double x = 3.0 * hi * k / 200.0;
      const double w = tls_gnc_weight(x, mu, c2);
      CHECK(w >= 0.0);
      CHECK(w <= previous);
      previous = w;
      const double h = 1e-6 * x;
      if (std::abs(x - lo) < 2 * h || std::abs(x - hi) < 2 * h) continue;
      const double d = (tls_surrogate(x + h, mu, c2) - tls_surrogate(x - h, mu, c2)) / (2 * h);
      CAPTURE(x);
      CHECK(d == doctest::Approx(w).epsilon(1e-6).scale(1.0));
    }
  }
  // μ₀ puts the largest residual at half the upper end of the middle piece: still weighed, at less than 1.
  const double max_chi2 = 500.0;
  const double mu0 = tls_gnc_initial_mu(max_chi2, c2);
  CHECK(mu0 == doctest::Approx(c2 / (2 * max_chi2 - c2)));
  CHECK((mu0 + 1.0) / mu0 * c2 == doctest::Approx(2 * max_chi2));
  CHECK(tls_gnc_weight(max_chi2, mu0, c2) > 0.0);
  CHECK(tls_gnc_weight(max_chi2, mu0, c2) < 1.0);
  // As μ grows the surrogate tends to min(χ², c̄²).
  for (const double x : {1.0, 11.0, 11.7, 40.0, 1e6})
    CHECK(tls_surrogate(x, 1e9, c2) == doctest::Approx(std::min(x, c2)).epsilon(1e-4));
  CHECK(std::isinf(tls_gnc_initial_mu(c2, c2)));
  CHECK(std::isinf(tls_gnc_initial_mu(1.0, c2)));
}
