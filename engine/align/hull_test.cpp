// Unit tests of engine/align/hull: lower hulls of dissimilarity clouds (eqs. 3.3–3.4) by qhull, on random
// clouds and on degenerate ones.
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
      double env = -1e300;
      for (const auto& pl : planes) env = std::max(env, pl.at(x[i], y[i]));
      touching += std::abs(env - c[i]) <= 1e-9;
      if (c[i] < c[imin]) imin = i;
    }
    double env_min = -1e300;
    for (const auto& pl : planes) env_min = std::max(env_min, pl.at(x[imin], y[imin]));
    CHECK(env_min == doctest::Approx(c[imin]).epsilon(1e-9));
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
      REQUIRE(filtered.size() == every.size());
      for (std::size_t m = 0; m < every.size(); ++m) {
        CHECK(filtered[m].r == doctest::Approx(every[m].r).epsilon(1e-9));
        CHECK(filtered[m].s == doctest::Approx(every[m].s).epsilon(1e-9));
        CHECK(filtered[m].t == doctest::Approx(every[m].t).epsilon(1e-9));
      }
    }
}
