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

TEST_CASE("a hull cache shared by the methods changes no result, and is refused for other hull options") {
  const auto p = exact_copy(14, 2.0, 1.0, 4.0, 3);
  AlignOptions o;
  o.region.max_rounds = 4;
  o.region.min_half_width = 2.0;
  for (const unsigned threads : {1u, 2u}) {
    o.threads = threads;
    const Regions global = global_regions(p, o);
    HullCache cache(o.hull);
    for (const Method m : {Method::proposed, Method::so_conv_hull, Method::symmetric, Method::affine}) {
      o.method = m;
      const AlignResult alone = align(p, o, &global);
      const AlignResult shared = align(p, o, &global, &cache);
      CHECK(shared.raw.a11 == alone.raw.a11);
      CHECK(shared.raw.a12 == alone.raw.a12);
      CHECK(shared.raw.a21 == alone.raw.a21);
      CHECK(shared.raw.a22 == alone.raw.a22);
      CHECK(shared.raw.tx == alone.raw.tx);
      CHECK(shared.raw.ty == alone.raw.ty);
      CHECK(shared.cost == alone.cost);
      CHECK(shared.sector == alone.sector);
      REQUIRE(shared.rounds.size() == alone.rounds.size());
      for (std::size_t r = 0; r < alone.rounds.size(); ++r) {
        CHECK(shared.rounds[r].planes == alone.rounds[r].planes);
        CHECK(shared.rounds[r].plane_rows == alone.rounds[r].plane_rows);
        CHECK(shared.rounds[r].iterations == alone.rounds[r].iterations);
        CHECK(shared.rounds[r].kept_boxes == alone.rounds[r].kept_boxes);
        CHECK(shared.rounds[r].cost == alone.rounds[r].cost);
      }
    }
    // The four methods converge on the same transform of an exact copy, so the later ones find its hulls.
    CHECK(cache.size() > 0);
    CHECK(cache.hits() > 0);
  }
  HullCache other([] {
    HullOptions h;
    h.max_slope = 10.0;
    return h;
  }());
  o.method = Method::proposed;
  check_message([&] { (void)align(p, o, nullptr, &other); }, "hull cache was made for other hull options");
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

namespace {

// A copy (as exact_copy, the query the inner points of a 16 × 16 grid) of a feature field that is symmetric
// under the half turn about the grid's centre, plus noise on the dissimilarity: θ and θ + π fit alike, so the
// convex relaxations cannot tell which half of the circle holds the best sector, and the sector tried first
// is often not the best.
AlignmentProblem symmetric_copy(double theta, std::uint64_t seed, double noise) {
  const int n = 16;
  const double mid = 0.5 * (n - 1);
  Rng rng(seed);
  std::vector<double> cx, cy, amp;
  for (int k = 0; k < 3 * 8; ++k)
    cx.push_back(rng.uniform(0, n - 1)), cy.push_back(rng.uniform(0, n - 1)),
        amp.push_back(rng.uniform(-1, 1));
  const auto feature = [&](double x, double y, double* f) {
    for (int d = 0; d < 3; ++d) {
      f[d] = 0;
      for (int k = 8 * d; k < 8 * (d + 1); ++k)
        for (double sign : {1.0, -1.0}) {  // the bump and its mirror through the centre
          const double bx = mid + sign * (cx[k] - mid), by = mid + sign * (cy[k] - mid);
          f[d] += amp[k] * std::exp(-((x - bx) * (x - bx) + (y - by) * (y - by)) / 8.0);
        }
    }
  };
  AlignmentProblem p;
  std::vector<double> fa, fb;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      p.ref_x.push_back(a), p.ref_y.push_back(b);
      double f[3];
      feature(a, b, f);
      fa.insert(fa.end(), f, f + 3);
    }
  // Query: inner points, seen through the inverse of (θ, t) with t keeping the centre fixed.
  const double c = std::cos(theta), s = std::sin(theta);
  const double tx = mid - (c * mid - s * mid), ty = mid - (s * mid + c * mid);
  for (std::size_t i = 0; i < p.ref_x.size(); ++i) {
    if (p.ref_x[i] < 4 || p.ref_x[i] > n - 5 || p.ref_y[i] < 4 || p.ref_y[i] > n - 5) continue;
    const double dx = p.ref_x[i] - tx, dy = p.ref_y[i] - ty;
    p.query_x.push_back(c * dx + s * dy), p.query_y.push_back(-s * dx + c * dy);
    fb.insert(fb.end(), fa.begin() + 3 * static_cast<std::ptrdiff_t>(i),
              fa.begin() + 3 * static_cast<std::ptrdiff_t>(i) + 3);
  }
  p.dissimilarity = euclidean_dissimilarity(fa, fb, 3);
  for (double& v : p.dissimilarity) v += noise * std::abs(rng.normal());
  return p;
}

// Every sector solved to the end on a fresh LP: the lowest cost, ties to the lowest index.
std::pair<int, double> best_sector_by_full_solves(const AlignmentProblem& p, const Regions& reg,
                                                  bool lazy_boxes) {
  LpSettings settings;
  settings.lazy_boxes = lazy_boxes;
  int best = -1;
  double cost = 0;
  for (int k = 0; k < 8; ++k) {
    HullLp lp(Parameterization::rotation_like, p.query_x, p.query_y, reg.planes, reg.boxes, settings);
    lp.set_cs_rows(sector_rows(k));
    const LpSolution s = lp.solve();
    REQUIRE(s.status != LpStatus::failed);
    if (s.status == LpStatus::optimal && (best < 0 || s.cost < cost)) best = k, cost = s.cost;
  }
  return {best, cost};
}

}  // namespace

TEST_CASE("Proposed keeps the sector that solving all eight to the end keeps, in every round") {
  // align skips sectors (box exclusion, Lagrangian minorants) and stops others early (the dual simplex's
  // cutoff); the brute force solves every sector on its own LP. Round by round, the regions are rebuilt here
  // from the trace as align builds them (boxes centred on the previous round's transformed points).
  for (int trial = 0; trial < 12; ++trial) {
    const double theta = -kPi + (trial + 0.37) * (2 * kPi / 12);
    const auto p = symmetric_copy(theta, 5 + static_cast<std::uint64_t>(trial), 0.05);
    AlignOptions o;
    o.method = Method::proposed;
    o.region.max_rounds = 3;
    o.region.min_half_width = 2.0;
    const AlignResult r = align(p, o);
    REQUIRE(r.rounds.size() >= 3);
    Regions reg = global_regions(p, o);
    for (std::size_t round = 0; round < r.rounds.size(); ++round) {
      CAPTURE(theta);
      CAPTURE(round);
      if (round > 0) {  // the regions of this round, as align builds them
        const Transform2& T = r.rounds[round - 1].transform;
        const double w = r.rounds[round].half_width;
        Regions next;
        for (std::size_t j = 0; j < p.query_size(); ++j) {
          const double px = T.a11 * p.query_x[j] + T.a12 * p.query_y[j] + T.tx;
          const double py = T.a21 * p.query_x[j] + T.a22 * p.query_y[j] + T.ty;
          const Box box{px - w, px + w, py - w, py + w};
          std::vector<double> x, y, c;
          for (std::size_t i = 0; i < p.reference_size(); ++i)
            if (p.ref_x[i] >= box.x_lo && p.ref_x[i] <= box.x_hi && p.ref_y[i] >= box.y_lo &&
                p.ref_y[i] <= box.y_hi)
              x.push_back(p.ref_x[i]), y.push_back(p.ref_y[i]), c.push_back(p.c(i, j));
          if (x.size() >= o.region.min_points) {
            next.boxes.push_back(box);
            next.planes.push_back(lower_hull_planes(x, y, c, o.hull));
          } else {
            next.boxes.push_back(reg.boxes[j]);
            next.planes.push_back(reg.planes[j]);
          }
        }
        reg = std::move(next);
      }
      const auto [sector, cost] = best_sector_by_full_solves(p, reg, round == 0);
      CHECK(r.rounds[round].sector == sector);
      CHECK(r.rounds[round].cost == doctest::Approx(cost).epsilon(1e-9));
    }
  }
}

TEST_CASE("boxes_exclude_sector: true exactly when no rotation on the sector's edge fits every box") {
  Rng rng(31);
  const double radius = 1.0 / kBarniDelta;
  int excluded = 0, kept = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const double theta = rng.uniform(-kPi, kPi), w = rng.uniform(0.05, 3.0);
    std::vector<double> qx, qy;
    std::vector<Box> boxes;
    for (int j = 0; j < 30; ++j) {
      qx.push_back(rng.uniform(-10, 10)), qy.push_back(rng.uniform(-10, 10));
      const double px = std::cos(theta) * qx.back() - std::sin(theta) * qy.back() + 2.0 + rng.uniform(-w, w);
      const double py = std::sin(theta) * qx.back() + std::cos(theta) * qy.back() - 1.0 + rng.uniform(-w, w);
      boxes.push_back({px - w, px + w, py - w, py + w});
    }
    for (int k = 0; k < 8; ++k) {
      // The excess of the translation interval, on a fine grid of the edge: a translation exists at λ iff ≤
      // 0.
      double best = 1e300;
      for (int q = 0; q <= 4000; ++q) {
        const double lambda = q / 4000.0;
        const double a0 = k * kPi / 4, a1 = (k + 1) * kPi / 4;
        const double c = radius * ((1 - lambda) * std::cos(a0) + lambda * std::cos(a1));
        const double s = radius * ((1 - lambda) * std::sin(a0) + lambda * std::sin(a1));
        double lx = -1e300, hx = 1e300, ly = -1e300, hy = 1e300;
        for (std::size_t j = 0; j < qx.size(); ++j) {
          const double ax = c * qx[j] - s * qy[j], ay = s * qx[j] + c * qy[j];
          lx = std::max(lx, boxes[j].x_lo - ax), hx = std::min(hx, boxes[j].x_hi - ax);
          ly = std::max(ly, boxes[j].y_lo - ay), hy = std::min(hy, boxes[j].y_hi - ay);
        }
        best = std::min(best, std::max(lx - hx, ly - hy));
      }
      const bool ex = boxes_exclude_sector(qx, qy, boxes, k, 1e-6);
      CAPTURE(trial);
      CAPTURE(k);
      CAPTURE(best);
      if (ex) {
        CHECK(best > 1e-6);  // no sampled rotation fits
        // and the sector's LP (boxes as rows, any planes) is infeasible
        std::vector<std::vector<Plane>> planes(qx.size(), std::vector<Plane>{{0.0, 0.0, 0.0}});
        LpSettings settings;
        settings.lazy_boxes = false;
        HullLp lp(Parameterization::rotation_like, qx, qy, planes, boxes, settings);
        lp.set_cs_rows(sector_rows(k));
        CHECK(lp.solve().status == LpStatus::infeasible);
      } else {
        CHECK(best <= 1e-3);  // some rotation fits, to the grid's resolution
      }
      (ex ? excluded : kept) += 1;
    }
  }
  CHECK(excluded > 20);  // both answers occur
  CHECK(kept > 10);
  CHECK_THROWS_AS((void)boxes_exclude_sector({0.0}, {0.0}, {Box{}}, 8, 0.0), std::invalid_argument);
}
