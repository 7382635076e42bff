// Unit tests of engine/align/align: the octagon sectors (eqs. 3.13–3.19), the projection to SE(2), the
// alignment of exact copies by every method and over the shrinking region, the depth gate (eq. 3.9) and bad
// inputs.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <utility>
#include <vector>

#include "align/align.hpp"
#include "align/test_problems.hpp"
#include "core/random.hpp"

using namespace keel::align;
using namespace keel::align::test;
using keel::core::Rng;

TEST_CASE("Barni constants of eq. 3.14 for n = 2") {
  CHECK(kBarniAlpha1 == 1.0);
  CHECK(kBarniAlpha2 == doctest::Approx(std::sqrt(2.0) - 1.0).epsilon(1e-15));
  const double delta = 2.0 / (1.0 + std::sqrt(1.0 + kBarniAlpha2 * kBarniAlpha2));
  CHECK(kBarniDelta == doctest::Approx(delta).epsilon(1e-15));
  CHECK(std::abs(kBarniDelta - 0.960434) < 5e-7);  // the and notes' value; the thesis prints 0.96044
}

TEST_CASE("each sector of eq. 3.19 admits exactly its octagon edge (sign-aware eq. 3.17)") {
  const double R = 1.0 / kBarniDelta;  // vertex radius
  for (int k = 0; k < 8; ++k) {
    const auto rows = sector_rows(k);
    auto feasible = [&](double c, double s) {
      for (const auto& r : rows) {
        const double v = r.a_c * c + r.a_s * s;
        if (v < r.lo - 1e-12 || v > r.hi + 1e-12) return false;
      }
      return true;
    };
    const double a0 = k * kPi / 4, a1 = (k + 1) * kPi / 4;
    const double v0c = R * std::cos(a0), v0s = R * std::sin(a0), v1c = R * std::cos(a1),
                 v1s = R * std::sin(a1);
    // Along the line through the two vertices, feasible exactly for the parameter in [0, 1].
    for (int q = -40; q <= 140; ++q) {
      const double t = q / 100.0;
      const double c = v0c + t * (v1c - v0c), s = v0s + t * (v1s - v0s);
      CHECK_MESSAGE(feasible(c, s) == (t >= -1e-12 && t <= 1 + 1e-12), "sector ", k, " t ", t);
      if (t >= 0 && t <= 1) {
        const double r = std::hypot(c, s);
        CHECK(r >= 0.96193 - 1e-5);  // the octagon lies within [0.96194, 1.04120] of the unit circle
        CHECK(r <= R + 1e-12);
      }
    }
    // Points far off the edge (radius 2.5 in every direction) are infeasible: the printed eq. 3.17 admits
    // some.
    for (int a = 0; a < 64; ++a) CHECK(!feasible(2.5 * std::cos(a * kPi / 32), 2.5 * std::sin(a * kPi / 32)));
  }
  CHECK(1.0 / kBarniDelta == doctest::Approx(1.04120).epsilon(1e-5));
  CHECK(std::cos(kPi / 8) / kBarniDelta == doctest::Approx(0.96194).epsilon(1e-5));
}

TEST_CASE("projection to SE(2) and singular values") {
  const Transform2 t{2 * std::cos(0.3), -2 * std::sin(0.3), 2 * std::sin(0.3), 2 * std::cos(0.3), 1, 2};
  double s1, s2;
  singular_values(t, s1, s2);
  CHECK(s1 == doctest::Approx(2.0));
  CHECK(s2 == doctest::Approx(2.0));
  const Rigid2 r = project_to_rigid(t, 3, -1);
  CHECK(r.theta == doctest::Approx(0.3));
  // The centroid (3, −1) maps to the same point under t and under the projection.
  const double px = t.a11 * 3 + t.a12 * -1 + t.tx, py = t.a21 * 3 + t.a22 * -1 + t.ty;
  CHECK(std::cos(r.theta) * 3 - std::sin(r.theta) * -1 + r.tx == doctest::Approx(px));
  CHECK(std::sin(r.theta) * 3 + std::cos(r.theta) * -1 + r.ty == doctest::Approx(py));
  CHECK(!approximately_valid(t, 0.05));
  CHECK(approximately_valid({1.02, 0, 0, 0.99, 0, 0}, 0.05));
  CHECK(!approximately_valid({1, 0, 0, -1, 0, 0}, 0.05));  // a reflection
}

TEST_CASE("an exact copy of the reference is aligned exactly (every method, global round)") {
  // Angles where the octagon of the proposed method crosses the unit circle: φ = 22.5° ± acos(1 /
  // (δ√(1+α2²))).
  const double cross = kPi / 8 - std::acos(1.0 / (kBarniDelta * std::hypot(1.0, kBarniAlpha2)));
  for (Method m : {Method::so_conv_hull, Method::symmetric, Method::affine, Method::proposed}) {
    for (double theta : {cross + kPi / 2, cross - 3 * kPi / 4 + kPi / 4}) {
      const double tx = 3.0, ty = -2.0;
      const auto p = exact_copy(10, theta, tx, ty);
      AlignOptions o;
      o.method = m;
      o.region.max_rounds = 0;
      const auto r = align(p, o);
      INFO(to_string(m), " theta ", theta);
      CHECK(angle_error(r.rigid.theta, theta) < 1e-6);
      CHECK(std::abs(r.raw.tx - tx) < 1e-6);
      CHECK(std::abs(r.raw.ty - ty) < 1e-6);
      CHECK(std::abs(r.cost) < 1e-6);
    }
  }
}

TEST_CASE("rounds of the shrinking region keep an exact copy exact; the result does not depend on threads") {
  const auto p = exact_copy(14, 2.0, 1.0, 4.0, 3);
  for (Method m : {Method::symmetric, Method::proposed}) {
    AlignOptions o;
    o.method = m;
    o.region.max_rounds = 4;
    o.region.min_half_width = 2.0;
    o.threads = 1;
    const auto a = align(p, o);
    o.threads = 2;
    const auto b = align(p, o);
    CHECK(a.rounds.size() >= 2);
    CHECK(a.raw.a11 == b.raw.a11);
    CHECK(a.raw.a21 == b.raw.a21);
    CHECK(a.raw.tx == b.raw.tx);
    CHECK(a.raw.ty == b.raw.ty);
    CHECK(a.cost == b.cost);
    if (m == Method::symmetric) CHECK(angle_error(a.rigid.theta, 2.0) < 1e-6);
    if (m == Method::proposed) CHECK(angle_error(a.rigid.theta, 2.0) < 0.05);
  }
}

TEST_CASE("bad inputs give clear errors") {
  auto p = exact_copy(5, 0.3, 0, 0);
  AlignOptions o;
  auto expect = [&](const AlignmentProblem& q, const char* msg) {
    check_message([&] { (void)align(q, o); }, msg);
  };
  {
    auto q = p;
    q.ref_x.resize(2), q.ref_y.resize(2);
    expect(q, "reference points (need at least 3)");
  }
  {
    auto q = p;
    q.query_y.pop_back();
    expect(q, "query_y");
  }
  {
    auto q = p;
    q.ref_x[3] = NAN;
    expect(q, "ref_x[3]");
  }
  {
    auto q = p;
    q.dissimilarity[7] = NAN;
    expect(q, "dissimilarity C(");
  }
  {
    auto q = p;
    q.dissimilarity.pop_back();
    expect(q, "dissimilarity has");
  }
  {
    auto q = p;
    for (auto& v : q.ref_y) v = 2 * q.ref_x[&v - q.ref_y.data()];  // collinear
    expect(q, "collinear");
  }
  {
    auto q = p;
    for (auto& v : q.query_x) v *= 3;  // larger than the reference: cannot lie inside it
    expect(q, "cannot lie inside the reference");
  }
  {
    auto q = p;
    q.ref_z.assign(q.ref_x.size(), 0.0);
    expect(q, "depths given for one trajectory only");
  }
  o.region.shrink = 1.5;
  check_message([&] { (void)align(p, o); }, "RegionOptions.shrink = 1.5");
  CHECK_THROWS_AS((void)method_from_string("octagon"), std::invalid_argument);
  CHECK(method_from_string("so_conv_hull") == Method::so_conv_hull);
}

TEST_CASE(
    "known depth (eq. 3.9): the depth gate pairs query points with reference points at their depth only") {
  // Reference: the grid at depth 0 and a copy of its positions at depth 5 with shuffled features (a decoy
  // layer that matches every query feature somewhere else); query: the depth-0 layer, rotated and translated.
  auto p = exact_copy(10, 0.9, 1.0, -1.0, 21, 2);
  const std::size_t na = p.ref_x.size(), nb = p.query_size();
  std::vector<double> dis(2 * na * nb);
  Rng rng(5);
  std::vector<std::size_t> perm(na);
  for (std::size_t i = 0; i < na; ++i) perm[i] = i;
  for (std::size_t i = na - 1; i > 0; --i)
    std::swap(perm[i], perm[static_cast<std::size_t>(rng.uniform() * (i + 1))]);
  for (std::size_t i = 0; i < na; ++i)
    for (std::size_t j = 0; j < nb; ++j) {
      dis[i * nb + j] = p.c(i, j);
      dis[(na + i) * nb + j] = p.c(perm[i], j);
    }
  p.ref_x.insert(p.ref_x.end(), p.ref_x.begin(), p.ref_x.end());
  p.ref_y.insert(p.ref_y.end(), p.ref_y.begin(), p.ref_y.end());
  p.ref_z.assign(2 * na, 0.0);
  for (std::size_t i = na; i < 2 * na; ++i) p.ref_z[i] = 5.0;
  p.query_z.assign(nb, 0.0);
  p.dissimilarity = dis;
  AlignOptions o;
  o.method = Method::symmetric;
  o.region.max_rounds = 0;
  o.depth_gate = 1.0;
  const auto gated = align(p, o);
  CHECK(angle_error(gated.rigid.theta, 0.9) < 1e-6);
  CHECK(std::abs(gated.cost) < 1e-6);
  // Without the gate every reference point enters each cloud: the envelope of a superset lies below.
  const Regions with_gate = global_regions(p, o);
  o.depth_gate = 0.0;
  const Regions without = global_regions(p, o);
  CHECK(with_gate.plane_count != without.plane_count);
  std::size_t lower = 0;
  for (std::size_t j = 0; j < nb; ++j)
    for (double x = 0.5; x < 9; x += 2.0) {
      double a = -1e300, b = -1e300;
      for (const auto& pl : with_gate.planes[j]) a = std::max(a, pl.at(x, x));
      for (const auto& pl : without.planes[j]) b = std::max(b, pl.at(x, x));
      CHECK(b <= a + 1e-9);
      lower += b < a - 1e-6;
    }
  CHECK(lower > 0);
  AlignmentProblem flat = exact_copy(6, 0.1, 0, 0);
  o.depth_gate = 1.0;
  check_message([&] { (void)align(flat, o); }, "depth_gate > 0 needs depths");
}
