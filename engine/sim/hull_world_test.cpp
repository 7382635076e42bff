// The ship-hull substitute of §3.8: curvature of surface graphs (analytic and fitted), the DVL (ray casting,
// range noise, dropouts, range gating), the known-depth ground truth of eq. 3.9, determinism, option
// validation.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "kit/test_kit.hpp"
#include "sim/hull_world.hpp"

using namespace keel::sim;
using keel::testkit::contains;
using keel::testkit::message_of;

namespace {

// A surface without dents, bilges or keel: depth = draft − trim·x − rocker·x²/2.
HullWorldOptions plain_hull() {
  HullWorldOptions o;
  o.surface.dents = 0;
  o.surface.deadrise = 0.0;
  o.surface.bilge_curvature = 0.0;
  o.surface.trim = 0.0;
  o.surface.rocker = 0.0;
  o.dvl.range_noise = 0.0;
  o.dvl.dropout = 0.0;
  return o;
}

double hypot3(double a, double b, double c) { return std::sqrt(a * a + b * b + c * c); }

}  // namespace

TEST_CASE("graph curvature: a sphere has κ1 = κ2 = 1/R everywhere, a cylinder 1/R and 0") {
  const double R = 4.0;
  for (const double u : {0.0, 1.0, -2.5}) {
    for (const double v : {0.0, 0.7, 2.0}) {
      // Lower half of a sphere seen as z = −√(R² − u² − v²) (a bowl: curvature +1/R).
      const double g = std::sqrt(R * R - u * u - v * v);
      const auto k = graph_curvature(u / g, v / g, 1.0 / g + u * u / (g * g * g), u * v / (g * g * g),
                                     1.0 / g + v * v / (g * g * g));
      CHECK(k.kappa1 == doctest::Approx(1.0 / R));
      CHECK(k.kappa2 == doctest::Approx(1.0 / R));
      CHECK(k.gaussian == doctest::Approx(1.0 / (R * R)));
      CHECK(k.mean == doctest::Approx(1.0 / R));
      CHECK(k.slope == doctest::Approx(std::hypot(u, v) / g));
      // Cylinder along u: z = √(R² − v²) (a ridge: curvature −1/R across, 0 along).
      const double h = std::sqrt(R * R - v * v);
      const auto c = graph_curvature(0.0, -v / h, 0.0, 0.0, -1.0 / h - v * v / (h * h * h));
      CHECK(c.kappa1 == doctest::Approx(0.0));
      CHECK(c.kappa2 == doctest::Approx(-1.0 / R));
      CHECK(c.gaussian == doctest::Approx(0.0));
    }
  }
}

TEST_CASE("fit_surface_curvature recovers a quadric exactly and a sphere closely; flags degenerate designs") {
  keel::core::Rng rng(17);
  std::vector<double> x, y, z;
  // An exact quadric z = 1 + 0.1u − 0.2v + 0.3u² − 0.1uv + 0.05v² around (3, −2).
  for (int i = 0; i < 40; ++i) {
    const double u = rng.uniform(-1.5, 1.5), v = rng.uniform(-1.5, 1.5);
    x.push_back(3.0 + u);
    y.push_back(-2.0 + v);
    z.push_back(1.0 + 0.1 * u - 0.2 * v + 0.3 * u * u - 0.1 * u * v + 0.05 * v * v);
  }
  const auto q = fit_surface_curvature(x, y, z, 3.0, -2.0);
  const auto exact = graph_curvature(0.1, -0.2, 0.6, -0.1, 0.1);
  CHECK(q.ok);
  CHECK(q.points == 40);
  CHECK(q.kappa1 == doctest::Approx(exact.kappa1).epsilon(1e-9));
  CHECK(q.kappa2 == doctest::Approx(exact.kappa2).epsilon(1e-9));
  CHECK(q.slope == doctest::Approx(exact.slope).epsilon(1e-9));

  // Points of a sphere of radius 10 within 1.5 m of an off-centre point: the quadric's curvature is 1/R
  // within the fourth-order terms the quadric cannot represent.
  const double R = 10.0, cx = 2.0, cy = 3.0;
  x.clear(), y.clear(), z.clear();
  for (int i = 0; i < 60; ++i) {
    const double u = rng.uniform(-1.5, 1.5), v = rng.uniform(-1.5, 1.5);
    x.push_back(cx + u);
    y.push_back(cy + v);
    z.push_back(-std::sqrt(R * R - (cx + u) * (cx + u) - (cy + v) * (cy + v)));
  }
  const auto s = fit_surface_curvature(x, y, z, cx, cy);
  CHECK(s.ok);
  CHECK(s.kappa1 == doctest::Approx(1.0 / R).epsilon(0.01));
  CHECK(s.kappa2 == doctest::Approx(1.0 / R).epsilon(0.01));
  CHECK(s.slope == doctest::Approx(std::hypot(cx, cy) / std::sqrt(R * R - cx * cx - cy * cy)).epsilon(0.01));

  // Degenerate: two parallel lines (v² is a multiple of the constant), or too few points.
  std::vector<double> lx, ly, lz;
  for (int i = 0; i < 10; ++i)
    for (const double v : {-0.6, 0.6}) {
      lx.push_back(0.2 * i);
      ly.push_back(v);
      lz.push_back(0.1 * i + 0.3 * v);
    }
  const auto d = fit_surface_curvature(lx, ly, lz, 1.0, 0.0);
  CHECK_FALSE(d.ok);
  CHECK(d.kappa1 == 0.0);
  CHECK(d.slope == doctest::Approx(std::hypot(0.5, 0.3)));  // from the plane fit
  CHECK_FALSE(fit_surface_curvature(std::vector<double>{0, 1}, std::vector<double>{0, 1},
                                    std::vector<double>{0, 1}, 0, 0)
                  .ok);
  CHECK(contains(message_of([] {
                   (void)fit_surface_curvature(std::vector<double>{0}, std::vector<double>{},
                                               std::vector<double>{0}, 0, 0);
                 }),
                 "1 x, 0 y and 1 z"));
}

TEST_CASE("hull surface: analytic derivatives match central differences; shape features where designed") {
  const auto w = make_hull_world(HullWorldOptions{}, 3, 1);
  const auto& h = w.surface;
  CHECK(h.dent_x.size() == 25u);
  const double e = 1e-5;
  for (const auto& [x, y] :
       {std::pair{0.0, 0.0}, std::pair{3.1, -2.2}, std::pair{-10.0, 5.5}, std::pair{7.0, -7.9}}) {
    double gx = 0, gy = 0, hxx = 0, hxy = 0, hyy = 0;
    h.depth(x, y, &gx, &gy, &hxx, &hxy, &hyy);
    CHECK(gx == doctest::Approx((h.depth(x + e, y) - h.depth(x - e, y)) / (2 * e)).epsilon(1e-6));
    CHECK(gy == doctest::Approx((h.depth(x, y + e) - h.depth(x, y - e)) / (2 * e)).epsilon(1e-6));
    double ax = 0, ay = 0, bx = 0, by = 0;
    h.depth(x + e, y, &ax, &ay);
    h.depth(x - e, y, &bx, &by);
    CHECK(hxx == doctest::Approx((ax - bx) / (2 * e)).epsilon(1e-5));
    CHECK(hxy == doctest::Approx((ay - by) / (2 * e)).epsilon(1e-5));
    h.depth(x, y + e, &ax, &ay);
    h.depth(x, y - e, &bx, &by);
    CHECK(hyy == doctest::Approx((ay - by) / (2 * e)).epsilon(1e-5));
  }
  // Without dents: the keel is the deepest line, the bilges turn with the designed curvature.
  HullSurface plain = h;
  plain.dent_x.clear(), plain.dent_y.clear(), plain.dent_sigma.clear(), plain.dent_amplitude.clear();
  CHECK(plain.depth(0, 0) == doctest::Approx(plain.shape.draft));
  CHECK(plain.depth(0, 0) > plain.depth(0, 2));
  CHECK(plain.depth(0, 2) > plain.depth(0, 6));
  CHECK(plain.depth(0, 3) == doctest::Approx(plain.depth(0, -3)));
  CHECK(plain.curvature(0, 0).kappa2 == doctest::Approx(-plain.shape.deadrise / plain.shape.keel_radius));
  double hyy = 0;
  plain.depth(0, 12, nullptr, nullptr, nullptr, nullptr, &hyy);
  CHECK(hyy == doctest::Approx(-plain.shape.bilge_curvature).epsilon(0.02));  // deadrise adds a little
}

TEST_CASE("hull worlds: counts, determinism, the query inside the reference rectangle") {
  HullWorldOptions o;
  o.position_noise = 0.05;
  const auto a = make_hull_world(o, 5, 2), b = make_hull_world(o, 5, 2), c = make_hull_world(o, 5, 3);
  CHECK(a.ref_x.size() == 17u * 73u);  // 16 m / 1 m + 1 tracks of 36 m / 0.5 m + 1 positions
  CHECK(a.query_x.size() == 9u * 25u);
  CHECK(a.ref_features.size() == a.ref_x.size() * 3);
  CHECK(a.query_features.size() == a.query_x.size() * 3);
  CHECK(a.ref_fits.size() == a.ref_x.size());
  CHECK(a.ref_return_x.size() <= 4 * a.ref_x.size());
  CHECK(a.ref_return_x.size() > 3 * a.ref_x.size());  // 5 % dropout
  CHECK(a.feature_dim == 3);
  CHECK(a.ref_x == b.ref_x);
  CHECK(a.query_x == b.query_x);
  CHECK(a.ref_features == b.ref_features);
  CHECK(a.query_features == b.query_features);
  CHECK(a.ref_return_z == b.ref_return_z);
  CHECK(a.theta == b.theta);
  CHECK(a.surface.dent_x != c.surface.dent_x);
  CHECK(a.ref_features != c.ref_features);
  CHECK(a.theta != c.theta);
  for (int s = 0; s < 50; ++s) {
    const auto w = make_hull_world(o, 1, s);
    CHECK(w.query_x0 >= -0.5 * o.reference_length);
    CHECK(w.query_x0 + o.query_length <= 0.5 * o.reference_length);
    CHECK(w.query_y0 >= -0.5 * o.reference_width);
    CHECK(w.query_y0 + o.query_width <= 0.5 * o.reference_width);
    int bad = 0;
    for (const auto& f : w.ref_fits) bad += !f.ok;
    for (const auto& f : w.query_fits) bad += !f.ok;
    CHECK(bad == 0);
  }
}

TEST_CASE(
    "known-depth ground truth (eq. 3.9): R(θ) p_b + t = p_a in xy, depth unchanged, returns on the hull") {
  HullWorldOptions o;
  o.dvl.range_noise = 0.0;
  for (int s = 0; s < 20; ++s) {
    const auto w = make_hull_world(o, 8, s);
    const double c = std::cos(w.theta), sn = std::sin(w.theta);
    double err = 0, depth_err = 0;
    for (std::size_t j = 0; j < w.query_x.size(); ++j) {
      err = std::max(err, std::fabs(c * w.query_x[j] - sn * w.query_y[j] + w.tx - w.query_true_x[j]));
      err = std::max(err, std::fabs(sn * w.query_x[j] + c * w.query_y[j] + w.ty - w.query_true_y[j]));
      depth_err = std::max(depth_err, std::fabs(w.query_z[j] - o.standoff -
                                                w.surface.depth(w.query_true_x[j], w.query_true_y[j])));
    }
    for (std::size_t i = 0; i < w.ref_x.size(); ++i)
      depth_err =
          std::max(depth_err, std::fabs(w.ref_z[i] - o.standoff - w.surface.depth(w.ref_x[i], w.ref_y[i])));
    CHECK(err < 1e-12);
    CHECK(depth_err < 1e-12);
    // Noiseless returns lie on the hull, the query's after mapping them to the ship frame; each within
    // max_range of the position that measured it, at the beam angle from the vertical.
    double on = 0, angle = 0;
    for (std::size_t k = 0; k < w.ref_return_x.size(); ++k) {
      const int i = w.ref_return_owner[k];
      on = std::max(on, std::fabs(w.ref_return_z[k] - w.surface.depth(w.ref_return_x[k], w.ref_return_y[k])));
      const double r = hypot3(w.ref_return_x[k] - w.ref_x[i], w.ref_return_y[k] - w.ref_y[i],
                              w.ref_return_z[k] - w.ref_z[i]);
      CHECK(r <= o.dvl.max_range);
      angle = std::max(angle, std::fabs(std::acos((w.ref_z[i] - w.ref_return_z[k]) / r) - o.dvl.beam_angle));
    }
    for (std::size_t k = 0; k < w.query_return_x.size(); ++k) {
      const double x = c * w.query_return_x[k] - sn * w.query_return_y[k] + w.tx;
      const double y = sn * w.query_return_x[k] + c * w.query_return_y[k] + w.ty;
      on = std::max(on, std::fabs(w.query_return_z[k] - w.surface.depth(x, y)));
    }
    CHECK(on < 1e-9);
    CHECK(angle < 1e-9);
  }
}

TEST_CASE("DVL: range noise N(0, σ²), dropouts at the configured rate, range gating") {
  HullWorldOptions o = plain_hull();  // flat hull: every true range is standoff / cos(beam_angle)
  o.dvl.range_noise = 0.05;
  o.dvl.dropout = 0.2;
  const double r0 = o.standoff / std::cos(o.dvl.beam_angle);
  double s1 = 0, s2 = 0;
  long long n_ref = 0, returns = 0, beams = 0;
  for (int s = 0; s < 5; ++s) {
    const auto w = make_hull_world(o, 4, s);
    beams += 4 * static_cast<long long>(w.ref_x.size() + w.query_x.size());
    returns += static_cast<long long>(w.ref_return_x.size() + w.query_return_x.size());
    for (std::size_t k = 0; k < w.ref_return_x.size(); ++k) {
      const int i = w.ref_return_owner[k];
      const double e = hypot3(w.ref_return_x[k] - w.ref_x[i], w.ref_return_y[k] - w.ref_y[i],
                              w.ref_return_z[k] - w.ref_z[i]) -
                       r0;
      s1 += e;
      s2 += e * e;
      ++n_ref;
    }
  }
  CHECK(std::fabs(s1 / n_ref) < 4.0 * 0.05 / std::sqrt(static_cast<double>(n_ref)));
  CHECK(std::sqrt(s2 / n_ref) == doctest::Approx(0.05).epsilon(0.03));
  CHECK(static_cast<double>(returns) / beams == doctest::Approx(0.8).epsilon(0.02));

  // Gating: a hull beyond max_range gives no returns, and no fit.
  o.dvl.max_range = 0.9 * o.standoff;
  const auto g = make_hull_world(o, 4, 0);
  CHECK(g.ref_return_x.empty());
  CHECK(g.query_return_x.empty());
  CHECK(std::none_of(g.ref_fits.begin(), g.ref_fits.end(), [](const auto& f) { return f.ok; }));
  // Just beyond the slant range only the noisy returns that fall short of max_range stay.
  o.dvl.max_range = r0;
  o.dvl.dropout = 0.0;
  const auto h = make_hull_world(o, 4, 0);
  CHECK(static_cast<double>(h.ref_return_x.size()) / (4.0 * h.ref_x.size()) ==
        doctest::Approx(0.5).epsilon(0.1));
}

TEST_CASE("curvature features recover the analytic curvature of the hull without range noise") {
  // A quadric hull (rocker and trim: a parabolic cylinder across x): the fit is exact.
  HullWorldOptions o = plain_hull();
  o.surface.rocker = 0.03;
  o.surface.trim = 0.02;
  auto max_errors = [](const HullWorld& w) {
    double e = 0, eq = 0;
    for (std::size_t i = 0; i < w.ref_x.size(); ++i) {
      const auto k = w.surface.curvature(w.ref_x[i], w.ref_y[i]);
      REQUIRE(w.ref_fits[i].ok);
      e = std::max({e, std::fabs(w.ref_features[i * 3] - k.kappa1),
                    std::fabs(w.ref_features[i * 3 + 1] - k.kappa2),
                    std::fabs(w.ref_features[i * 3 + 2] - k.slope)});
    }
    // The query's features are the same function of the surface, whatever θ: invariant to the transform.
    for (std::size_t j = 0; j < w.query_x.size(); ++j) {
      const auto k = w.surface.curvature(w.query_true_x[j], w.query_true_y[j]);
      eq = std::max({eq, std::fabs(w.query_features[j * 3] - k.kappa1),
                     std::fabs(w.query_features[j * 3 + 1] - k.kappa2),
                     std::fabs(w.query_features[j * 3 + 2] - k.slope)});
    }
    return std::pair{e, eq};
  };
  for (int s = 0; s < 3; ++s) {
    const auto w = make_hull_world(o, 6, s);
    const auto [e, eq] = max_errors(w);
    CHECK(e < 1e-9);
    CHECK(eq < 1e-9);
    CHECK(w.surface.curvature(0, 0).kappa2 == doctest::Approx(-0.03 / std::pow(1.0 + 0.02 * 0.02, 1.5)));
  }
  // Add a wide keel (D ≈ −deadrise·y²/(2 r_k), curvature −0.025 1/m at the keel, −0.020 at |y| = 8): no
  // longer a quadric; the fit over 1.5 m stays within 2 % of the curvatures (the worst at the survey's edges,
  // where the window is one-sided).
  o.surface.deadrise = 0.5;
  o.surface.keel_radius = 20.0;
  for (int s = 0; s < 3; ++s) {
    const auto [e, eq] = max_errors(make_hull_world(o, 6, s));
    CHECK(e < 6e-4);
    CHECK(eq < 6e-4);
  }
  // A flat hull has zero curvature and slope.
  const auto flat = make_hull_world(plain_hull(), 6, 0);
  const double m = *std::max_element(flat.ref_features.begin(), flat.ref_features.end(),
                                     [](double a, double b) { return std::fabs(a) < std::fabs(b); });
  CHECK(std::fabs(m) < 1e-9);
}

TEST_CASE("hull options validation names the struct, the field and the value") {
  auto msg = [](auto edit) {
    HullWorldOptions p;
    edit(p);
    return message_of([&] { (void)make_hull_world(p, 1, 1); });
  };
  CHECK(message_of([] { HullWorldOptions{}.validate(); }) == keel::testkit::kNoThrow);
  CHECK(contains(msg([](auto& p) { p.reference_length = 0; }), "HullWorldOptions.reference_length = 0"));
  CHECK(contains(msg([](auto& p) { p.query_width = 20; }), "HullWorldOptions.query_width = 20"));
  CHECK(contains(msg([](auto& p) { p.query_length = 40; }), "HullWorldOptions.query_length = 40"));
  CHECK(contains(msg([](auto& p) { p.track_spacing = 0; }), "HullWorldOptions.track_spacing"));
  CHECK(contains(msg([](auto& p) { p.standoff = -1; }), "HullWorldOptions.standoff = -1"));
  CHECK(contains(msg([](auto& p) { p.feature_radius = 0; }), "HullWorldOptions.feature_radius"));
  CHECK(contains(msg([](auto& p) { p.max_rotation = 7; }), "HullWorldOptions.max_rotation = 7"));
  CHECK(contains(msg([](auto& p) { p.surface.draft = 0; }), "HullSurfaceOptions.draft = 0"));
  CHECK(contains(msg([](auto& p) { p.surface.keel_radius = 0; }), "HullSurfaceOptions.keel_radius"));
  CHECK(contains(msg([](auto& p) { p.surface.dents = -1; }), "HullSurfaceOptions.dents = -1"));
  CHECK(contains(msg([](auto& p) { p.surface.dent_sigma_max = 0.1; }), "HullSurfaceOptions.dent_sigma_max"));
  CHECK(contains(msg([](auto& p) { p.surface.dent_amplitude_min = 1; }),
                 "HullSurfaceOptions.dent_amplitude_max"));
  CHECK(contains(msg([](auto& p) { p.dvl.beam_angle = 2; }), "DvlOptions.beam_angle = 2"));
  CHECK(contains(msg([](auto& p) { p.dvl.dropout = 1; }), "DvlOptions.dropout = 1"));
  CHECK(contains(msg([](auto& p) { p.dvl.range_noise = -0.1; }), "DvlOptions.range_noise"));
  CHECK(contains(msg([](auto& p) { p.dvl.max_range = 0; }), "DvlOptions.max_range = 0"));
}
