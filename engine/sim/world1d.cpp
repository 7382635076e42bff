#include "sim/world1d.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "core/names.hpp"

namespace keel::sim {

namespace {

// Throws std::invalid_argument with the formatted message.
template <class... A>
[[noreturn]] void fail(fmt::format_string<A...> format, A&&... args) {
  throw std::invalid_argument(fmt::format(format, std::forward<A>(args)...));
}

// Uniform integer in [lo, hi].
int uniform_int(core::Rng& rng, int lo, int hi) {
  const int k = lo + static_cast<int>(rng.uniform() * static_cast<double>(hi - lo + 1));
  return std::min(k, hi);
}

}  // namespace

namespace {
constexpr core::NameTable<MeasurementLabel, 3> kMeasurementLabelNames{
    "sim::MeasurementLabel",
    {{{MeasurementLabel::inlier, "inlier"},
      {MeasurementLabel::aliased, "aliased"},
      {MeasurementLabel::random, "random"}}}};
}  // namespace

std::string_view to_string(MeasurementLabel v) { return kMeasurementLabelNames.name(v); }
MeasurementLabel measurement_label_from_string(std::string_view s) { return kMeasurementLabelNames.parse(s); }

void World1DOptions::validate() const {
  if (!std::isfinite(x)) fail("World1DOptions::x must be finite (got {:g})", x);
  if (!(sigma_inlier > 0.0) || !std::isfinite(sigma_inlier))
    fail("World1DOptions::sigma_inlier must be > 0 and finite (got {:g})", sigma_inlier);
  const struct {
    const char* name;
    int lo, hi;
  } counts[] = {{"inliers", inliers_min, inliers_max},
                {"aliased", aliased_min, aliased_max},
                {"random", random_min, random_max}};
  for (const auto& c : counts) {
    if (c.lo < 0 || c.hi < c.lo) {
      fail("World1DOptions::{}_min/_max: need 0 <= min <= max (got {}, {})", c.name, c.lo, c.hi);
    }
  }
  if (inliers_max + aliased_max + random_max < 1) {
    throw std::invalid_argument(
        "World1DOptions: the maximum counts of inliers, aliased and random outliers are all 0 "
        "(a world needs at least one measurement)");
  }
  if (!(outlier_mean_range >= 0.0) || !std::isfinite(outlier_mean_range))
    fail("World1DOptions::outlier_mean_range must be >= 0 and finite (got {:g})", outlier_mean_range);
  if (!(outlier_sigma_min > 0.0) || !(outlier_sigma_max >= outlier_sigma_min) ||
      !std::isfinite(outlier_sigma_max))
    fail("World1DOptions::outlier_sigma_min/_max: need 0 < min <= max < inf (got {:g}, {:g})",
         outlier_sigma_min, outlier_sigma_max);
}

World1DOptions world1d_options_with_total(const World1DOptions& base, int total, double inlier_fraction,
                                          double aliased_fraction) {
  if (total < 1) fail("world1d_options_with_total: total must be >= 1 (got {})", total);
  if (!(inlier_fraction >= 0.0 && aliased_fraction >= 0.0 && inlier_fraction + aliased_fraction <= 1.0)) {
    fail("world1d_options_with_total: need fractions >= 0 with inlier + aliased <= 1 (got {:g}, {:g})",
         inlier_fraction, aliased_fraction);
  }
  World1DOptions o = base;
  const int n_in = std::min(total, static_cast<int>(std::lround(inlier_fraction * total)));
  const int n_al = std::min(total - n_in, static_cast<int>(std::lround(aliased_fraction * total)));
  o.inliers_min = o.inliers_max = n_in;
  o.aliased_min = o.aliased_max = n_al;
  o.random_min = o.random_max = total - n_in - n_al;
  o.validate();
  return o;
}

int World1D::count(MeasurementLabel label) const {
  return static_cast<int>(std::count(labels.begin(), labels.end(), label));
}

World1D generate_world1d(const World1DOptions& options, core::Rng& rng) {
  options.validate();
  World1D w;
  w.x = options.x;
  const int n_in = uniform_int(rng, options.inliers_min, options.inliers_max);
  const int n_al = uniform_int(rng, options.aliased_min, options.aliased_max);
  const int n_rand = uniform_int(rng, options.random_min, options.random_max);
  const int m = n_in + n_al + n_rand;
  w.z.reserve(m);
  w.sigma.reserve(m);
  w.labels.reserve(m);
  auto add = [&](double z, double s, MeasurementLabel l) {
    w.z.push_back(z);
    w.sigma.push_back(s);
    w.labels.push_back(l);
  };
  const double R = options.outlier_mean_range;
  const double smin = options.outlier_sigma_min, smax = options.outlier_sigma_max;
  // §2.7.1: inliers from a Gaussian of fixed variance centred on x.
  for (int i = 0; i < n_in; ++i)
    add(options.x + options.sigma_inlier * rng.normal(), options.sigma_inlier, MeasurementLabel::inlier);
  // One perceptually aliased group: several samples from a single Gaussian with its own (random) mean and
  // variance.
  w.aliased_mean = rng.uniform(options.x - R, options.x + R);
  w.aliased_sigma = rng.uniform(smin, smax);
  for (int i = 0; i < n_al; ++i)
    add(w.aliased_mean + w.aliased_sigma * rng.normal(), w.aliased_sigma, MeasurementLabel::aliased);
  // Random outliers: each from its own Gaussian with random mean and variance.
  for (int i = 0; i < n_rand; ++i) {
    const double mu = rng.uniform(options.x - R, options.x + R);
    const double s = rng.uniform(smin, smax);
    add(mu + s * rng.normal(), s, MeasurementLabel::random);
  }
  if (options.shuffle) {  // Fisher–Yates with the world's own stream
    for (int i = m - 1; i > 0; --i) {
      const int j = uniform_int(rng, 0, i);
      std::swap(w.z[i], w.z[j]);
      std::swap(w.sigma[i], w.sigma[j]);
      std::swap(w.labels[i], w.labels[j]);
    }
  }
  return w;
}

World1D generate_world1d(const World1DOptions& options, std::uint64_t seed, std::uint64_t world_index) {
  core::Rng rng = core::Rng::stream(seed, world_index);
  return generate_world1d(options, rng);
}

pcm::ConsistencyMatrix world1d_consistency_matrix(const World1D& world) {
  const int m = world.size();
  if (m == 0) throw std::invalid_argument("world1d_consistency_matrix: the world has no measurements");
  if (world.sigma.size() != world.z.size()) {
    fail("world1d_consistency_matrix: {} measurements but {} standard deviations", world.z.size(),
         world.sigma.size());
  }
  for (int u = 0; u < m; ++u) {
    if (!std::isfinite(world.z[u]))
      fail("world1d_consistency_matrix: measurement z = {:g} is not finite", world.z[u]);
    if (!(world.sigma[u] > 0.0) || !std::isfinite(world.sigma[u]))
      fail("world1d_consistency_matrix: standard deviation {:g} must be > 0 and finite", world.sigma[u]);
  }
  pcm::ConsistencyMatrix Q;
  Q.n = m;
  Q.dof = kWorld1DDof;
  Q.q.assign(static_cast<std::size_t>(m) * m, 0.0);
  for (int u = 0; u < m; ++u) {
    for (int v = u + 1; v < m; ++v) {
      const double d = world.z[u] - world.z[v];
      // Squared Mahalanobis distance of z_u − z_v ~ N(0, σ_u² + σ_v²) under the hypothesis that both observe
      // x.
      const double q = d * d / (world.sigma[u] * world.sigma[u] + world.sigma[v] * world.sigma[v]);
      Q.q[static_cast<std::size_t>(u) * m + v] = q;
      Q.q[static_cast<std::size_t>(v) * m + u] = q;
    }
  }
  return Q;
}

}  // namespace keel::sim
