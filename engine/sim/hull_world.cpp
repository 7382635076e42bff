#include "sim/hull_world.hpp"

#include <Eigen/Core>
#include <Eigen/QR>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "core/random.hpp"
#include "sim/alignment_world.hpp"

namespace keel::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

template <class... A>
[[noreturn]] void fail(fmt::format_string<A...> format, A&&... args) {
  throw std::invalid_argument(fmt::format(format, std::forward<A>(args)...));
}

void positive(const char* type, const char* name, double v) {
  if (!(v > 0.0) || !std::isfinite(v)) fail("{}.{} = {:g}: must be > 0 and finite", type, name, v);
}
void non_negative(const char* type, const char* name, double v) {
  if (!(v >= 0.0) || !std::isfinite(v)) fail("{}.{} = {:g}: must be >= 0 and finite", type, name, v);
}

// softplus and its derivative (the logistic function), overflow-safe.
double softplus(double s) { return s > 30.0 ? s : std::log1p(std::exp(s)); }
double logistic(double s) { return 1.0 / (1.0 + std::exp(-s)); }

// Random dents over [x_lo, x_hi] × [y_lo, y_hi] grown by the largest dent σ.
HullSurface make_hull_surface(const HullSurfaceOptions& o, double x_lo, double x_hi, double y_lo, double y_hi,
                              core::Rng& rng) {
  HullSurface h;
  h.shape = o;
  const double m = o.dent_sigma_max;
  for (int k = 0; k < o.dents; ++k) {
    h.dent_x.push_back(rng.uniform(x_lo - m, x_hi + m));
    h.dent_y.push_back(rng.uniform(y_lo - m, y_hi + m));
    h.dent_sigma.push_back(rng.uniform(o.dent_sigma_min, o.dent_sigma_max));
    const double sign = rng.uniform() < 0.5 ? -1.0 : 1.0;
    h.dent_amplitude.push_back(sign * rng.uniform(o.dent_amplitude_min, o.dent_amplitude_max));
  }
  return h;
}

// Range along the unit direction (ux, uy, uz), uz < 0 (upwards), from (x, y, z) below the hull to the
// surface; < 0 when the surface is not reached within max_range. Safeguarded Newton on f(r) = z + r uz − D(x
// + r ux, ...), which is positive below the hull.
double ray_cast(const HullSurface& h, double x, double y, double z, double ux, double uy, double uz,
                double max_range) {
  auto f = [&](double r, double* df) {
    double dx = 0, dy = 0;
    const double d = h.depth(x + r * ux, y + r * uy, &dx, &dy);
    if (df) *df = uz - dx * ux - dy * uy;
    return z + r * uz - d;
  };
  double lo = 0.0, hi = max_range;
  if (f(lo, nullptr) <= 0.0) return 0.0;  // at or above the surface
  if (f(hi, nullptr) > 0.0) return -1.0;  // not reached
  double r = std::min(hi, (z - h.depth(x, y)) / -uz);
  for (int it = 0; it < 100; ++it) {
    double df = 0;
    const double v = f(r, &df);
    if (v > 0.0)
      lo = r;
    else
      hi = r;
    if (std::fabs(v) < 1e-13 || hi - lo < 1e-13) break;
    double next = df < 0.0 ? r - v / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    r = next;
  }
  return r;
}

struct Survey {
  std::vector<double> nav_x, nav_y, z;  // positions in the survey's own frame (navigation, possibly noisy)
  std::vector<double> rx, ry, rz;       // returns, own frame
  std::vector<int> owner;
  std::vector<SurfaceCurvature> fits;
  std::vector<double> features;
};

// Simulates the DVL of one survey. True positions (ship frame) drive the physics; the survey's own frame is
// p_own = R(θ)ᵀ (p_true − t) (θ = 0, t = 0 for the reference), plus position noise.
Survey survey(const HullWorldOptions& o, const HullSurface& hull, const LawnMower& path, double theta,
              double tx, double ty, core::Rng& dvl_rng, core::Rng& position_rng) {
  Survey s;
  const std::size_t n = path.x.size();
  const double c = std::cos(theta), sn = std::sin(theta);
  s.nav_x.resize(n);
  s.nav_y.resize(n);
  s.z.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = path.x[i] - tx, dy = path.y[i] - ty;
    s.nav_x[i] = c * dx + sn * dy + o.position_noise * position_rng.normal();
    s.nav_y[i] = -sn * dx + c * dy + o.position_noise * position_rng.normal();
    s.z[i] = hull.depth(path.x[i], path.y[i]) + o.standoff;
  }
  const double sb = std::sin(o.dvl.beam_angle), cb = std::cos(o.dvl.beam_angle);
  for (std::size_t i = 0; i < n; ++i) {
    const int track = static_cast<int>(i) / path.per_track;
    const double heading = track % 2 == 0 ? 0.0 : kPi;  // ship frame: driving direction of the trackline
    for (int b = 0; b < 4; ++b) {
      const double az = heading + kPi / 4.0 + b * kPi / 2.0;
      const double ux = sb * std::cos(az), uy = sb * std::sin(az), uz = -cb;
      // Every beam draws its dropout and noise, so the stream does not depend on which beams return.
      const bool lost = dvl_rng.uniform() < o.dvl.dropout;
      const double noise = o.dvl.range_noise * dvl_rng.normal();
      const double r = ray_cast(hull, path.x[i], path.y[i], s.z[i], ux, uy, uz, o.dvl.max_range);
      if (lost || r < 0.0) continue;
      const double range = r + noise;
      if (!(range > 0.0) || range > o.dvl.max_range) continue;
      s.rx.push_back(s.nav_x[i] + range * (c * ux + sn * uy));  // beam direction in the own frame
      s.ry.push_back(s.nav_y[i] + range * (-sn * ux + c * uy));
      s.rz.push_back(s.z[i] + range * uz);
      s.owner.push_back(static_cast<int>(i));
    }
  }
  // Curvature features from the returns of the positions within feature_radius.
  std::vector<std::vector<int>> returns_of(n);
  for (std::size_t k = 0; k < s.owner.size(); ++k) returns_of[s.owner[k]].push_back(static_cast<int>(k));
  s.fits.resize(n);
  s.features.resize(n * HullWorld::kFeatureDim);
  const double r2 = o.feature_radius * o.feature_radius;
  std::vector<double> px, py, pz;
  for (std::size_t i = 0; i < n; ++i) {
    px.clear();
    py.clear();
    pz.clear();
    for (std::size_t j = 0; j < n; ++j) {
      const double dx = s.nav_x[j] - s.nav_x[i], dy = s.nav_y[j] - s.nav_y[i];
      if (dx * dx + dy * dy > r2) continue;
      for (const int k : returns_of[j]) {
        px.push_back(s.rx[k]);
        py.push_back(s.ry[k]);
        pz.push_back(s.rz[k]);
      }
    }
    s.fits[i] = fit_surface_curvature(px, py, pz, s.nav_x[i], s.nav_y[i]);
    s.features[i * 3 + 0] = s.fits[i].kappa1;
    s.features[i * 3 + 1] = s.fits[i].kappa2;
    s.features[i * 3 + 2] = s.fits[i].slope;
  }
  return s;
}

}  // namespace

void HullSurfaceOptions::validate() const {
  constexpr const char* T = "HullSurfaceOptions";
  positive(T, "draft", draft);
  if (!std::isfinite(trim)) fail("HullSurfaceOptions.trim = {:g}: must be finite", trim);
  non_negative(T, "rocker", rocker);
  non_negative(T, "deadrise", deadrise);
  positive(T, "keel_radius", keel_radius);
  non_negative(T, "bilge_offset", bilge_offset);
  non_negative(T, "bilge_curvature", bilge_curvature);
  positive(T, "bilge_smoothing", bilge_smoothing);
  if (dents < 0) fail("HullSurfaceOptions.dents = {}: must be >= 0", dents);
  non_negative(T, "dent_amplitude_min", dent_amplitude_min);
  non_negative(T, "dent_amplitude_max", dent_amplitude_max);
  if (dent_amplitude_max < dent_amplitude_min)
    fail("HullSurfaceOptions.dent_amplitude_max = {:g}: must be >= dent_amplitude_min = {:g}",
         dent_amplitude_max, dent_amplitude_min);
  positive(T, "dent_sigma_min", dent_sigma_min);
  positive(T, "dent_sigma_max", dent_sigma_max);
  if (dent_sigma_max < dent_sigma_min)
    fail("HullSurfaceOptions.dent_sigma_max = {:g}: must be >= dent_sigma_min = {:g}", dent_sigma_max,
         dent_sigma_min);
}

void DvlOptions::validate() const {
  if (!(beam_angle > 0.0) || !(beam_angle < 0.5 * kPi))
    fail("DvlOptions.beam_angle = {:g}: must be in (0, pi/2)", beam_angle);
  non_negative("DvlOptions", "range_noise", range_noise);
  if (!(dropout >= 0.0) || !(dropout < 1.0)) fail("DvlOptions.dropout = {:g}: must be in [0, 1)", dropout);
  positive("DvlOptions", "max_range", max_range);
}

void HullWorldOptions::validate() const {
  constexpr const char* T = "HullWorldOptions";
  positive(T, "reference_length", reference_length);
  positive(T, "reference_width", reference_width);
  positive(T, "query_length", query_length);
  positive(T, "query_width", query_width);
  if (query_length > reference_length)
    fail("HullWorldOptions.query_length = {:g}: must be <= reference_length = {:g}", query_length,
         reference_length);
  if (query_width > reference_width)
    fail("HullWorldOptions.query_width = {:g}: must be <= reference_width = {:g}", query_width,
         reference_width);
  positive(T, "track_spacing", track_spacing);
  positive(T, "sample_spacing", sample_spacing);
  positive(T, "standoff", standoff);
  positive(T, "feature_radius", feature_radius);
  non_negative(T, "position_noise", position_noise);
  non_negative(T, "max_translation", max_translation);
  if (!(max_rotation >= 0.0) || !(max_rotation <= kPi))
    fail("HullWorldOptions.max_rotation = {:g}: must be in [0, pi]", max_rotation);
  surface.validate();
  dvl.validate();
}

SurfaceCurvature graph_curvature(double fu, double fv, double fuu, double fuv, double fvv) {
  SurfaceCurvature k;
  const double w2 = 1.0 + fu * fu + fv * fv, w = std::sqrt(w2);
  k.gaussian = (fuu * fvv - fuv * fuv) / (w2 * w2);
  k.mean = ((1.0 + fv * fv) * fuu - 2.0 * fu * fv * fuv + (1.0 + fu * fu) * fvv) / (2.0 * w2 * w);
  const double disc = std::sqrt(std::max(0.0, k.mean * k.mean - k.gaussian));
  k.kappa1 = k.mean + disc;
  k.kappa2 = k.mean - disc;
  k.slope = std::hypot(fu, fv);
  return k;
}

SurfaceCurvature fit_surface_curvature(std::span<const double> x, std::span<const double> y,
                                       std::span<const double> z, double cx, double cy) {
  if (x.size() != y.size() || x.size() != z.size())
    fail("fit_surface_curvature: {} x, {} y and {} z values", x.size(), y.size(), z.size());
  const Eigen::Index n = static_cast<Eigen::Index>(x.size());
  double scale = 0.0;  // u, v are divided by their largest magnitude for conditioning
  for (Eigen::Index i = 0; i < n; ++i) scale = std::max({scale, std::fabs(x[i] - cx), std::fabs(y[i] - cy)});
  if (!(scale > 0.0)) scale = 1.0;
  Eigen::MatrixXd A(n, 6);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double u = (x[i] - cx) / scale, v = (y[i] - cy) / scale;
    A.row(i) << 1.0, u, v, u * u, u * v, v * v;
    b(i) = z[i];
  }
  if (n >= 6) {
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
    qr.setThreshold(1e-9);
    if (qr.rank() == 6) {
      const Eigen::VectorXd p = qr.solve(b);
      const double s2 = scale * scale;
      SurfaceCurvature k =
          graph_curvature(p(1) / scale, p(2) / scale, 2.0 * p(3) / s2, p(4) / s2, 2.0 * p(5) / s2);
      k.points = static_cast<int>(n);
      return k;
    }
  }
  SurfaceCurvature k;
  k.ok = false;
  k.points = static_cast<int>(n);
  if (n >= 3) {
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A.leftCols(3));
    qr.setThreshold(1e-9);
    if (qr.rank() == 3) {
      const Eigen::VectorXd p = qr.solve(b);
      k.slope = std::hypot(p(1), p(2)) / scale;
    }
  }
  return k;
}

double HullSurface::depth(double x, double y, double* dx, double* dy, double* dxx, double* dxy,
                          double* dyy) const {
  const HullSurfaceOptions& o = shape;
  double d = o.draft - o.trim * x - 0.5 * o.rocker * x * x;
  double gx = -o.trim - o.rocker * x, gy = 0.0, hxx = -o.rocker, hxy = 0.0, hyy = 0.0;
  // Rounded-V keel.
  const double rk = o.keel_radius, g = std::sqrt(y * y + rk * rk);
  d -= o.deadrise * (g - rk);
  gy -= o.deadrise * y / g;
  hyy -= o.deadrise * rk * rk / (g * g * g);
  // Bilges: one smooth quadratic turn on each side.
  const double l = o.bilge_smoothing;
  for (const double side : {1.0, -1.0}) {
    const double s = (side * y - o.bilge_offset) / l, sp = softplus(s), sg = logistic(s);
    d -= 0.5 * o.bilge_curvature * l * l * sp * sp;
    gy -= side * o.bilge_curvature * l * sp * sg;
    hyy -= o.bilge_curvature * (sg * sg + sp * sg * (1.0 - sg));
  }
  // Dents and bulges.
  for (std::size_t k = 0; k < dent_x.size(); ++k) {
    const double ex = x - dent_x[k], ey = y - dent_y[k], s2 = dent_sigma[k] * dent_sigma[k];
    const double q = (ex * ex + ey * ey) / (2.0 * s2);
    if (q > 40.0) continue;  // exp(−40) ≈ 4e-18 of a few centimetres
    const double a = dent_amplitude[k] * std::exp(-q);
    d += a;
    gx -= a * ex / s2;
    gy -= a * ey / s2;
    hxx += a * (ex * ex / (s2 * s2) - 1.0 / s2);
    hxy += a * ex * ey / (s2 * s2);
    hyy += a * (ey * ey / (s2 * s2) - 1.0 / s2);
  }
  if (dx) *dx = gx;
  if (dy) *dy = gy;
  if (dxx) *dxx = hxx;
  if (dxy) *dxy = hxy;
  if (dyy) *dyy = hyy;
  return d;
}

double HullSurface::depth(double x, double y) const { return depth(x, y, nullptr, nullptr); }

SurfaceCurvature HullSurface::curvature(double x, double y) const {
  double gx = 0, gy = 0, hxx = 0, hxy = 0, hyy = 0;
  depth(x, y, &gx, &gy, &hxx, &hxy, &hyy);
  return graph_curvature(gx, gy, hxx, hxy, hyy);
}

HullWorld make_hull_world(const HullWorldOptions& o, std::uint64_t seed, std::uint64_t stream) {
  o.validate();
  core::Rng root = core::Rng::stream(seed, stream);
  core::Rng hull_rng(root.next()), place_rng(root.next()), transform_rng(root.next()), dvl_rng(root.next()),
      position_rng(root.next());

  HullWorld w;
  const double hx = 0.5 * o.reference_length, hy = 0.5 * o.reference_width;
  w.surface = make_hull_surface(o.surface, -hx, hx, -hy, hy, hull_rng);

  const LawnMower ref =
      lawn_mower(-hx, -hy, o.reference_length, o.reference_width, o.track_spacing, o.sample_spacing);
  double qx0 = -hx + place_rng.uniform(0.0, o.reference_length - o.query_length);
  double qy0 = -hy + place_rng.uniform(0.0, o.reference_width - o.query_width);
  if (!o.query_track_offset) {
    qx0 = -hx + std::floor((qx0 + hx) / o.sample_spacing) * o.sample_spacing;
    qy0 = -hy + std::floor((qy0 + hy) / o.track_spacing) * o.track_spacing;
  }
  w.query_x0 = qx0;
  w.query_y0 = qy0;
  const LawnMower query =
      lawn_mower(qx0, qy0, o.query_length, o.query_width, o.track_spacing, o.sample_spacing);
  w.query_true_x = query.x;
  w.query_true_y = query.y;

  w.theta = transform_rng.uniform(-o.max_rotation, o.max_rotation);
  w.tx = transform_rng.uniform(-o.max_translation, o.max_translation);
  w.ty = transform_rng.uniform(-o.max_translation, o.max_translation);

  Survey a = survey(o, w.surface, ref, 0.0, 0.0, 0.0, dvl_rng, position_rng);
  Survey b = survey(o, w.surface, query, w.theta, w.tx, w.ty, dvl_rng, position_rng);
  w.ref_x = std::move(a.nav_x);
  w.ref_y = std::move(a.nav_y);
  w.ref_z = std::move(a.z);
  w.ref_features = std::move(a.features);
  w.ref_fits = std::move(a.fits);
  w.ref_return_x = std::move(a.rx);
  w.ref_return_y = std::move(a.ry);
  w.ref_return_z = std::move(a.rz);
  w.ref_return_owner = std::move(a.owner);
  w.query_x = std::move(b.nav_x);
  w.query_y = std::move(b.nav_y);
  w.query_z = std::move(b.z);
  w.query_features = std::move(b.features);
  w.query_fits = std::move(b.fits);
  w.query_return_x = std::move(b.rx);
  w.query_return_y = std::move(b.ry);
  w.query_return_z = std::move(b.rz);
  w.query_return_owner = std::move(b.owner);
  return w;
}

}  // namespace keel::sim
