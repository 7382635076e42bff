// Unit tests of engine/align/certificate: the certificate of the global optimum over SO(2) against brute
// force over θ, on an exact copy and on a noisy problem.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "align/align.hpp"
#include "align/certificate.hpp"
#include "align/test_problems.hpp"
#include "core/random.hpp"

using namespace keel::align;
using namespace keel::align::test;
using keel::core::Rng;

TEST_CASE("the certificate finds the global optimum over SO(2): brute force over θ agrees") {
  const auto p = exact_copy(12, 1.1, 0.5, -0.5, 5, 3);
  AlignOptions o;
  const Regions reg = global_regions(p, o);
  const Certificate cert = certify_rotation(p, reg, o.lp, {});
  CHECK(cert.status == keel::core::SearchStatus::optimal);
  CHECK(cert.bound.lower <= cert.bound.upper);
  CHECK(cert.bound.upper - cert.bound.lower <= 1e-6 * std::max(1.0, cert.bound.upper));
  CHECK(std::abs(cert.bound.upper) < 1e-6);  // the exact copy has cost 0 at the true rotation
  CHECK(angle_error(cert.theta, 1.1) < 1e-4);
  // No θ on a fine grid beats the certified bound.
  for (int k = 0; k < 90; ++k) {
    const double th = -kPi + k * 2 * kPi / 90;
    CHECK(rigid_objective(p, reg, o.lp, th) >= cert.bound.lower - 1e-9);
  }
}

TEST_CASE("the certificate on a noisy problem: bound below every sampled θ, attained at its θ") {
  auto p = exact_copy(12, -2.4, 0.0, 0.0, 9, 3);
  Rng rng(3);
  for (auto& c : p.dissimilarity) c += 0.3 * rng.uniform();
  AlignOptions o;
  const Regions reg = global_regions(p, o);
  const Certificate cert = certify_rotation(p, reg, o.lp, {});
  CHECK(cert.status == keel::core::SearchStatus::optimal);
  CHECK(rigid_objective(p, reg, o.lp, cert.theta) == doctest::Approx(cert.bound.upper).epsilon(1e-9));
  double best = 1e300;
  for (int k = 0; k < 360; ++k) best = std::min(best, rigid_objective(p, reg, o.lp, -kPi + k * kPi / 180));
  CHECK(best >= cert.bound.lower - 1e-9);
  CHECK(best <= cert.bound.upper + 0.05 * std::abs(cert.bound.upper));
}
