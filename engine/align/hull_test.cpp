// Unit tests of engine/align/hull: lower hulls of dissimilarity clouds (eqs. 3.3–3.4) by qhull and by CGAL's
// regular triangulation, on random clouds and on degenerate ones.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "align/hull.hpp"
#include "align/test_problems.hpp"
#include "core/random.hpp"

using namespace keel::align;
using namespace keel::align::test;
using keel::core::Rng;

namespace {

// max over the planes at (x, y): the envelope c_j of eq. 3.4.
double envelope(const std::vector<Plane>& planes, double x, double y) {
  double e = -1e300;
  for (const auto& pl : planes) e = std::max(e, pl.at(x, y));
  return e;
}

}  // namespace

TEST_CASE("lower hull planes under-estimate every point and touch the hull vertices") {
  Rng rng(11);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> x, y, c;
    for (int i = 0; i < 300; ++i) {
      x.push_back(rng.uniform(-10, 10));
      y.push_back(rng.uniform(0, 5));
      c.push_back(std::sin(0.3 * x.back()) + 0.1 * y.back() * y.back() + 0.2 * rng.normal());
    }
    HullStats st;
    const auto planes = lower_hull_planes(x, y, c, {}, &st);
    REQUIRE(planes.size() >= 3);
    CHECK(st.steep == 0);
    std::size_t touching = 0;
    for (const auto& pl : planes) {
      std::size_t on = 0;
      for (std::size_t i = 0; i < x.size(); ++i) {
        const double gap = c[i] - pl.at(x[i], y[i]);
        CHECK(gap >= -1e-9);  // under-estimates every point
        on += gap <= 1e-9;
      }
      CHECK(on >= 3);  // each plane is a facet: it passes through at least three points of the cloud
    }
    // The envelope max_m plane_m equals C at the lower-hull vertices: the cloud's minimum is one of them.
    std::size_t imin = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      touching += std::abs(envelope(planes, x[i], y[i]) - c[i]) <= 1e-9;
      if (c[i] < c[imin]) imin = i;
    }
    CHECK(envelope(planes, x[imin], y[imin]) == doctest::Approx(c[imin]).epsilon(1e-9));
    CHECK(touching >= 3);
  }
}

TEST_CASE("hull of degenerate clouds: flat dissimilarity joggles, collinear positions give a clear error") {
  std::vector<double> x{0, 1, 0, 1, 0.5}, y{0, 0, 1, 1, 0.5}, c(5, 2.0);
  HullStats st;
  const auto planes = lower_hull_planes(x, y, c, {}, &st);
  REQUIRE(!planes.empty());
  for (const auto& pl : planes) CHECK(pl.at(0.5, 0.5) == doctest::Approx(2.0).epsilon(1e-6));
  std::vector<double> lx{0, 1, 2, 3}, ly{0, 0, 0, 0}, lc{1, 0, 2, 1};
  CHECK_THROWS((void)lower_hull_planes(lx, ly, lc));
  std::vector<double> nx{0, 1, 0}, ny{0, 0, 1}, nc{1, NAN, 0};
  check_message([&] { (void)lower_hull_planes(nx, ny, nc); }, "not finite");
  CHECK_THROWS_AS((void)lower_hull_planes(std::vector<double>{0, 1}, std::vector<double>{0, 1},
                                          std::vector<double>{0, 1}),
                  std::invalid_argument);
}

TEST_CASE("the prefilter drops points above the lower hull and keeps its facets") {
  Rng rng(23);
  HullOptions all;
  all.prefilter = false;
  // Lawn-mower positions (exactly collinear rows, as the simulated surveys) and scattered ones; a rough
  // field, a smooth one and a paraboloid (every point on the lower hull).
  for (int layout = 0; layout < 2; ++layout)
    for (int field = 0; field < 3; ++field) {
      std::vector<double> x, y, c;
      for (int i = 0; i < 900; ++i) {
        const double px = layout == 0 ? static_cast<double>(i % 45) : rng.uniform(0, 44);
        const double py = layout == 0 ? 2.0 * static_cast<double>(i / 45) : rng.uniform(0, 40);
        x.push_back(px), y.push_back(py);
        const double smooth = std::sin(0.2 * px) + std::cos(0.15 * py);
        c.push_back(field == 0   ? smooth + 0.5 * rng.normal()
                    : field == 1 ? smooth + 0.01 * rng.normal()
                                 : 0.01 * ((px - 20) * (px - 20) + (py - 17) * (py - 17)));
      }
      HullStats fs, as;
      auto filtered = lower_hull_planes(x, y, c, {}, &fs);
      auto every = lower_hull_planes(x, y, c, all, &as);
      CAPTURE(layout);
      CAPTURE(field);
      CHECK(as.hull_points == x.size());
      if (field == 0) CHECK(fs.hull_points < x.size() / 2);  // a rough field: most points lie above others
      // On survey lines (straight runs in the input) the lower chain of each line drops most of the rest.
      if (layout == 0 && field < 2) CHECK(fs.hull_points < x.size() / 4);
      // The same planes, each within rounding of one of the other set (the sorted order can differ where two
      // planes' slopes agree to rounding).
      REQUIRE(filtered.size() == every.size());
      const auto near = [](const Plane& a, const Plane& b) {
        return std::abs(a.r - b.r) <= 1e-9 * (1 + std::abs(b.r)) &&
               std::abs(a.s - b.s) <= 1e-9 * (1 + std::abs(b.s)) &&
               std::abs(a.t - b.t) <= 1e-9 * (1 + std::abs(b.t));
      };
      for (const auto* set : {&filtered, &every}) {
        const auto& other = set == &filtered ? every : filtered;
        for (const Plane& p : *set)
          CHECK(std::any_of(other.begin(), other.end(), [&](const Plane& q) { return near(p, q); }));
      }
    }
}

TEST_CASE("the regular triangulation and qhull give the same lower envelope") {
  Rng rng(29);
  HullOptions rt;
  rt.backend = HullBackend::regular_triangulation;
  HullOptions rt_all = rt, q_all;
  rt_all.prefilter = q_all.prefilter = false;
  // Survey rows (exactly collinear runs, repeated positions at the row ends), scattered positions, and a grid
  // with flat patches (coplanar facets: several triangles of one plane); rough and smooth fields.
  for (int layout = 0; layout < 3; ++layout)
    for (int field = 0; field < 2; ++field)
      for (const int n : {12, 60, 400}) {
        std::vector<double> x, y, c;
        for (int i = 0; i < n; ++i) {
          const int cols = layout == 1 ? 0 : static_cast<int>(std::sqrt(n));
          const double px = layout == 1 ? rng.uniform(0, 30) : static_cast<double>(i % cols);
          const double py = layout == 1 ? rng.uniform(0, 20) : 2.0 * static_cast<double>(i / cols);
          x.push_back(px), y.push_back(py);
          double v = std::sin(0.2 * px) + std::cos(0.15 * py) + (field == 0 ? 0.5 : 0.01) * rng.normal();
          if (layout == 2) v = std::max(v, 0.5);  // flat where the field dips below 0.5
          c.push_back(v);
        }
        CAPTURE(layout);
        CAPTURE(field);
        CAPTURE(n);
        HullStats qs, ts;
        const auto q = lower_hull_planes(x, y, c, {}, &qs);
        const auto t = lower_hull_planes(x, y, c, rt, &ts);
        const auto ta = lower_hull_planes(x, y, c, rt_all, nullptr);
        const auto qa = lower_hull_planes(x, y, c, q_all, nullptr);
        CHECK(!qs.joggled);
        CHECK(!ts.joggled);
        CHECK(ts.hull_points == qs.hull_points);  // the same prefilter in front of either
        // The same envelope at every input position and between them (convex combinations of three).
        double worst = 0;
        const auto compare = [&](double px, double py) {
          const double e = envelope(q, px, py);
          for (const auto* other : {&t, &ta, &qa})
            worst = std::max(worst, std::abs(envelope(*other, px, py) - e) / (1.0 + std::abs(e)));
        };
        for (std::size_t i = 0; i < x.size(); ++i) compare(x[i], y[i]);
        for (int k = 0; k < 50; ++k) {
          const auto a = static_cast<std::size_t>(rng.uniform(0, static_cast<double>(n) - 1e-9));
          const auto b = static_cast<std::size_t>(rng.uniform(0, static_cast<double>(n) - 1e-9));
          const auto d = static_cast<std::size_t>(rng.uniform(0, static_cast<double>(n) - 1e-9));
          const double wa = rng.uniform(0, 1), wb = rng.uniform(0, 1 - wa), wd = 1 - wa - wb;
          compare(wa * x[a] + wb * x[b] + wd * x[d], wa * y[a] + wb * y[b] + wd * y[d]);
        }
        CHECK(worst <= 1e-9);
        // Every plane of the triangulation is a supporting plane: below every point, through at least three.
        for (const auto& pl : t) {
          std::size_t on = 0;
          for (std::size_t i = 0; i < x.size(); ++i) {
            const double gap = c[i] - pl.at(x[i], y[i]);
            CHECK(gap >= -1e-9);
            on += gap <= 1e-9;
          }
          CHECK(on >= 3);
        }
        // Coplanar triangles are merged by the deduplication: no more planes than qhull's merged facets
        // triangulated, and the same count where no facet is flat.
        if (layout != 2) CHECK(t.size() == q.size());
      }
}

TEST_CASE("the regular triangulation falls back on qhull where the positions span no triangle") {
  HullOptions rt;
  rt.backend = HullBackend::regular_triangulation;
  // Collinear positions: no triangle, and qhull's joggle cannot make a 2D hull either: the same clear error.
  std::vector<double> lx{0, 1, 2, 3}, ly{0, 0, 0, 0}, lc{1, 0, 2, 1};
  CHECK_THROWS((void)lower_hull_planes(lx, ly, lc, rt));
  // A flat cloud: the triangulation gives the one plane exactly (no joggle).
  std::vector<double> x{0, 1, 0, 1, 0.5}, y{0, 0, 1, 1, 0.5}, c(5, 2.0);
  HullStats st;
  const auto planes = lower_hull_planes(x, y, c, rt, &st);
  CHECK(!st.joggled);
  REQUIRE(planes.size() == 1);
  CHECK(planes[0].r == 0.0);
  CHECK(planes[0].s == 0.0);
  CHECK(planes[0].t == 2.0);
}
