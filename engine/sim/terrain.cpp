#include "sim/terrain.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/random.hpp"

namespace keel::sim {

namespace {

// The cell [i, i + 1] of the increasing nodes v that holds t (the last cell for t = v.back()).
std::size_t cell_of(const std::vector<double>& v, double t) {
  const auto it = std::upper_bound(v.begin(), v.end(), t);
  const auto i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - v.begin() - 1, 0));
  return std::min(i, v.size() - 2);
}

}  // namespace

TerrainField::TerrainField(TerrainGrid grid) : grid_(std::move(grid)) {
  const std::size_t rows = grid_.rows(), cols = grid_.cols();
  if (rows < 3 || cols < 3 || grid_.z.size() != rows * cols)
    throw std::invalid_argument(fmt::format(
        "TerrainField: a {} x {} grid with {} values: need at least 3 x 3", rows, cols, grid_.z.size()));
  slope_.assign(rows * cols, 0.0), curvature_.assign(rows * cols, 0.0);
  // Central differences on non-uniform spacing at (f₋, f₀, f₊) with steps h₋, h₊: first and second
  // derivative.
  const auto d1 = [](double fm, double f0, double fp, double hm, double hp) {
    return (hm * hm * fp - hp * hp * fm + (hp * hp - hm * hm) * f0) / (hm * hp * (hm + hp));
  };
  const auto d2 = [](double fm, double f0, double fp, double hm, double hp) {
    return 2 * (hm * fp - (hm + hp) * f0 + hp * fm) / (hm * hp * (hm + hp));
  };
  const auto& x = grid_.x;
  const auto& y = grid_.y;
  for (std::size_t i = 1; i + 1 < rows; ++i)
    for (std::size_t c = 1; c + 1 < cols; ++c) {
      const double hxm = x[c] - x[c - 1], hxp = x[c + 1] - x[c], hym = y[i] - y[i - 1], hyp = y[i + 1] - y[i];
      const double f0 = grid_.at(i, c);
      const double zx = d1(grid_.at(i, c - 1), f0, grid_.at(i, c + 1), hxm, hxp);
      const double zy = d1(grid_.at(i - 1, c), f0, grid_.at(i + 1, c), hym, hyp);
      slope_[i * cols + c] = std::hypot(zx, zy);
      curvature_[i * cols + c] = d2(grid_.at(i, c - 1), f0, grid_.at(i, c + 1), hxm, hxp) +
                                 d2(grid_.at(i - 1, c), f0, grid_.at(i + 1, c), hym, hyp);
    }
  // The border copies the nearest interior node.
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t c = 0; c < cols; ++c) {
      const std::size_t ii = std::clamp<std::size_t>(i, 1, rows - 2),
                        cc = std::clamp<std::size_t>(c, 1, cols - 2);
      if (ii != i || cc != c) {
        slope_[i * cols + c] = slope_[ii * cols + cc];
        curvature_[i * cols + c] = curvature_[ii * cols + cc];
      }
    }
}

bool TerrainField::contains(double x, double y) const {
  return x >= grid_.x.front() && x <= grid_.x.back() && y >= grid_.y.front() && y <= grid_.y.back();
}

void TerrainField::value_into(double x, double y, double* out) const {
  if (!contains(x, y))
    throw std::out_of_range(
        fmt::format("TerrainField: ({:.1f}, {:.1f}) m is outside the grid [{:.1f}, {:.1f}] x "
                    "[{:.1f}, {:.1f}] m",
                    x, y, grid_.x.front(), grid_.x.back(), grid_.y.front(), grid_.y.back()));
  const std::size_t c = cell_of(grid_.x, x), i = cell_of(grid_.y, y), cols = grid_.cols();
  const double u = (x - grid_.x[c]) / (grid_.x[c + 1] - grid_.x[c]);
  const double v = (y - grid_.y[i]) / (grid_.y[i + 1] - grid_.y[i]);
  const auto bilinear = [&](const std::vector<double>& f) {
    const std::size_t k = i * cols + c;
    return (1 - v) * ((1 - u) * f[k] + u * f[k + 1]) + v * ((1 - u) * f[k + cols] + u * f[k + cols + 1]);
  };
  out[0] = bilinear(grid_.z), out[1] = bilinear(slope_), out[2] = bilinear(curvature_);
}

double TerrainField::roughness(const std::vector<double>& x, const std::vector<double>& y) const {
  // Least squares z ≈ a + b (x − x̄) + c (y − ȳ), by the 3 × 3 normal equations (centred, so a = z̄).
  const std::size_t n = x.size();
  if (n < 3 || y.size() != n) throw std::invalid_argument("TerrainField::roughness: need >= 3 positions");
  std::vector<double> z(n);
  double mx = 0, my = 0, mz = 0;
  for (std::size_t k = 0; k < n; ++k) {
    double f[kDim];
    value_into(x[k], y[k], f);
    z[k] = f[0], mx += x[k], my += y[k], mz += z[k];
  }
  mx /= static_cast<double>(n), my /= static_cast<double>(n), mz /= static_cast<double>(n);
  double sxx = 0, sxy = 0, syy = 0, sxz = 0, syz = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double dx = x[k] - mx, dy = y[k] - my, dz = z[k] - mz;
    sxx += dx * dx, sxy += dx * dy, syy += dy * dy, sxz += dx * dz, syz += dy * dz;
  }
  const double det = sxx * syy - sxy * sxy;
  const double b = det > 0 ? (syy * sxz - sxy * syz) / det : 0.0,
               c = det > 0 ? (sxx * syz - sxy * sxz) / det : 0.0;
  double square = 0;
  for (std::size_t k = 0; k < n; ++k) square += std::pow(z[k] - mz - b * (x[k] - mx) - c * (y[k] - my), 2);
  return std::sqrt(square / static_cast<double>(n));
}

TerrainWorld make_terrain_world(const TerrainField& field, const AlignmentWorldOptions& o, std::uint64_t seed,
                                std::uint64_t stream) {
  if (o.feature_dim != TerrainField::kDim)
    throw std::invalid_argument(
        fmt::format("AlignmentWorldOptions.feature_dim = {}: a terrain world has {} "
                    "features (elevation, slope, curvature)",
                    o.feature_dim, TerrainField::kDim));
  const TerrainGrid& g = field.grid();
  const double half = 0.5 * o.reference_size;
  const double lo_x = g.x.front() + half, hi_x = g.x.back() - half, lo_y = g.y.front() + half,
               hi_y = g.y.back() - half;
  if (!(lo_x <= hi_x && lo_y <= hi_y))
    throw std::invalid_argument(
        fmt::format("AlignmentWorldOptions.reference_size = {} m: the reference square "
                    "does not fit the {:.0f} x {:.0f} m grid",
                    o.reference_size, g.x.back() - g.x.front(), g.y.back() - g.y.front()));
  TerrainWorld t;
  t.world = make_alignment_world(o, seed, stream, [&](std::uint64_t field_seed) -> FeatureFunction {
    core::Rng rng(field_seed);
    t.centre_x = rng.uniform(lo_x, hi_x), t.centre_y = rng.uniform(lo_y, hi_y);
    return [&field, cx = t.centre_x, cy = t.centre_y](double x, double y, double* out) {
      field.value_into(cx + x, cy + y, out);
    };
  });
  const auto shifted = [&](const std::vector<double>& v, double by) {
    std::vector<double> s(v);
    for (double& e : s) e += by;
    return s;
  };
  const AlignmentWorld& w = t.world;
  t.roughness = field.roughness(shifted(w.query_true_x, t.centre_x), shifted(w.query_true_y, t.centre_y));
  return t;
}

void to_length_units(AlignmentWorld& w, double length_unit) {
  if (!(length_unit > 0 && std::isfinite(length_unit)))
    throw std::invalid_argument(
        fmt::format("to_length_units: length_unit = {}: must be a length > 0", length_unit));
  const double to_unit = 1.0 / length_unit;
  for (auto* v : {&w.ref_x, &w.ref_y, &w.query_x, &w.query_y, &w.query_true_x, &w.query_true_y})
    for (double& e : *v) e *= to_unit;
  w.tx *= to_unit, w.ty *= to_unit, w.query_x0 *= to_unit, w.query_y0 *= to_unit;
}

}  // namespace keel::sim
