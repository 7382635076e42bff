#include "sim/alignment_world.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <utility>

#include "core/random.hpp"

namespace keel::sim {

namespace {

template <class... A>
[[noreturn]] void fail(fmt::format_string<A...> format, A&&... args) {
  throw std::invalid_argument(fmt::format(format, std::forward<A>(args)...));
}

// Number of grid steps of `spacing` that fit in `length`, tolerant of rounding (60 / 2 = 30, not 29).
int steps(double length, double spacing) {
  return static_cast<int>(std::floor(length / spacing * (1.0 + 1e-9) + 1e-9));
}

// Fills the field with `bumps` random bumps per component over [lo, hi]² grown by the largest σ, then
// rescales every component to unit RMS deviation about its mean over [lo, hi]² (sampled on a 64 × 64 grid).
FeatureField random_field(const AlignmentWorldOptions& o, double lo, double hi, core::Rng& rng) {
  FeatureField f;
  f.dim = o.feature_dim;
  f.per_component = o.bumps;
  const std::size_t n = static_cast<std::size_t>(o.feature_dim) * o.bumps;
  f.cx.resize(n);
  f.cy.resize(n);
  f.sigma.resize(n);
  f.amplitude.resize(n);
  const double margin = o.bump_sigma_max;
  for (std::size_t b = 0; b < n; ++b) {
    f.cx[b] = rng.uniform(lo - margin, hi + margin);
    f.cy[b] = rng.uniform(lo - margin, hi + margin);
    f.sigma[b] = rng.uniform(o.bump_sigma_min, o.bump_sigma_max);
    const double sign = rng.uniform() < 0.5 ? -1.0 : 1.0;
    f.amplitude[b] = sign * rng.uniform(0.5, 1.0);
  }
  constexpr int kGrid = 64;
  std::vector<double> sum(f.dim, 0.0), sum2(f.dim, 0.0), v(f.dim);
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const double x = lo + (hi - lo) * (i + 0.5) / kGrid, y = lo + (hi - lo) * (j + 0.5) / kGrid;
      f.value_into(x, y, v.data());
      for (int k = 0; k < f.dim; ++k) {
        sum[k] += v[k];
        sum2[k] += v[k] * v[k];
      }
    }
  }
  const double m = static_cast<double>(kGrid) * kGrid;
  for (int k = 0; k < f.dim; ++k) {
    const double mean = sum[k] / m, var = std::max(0.0, sum2[k] / m - mean * mean);
    const double scale = var > 0.0 ? 1.0 / std::sqrt(var) : 1.0;
    for (int b = k * f.per_component; b < (k + 1) * f.per_component; ++b) f.amplitude[b] *= scale;
  }
  return f;
}

}  // namespace

void AlignmentWorldOptions::validate() const {
  auto positive = [](const char* name, double v) {
    if (!(v > 0.0) || !std::isfinite(v))
      fail("AlignmentWorldOptions.{} = {:g}: must be > 0 and finite", name, v);
  };
  auto non_negative = [](const char* name, double v) {
    if (!(v >= 0.0) || !std::isfinite(v))
      fail("AlignmentWorldOptions.{} = {:g}: must be >= 0 and finite", name, v);
  };
  positive("reference_size", reference_size);
  positive("query_size", query_size);
  if (query_size > reference_size)
    fail(
        "AlignmentWorldOptions.query_size = {:g}: must be <= reference_size = {:g} (the query lies inside "
        "the "
        "reference area)",
        query_size, reference_size);
  if (query_random_heading && query_size * 1.4142135623730951 > reference_size)
    throw std::invalid_argument(
        fmt::format("AlignmentWorldOptions.query_size = {:g}: with query_random_heading the query square's "
                    "diagonal must fit "
                    "in reference_size = {:g}",
                    query_size, reference_size));
  if (query_random_heading && !query_track_offset)
    throw std::invalid_argument(
        "AlignmentWorldOptions.query_random_heading = true: needs query_track_offset = true (a rotated query "
        "cannot be snapped to the reference's grid)");
  positive("track_spacing", track_spacing);
  positive("sample_spacing", sample_spacing);
  if (feature_dim < 1 || feature_dim > 64)
    fail("AlignmentWorldOptions.feature_dim = {}: must be in [1, 64]", feature_dim);
  if (bumps < 1) fail("AlignmentWorldOptions.bumps = {}: must be >= 1", bumps);
  positive("bump_sigma_min", bump_sigma_min);
  positive("bump_sigma_max", bump_sigma_max);
  if (bump_sigma_max < bump_sigma_min)
    fail("AlignmentWorldOptions.bump_sigma_max = {:g}: must be >= bump_sigma_min = {:g}", bump_sigma_max,
         bump_sigma_min);
  non_negative("feature_noise", feature_noise);
  non_negative("position_noise", position_noise);
  non_negative("max_translation", max_translation);
  if (!(max_rotation >= 0.0) || !(max_rotation <= 3.14159265358979323846))
    fail("AlignmentWorldOptions.max_rotation = {:g}: must be in [0, pi]", max_rotation);
}

// The field sums Σ a exp(−q), q = |p − c|² / (2σ²), over the bumps in their order, and skips a bump only when
// adding it could not change the partial sum v, so the result is bit for bit the plain loop's
// (alignment_world_test checks it against that loop):
// - q > kUnderflow: exp(−746) ≈ 1e−324 is below half the smallest subnormal (4.94e−324), so exp rounds it to
//   +0 and a·(+0) = ±0 leaves v as it is (without calling exp, whose underflow path is its slowest).
// - v finite and normal, v ∈ [2^(kv−1), 2^kv) in magnitude, |a| < 2^ka: round-to-nearest returns v for v + x
//   whenever |x| < ulp(v)/4 = 2^(kv−55) (a quarter: below a power of two the spacing halves). The computed
//   term is at most |a|·exp(−q)·(1 + 2⁻⁵¹) < 2^(ka+1)·exp(−q) (exp within an ulp, one rounded product), so
//   q > (56 + ka − kv)·ln 2 suffices; the test asks q > (57 + ka − kv)·ln 2, a factor of two to spare.
// Once the nearest bumps are in v, the far ones (all but a few tens of a fine field's thousands of bumps
// per component) are skipped without calling exp.
constexpr double kUnderflow = 746.0;

namespace {
// The binary exponent e of a finite x with |x| < 2^e (the IEEE field minus the bias, plus one; 2^−1022
// bounds the subnormals and zero); 1025 for ±inf and NaN.
int exponent_bound(double x) {
  return static_cast<int>((std::bit_cast<std::uint64_t>(x) >> 52) & 0x7ff) - 1022;
}
}  // namespace

void FeatureField::value_into(double x, double y, double* out) const {
  constexpr double kLn2 = 0.6931471805599453;
  // q above bound(v) + ka·ln 2 cannot move v (ka: the bump's exponent_bound(a)); +inf while v is zero,
  // subnormal or not finite (no bump skipped on that ground).
  auto bound = [](double sum) {
    const int kv = exponent_bound(sum);
    return kv > -1022 && kv < 1025 ? (57 - kv) * kLn2 : std::numeric_limits<double>::infinity();
  };
  for (int k = 0; k < dim; ++k) {
    double v = offset;
    double skip_from = bound(v);
    for (int b = k * per_component; b < (k + 1) * per_component; ++b) {
      const double dx = x - cx[b], dy = y - cy[b];
      const double d2 = dx * dx + dy * dy, s2 = 2.0 * sigma[b] * sigma[b];
      // d2 > 746·s2: q > 746 (1 − 2ε), exp(−q) is +0. d2 > t·s2 with t = skip_from + ka·ln 2 below 746:
      // q > t (1 − 3ε), above (56 + ka − kv)·ln 2 with ln 2 to spare: |term| < ulp(v) / 4.
      const double t = std::min(kUnderflow, skip_from + exponent_bound(amplitude[b]) * kLn2);
      if (d2 > t * s2) continue;
      v += amplitude[b] * std::exp(-d2 / s2);
      skip_from = bound(v);
    }
    out[k] = v;
  }
}

std::vector<double> FeatureField::value(double x, double y) const {
  std::vector<double> v(static_cast<std::size_t>(dim));
  value_into(x, y, v.data());
  return v;
}

LawnMower lawn_mower(double x0, double y0, double width, double height, double track_spacing,
                     double sample_spacing) {
  if (!std::isfinite(x0) || !std::isfinite(y0))
    fail("lawn_mower: corner ({:g}, {:g}) must be finite", x0, y0);
  if (!(width >= 0.0) || !(height >= 0.0) || !std::isfinite(width) || !std::isfinite(height))
    fail("lawn_mower: width = {:g} and height = {:g} must be >= 0 and finite", width, height);
  if (!(track_spacing > 0.0) || !(sample_spacing > 0.0) || !std::isfinite(track_spacing) ||
      !std::isfinite(sample_spacing))
    fail("lawn_mower: track_spacing = {:g} and sample_spacing = {:g} must be > 0 and finite", track_spacing,
         sample_spacing);
  LawnMower l;
  l.tracks = steps(height, track_spacing) + 1;
  l.per_track = steps(width, sample_spacing) + 1;
  const std::size_t n = static_cast<std::size_t>(l.tracks) * l.per_track;
  l.x.reserve(n);
  l.y.reserve(n);
  for (int k = 0; k < l.tracks; ++k) {
    const double y = y0 + k * track_spacing;
    for (int m = 0; m < l.per_track; ++m) {
      const int mm = k % 2 == 0 ? m : l.per_track - 1 - m;
      l.x.push_back(x0 + mm * sample_spacing);
      l.y.push_back(y);
    }
  }
  return l;
}

namespace {

// The world of make_alignment_world; `draw_field` null: the bump field.
AlignmentWorld make_world(const AlignmentWorldOptions& o, std::uint64_t seed, std::uint64_t stream,
                          const std::function<FeatureFunction(std::uint64_t)>* draw_field) {
  o.validate();
  core::Rng root = core::Rng::stream(seed, stream);
  // Independent sub-streams (drawn in this fixed order), so one option changes only its own part of the
  // world.
  const std::uint64_t field_seed = root.next();
  core::Rng field_rng(field_seed), place_rng(root.next()), transform_rng(root.next()),
      feature_rng(root.next()), position_rng(root.next());

  AlignmentWorld w;
  w.feature_dim = o.feature_dim;
  const double half = 0.5 * o.reference_size;
  FeatureFunction custom;
  if (draw_field)
    custom = (*draw_field)(field_seed);
  else
    w.field = random_field(o, -half, half, field_rng);

  const LawnMower ref =
      lawn_mower(-half, -half, o.reference_size, o.reference_size, o.track_spacing, o.sample_spacing);
  w.ref_x = ref.x;
  w.ref_y = ref.y;

  // Query square: corner uniform so the square lies inside the reference square; optionally snapped to the
  // reference's sampling grid (same tracklines, same along-track positions). With query_random_heading the
  // query's tracklines run at a heading ψ ~ U[0, π) instead of along x (a second robot has no reason to
  // survey along the first one's lines), and the rotated square's centre is uniform where the square fits.
  const double room = o.reference_size - o.query_size;
  double qx0 = -half + place_rng.uniform(0.0, room), qy0 = -half + place_rng.uniform(0.0, room);
  if (!o.query_track_offset) {
    qx0 = -half + std::floor((qx0 + half) / o.sample_spacing) * o.sample_spacing;
    qy0 = -half + std::floor((qy0 + half) / o.track_spacing) * o.track_spacing;
  }
  LawnMower query;
  if (o.query_random_heading) {
    const double psi = place_rng.uniform(0.0, 3.14159265358979323846);
    const double cp = std::cos(psi), sp = std::sin(psi);
    const double q2 = 0.5 * o.query_size, extent = q2 * (std::abs(cp) + std::abs(sp));  // rotated half-extent
    const double cx = place_rng.uniform(-half + extent, half - extent);
    const double cy = place_rng.uniform(-half + extent, half - extent);
    query = lawn_mower(-q2, -q2, o.query_size, o.query_size, o.track_spacing, o.sample_spacing);
    for (std::size_t j = 0; j < query.x.size(); ++j) {
      const double x = query.x[j], y = query.y[j];
      query.x[j] = cx + cp * x - sp * y;
      query.y[j] = cy + sp * x + cp * y;
    }
    w.query_heading = psi;
    qx0 = cx + cp * -q2 - sp * -q2;  // the corner the lawn-mower starts from
    qy0 = cy + sp * -q2 + cp * -q2;
  } else {
    query = lawn_mower(qx0, qy0, o.query_size, o.query_size, o.track_spacing, o.sample_spacing);
  }
  w.query_x0 = qx0;
  w.query_y0 = qy0;
  w.query_true_x = query.x;
  w.query_true_y = query.y;

  w.theta = transform_rng.uniform(-o.max_rotation, o.max_rotation);
  w.tx = transform_rng.uniform(-o.max_translation, o.max_translation);
  w.ty = transform_rng.uniform(-o.max_translation, o.max_translation);
  const double c = std::cos(w.theta), s = std::sin(w.theta);
  const std::size_t nb = query.x.size(), na = ref.x.size();
  w.query_x.resize(nb);
  w.query_y.resize(nb);
  for (std::size_t j = 0; j < nb; ++j) {  // p_b = R(θ)ᵀ (p_a − t)
    const double dx = w.query_true_x[j] - w.tx, dy = w.query_true_y[j] - w.ty;
    w.query_x[j] = c * dx + s * dy;
    w.query_y[j] = -s * dx + c * dy;
  }

  // Features: the field at the true positions plus noise (reference first, then query).
  const std::size_t d = static_cast<std::size_t>(o.feature_dim);
  w.ref_features.resize(na * d);
  w.query_features.resize(nb * d);
  const FeatureFunction field =
      custom ? custom : [&w](double x, double y, double* out) { w.field.value_into(x, y, out); };
  for (std::size_t i = 0; i < na; ++i) field(w.ref_x[i], w.ref_y[i], &w.ref_features[i * d]);
  for (std::size_t j = 0; j < nb; ++j) field(w.query_true_x[j], w.query_true_y[j], &w.query_features[j * d]);
  if (custom) {
    // Standardised per component over the reference's noiseless values (the bump field is rescaled over the
    // reference square instead); a component that does not vary is left as it is.
    for (std::size_t k = 0; k < d; ++k) {
      double mean = 0, square = 0;
      for (std::size_t i = 0; i < na; ++i) mean += w.ref_features[i * d + k];
      mean /= static_cast<double>(na);
      for (std::size_t i = 0; i < na; ++i) square += std::pow(w.ref_features[i * d + k] - mean, 2);
      const double rms = std::sqrt(square / static_cast<double>(na));
      const double scale = rms > 0 && std::isfinite(rms) ? 1.0 / rms : 1.0;
      for (std::size_t i = 0; i < na; ++i)
        w.ref_features[i * d + k] = (w.ref_features[i * d + k] - mean) * scale;
      for (std::size_t j = 0; j < nb; ++j)
        w.query_features[j * d + k] = (w.query_features[j * d + k] - mean) * scale;
    }
  }
  if (o.feature_noise > 0.0) {
    for (double& v : w.ref_features) v += o.feature_noise * feature_rng.normal();
    for (double& v : w.query_features) v += o.feature_noise * feature_rng.normal();
  }
  if (o.position_noise > 0.0) {
    for (std::size_t i = 0; i < na; ++i) {
      w.ref_x[i] += o.position_noise * position_rng.normal();
      w.ref_y[i] += o.position_noise * position_rng.normal();
    }
    for (std::size_t j = 0; j < nb; ++j) {
      w.query_x[j] += o.position_noise * position_rng.normal();
      w.query_y[j] += o.position_noise * position_rng.normal();
    }
  }
  return w;
}

}  // namespace

AlignmentWorld make_alignment_world(const AlignmentWorldOptions& options, std::uint64_t seed,
                                    std::uint64_t stream) {
  return make_world(options, seed, stream, nullptr);
}

AlignmentWorld make_alignment_world(const AlignmentWorldOptions& options, std::uint64_t seed,
                                    std::uint64_t stream,
                                    const std::function<FeatureFunction(std::uint64_t)>& draw_field) {
  if (!draw_field) throw std::invalid_argument("make_alignment_world: draw_field is empty");
  return make_world(options, seed, stream, &draw_field);
}

}  // namespace keel::sim
