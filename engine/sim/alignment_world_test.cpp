// The alignment worlds of §3.7: determinism, the ground-truth transform (eq. 3.1), the lawn-mower geometry,
// the query inside the reference area, the field's normalisation and the noise statistics, option validation.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "kit/test_kit.hpp"
#include "sim/alignment_world.hpp"

using namespace keel::sim;
using keel::testkit::contains;
using keel::testkit::message_of;

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TEST_CASE("lawn_mower: tracklines along x, boustrophedon order, counts from the spacings") {
  const auto l = lawn_mower(1.0, 2.0, 4.0, 3.0, 1.5, 1.0);
  CHECK(l.tracks == 3);  // y = 2, 3.5, 5
  CHECK(l.per_track == 5);
  REQUIRE(l.x.size() == 15);
  REQUIRE(l.y.size() == 15);
  CHECK(l.x[0] == 1.0);
  CHECK(l.x[4] == 5.0);
  CHECK(l.x[5] == 5.0);  // second track driven back
  CHECK(l.x[9] == 1.0);
  CHECK(l.x[10] == 1.0);
  CHECK(l.y[4] == 2.0);
  CHECK(l.y[5] == 3.5);
  CHECK(l.y[14] == 5.0);
  // Consecutive positions are one sample apart along a track, one track apart at a turn.
  for (std::size_t i = 1; i < l.x.size(); ++i) {
    const double d = std::hypot(l.x[i] - l.x[i - 1], l.y[i] - l.y[i - 1]);
    CHECK((d == doctest::Approx(1.0) || d == doctest::Approx(1.5)));
  }
  // 60 / 2 counts 31 tracks despite rounding; a zero-size survey is one position.
  CHECK(lawn_mower(0, 0, 60.0, 60.0, 2.0, 1.0).tracks == 31);
  CHECK(lawn_mower(0, 0, 0.3 * 3, 0.1 * 3, 0.1, 0.3).tracks == 4);
  CHECK(lawn_mower(0, 0, 0.3 * 3, 0.1 * 3, 0.1, 0.3).per_track == 4);
  CHECK(lawn_mower(0, 0, 0, 0, 1, 1).x.size() == 1);
  CHECK(contains(message_of([] { (void)lawn_mower(0, 0, -1, 1, 1, 1); }), "width"));
  CHECK(contains(message_of([] { (void)lawn_mower(0, 0, 1, 1, 0, 1); }), "track_spacing"));
}

TEST_CASE("alignment worlds are deterministic per (seed, stream)") {
  AlignmentWorldOptions o;
  o.position_noise = 0.2;
  const auto a = make_alignment_world(o, 7, 3), b = make_alignment_world(o, 7, 3);
  const auto c = make_alignment_world(o, 7, 4), d = make_alignment_world(o, 8, 3);
  CHECK(a.ref_x == b.ref_x);
  CHECK(a.ref_y == b.ref_y);
  CHECK(a.query_x == b.query_x);
  CHECK(a.query_y == b.query_y);
  CHECK(a.ref_features == b.ref_features);
  CHECK(a.query_features == b.query_features);
  CHECK(a.field.amplitude == b.field.amplitude);
  CHECK(a.theta == b.theta);
  CHECK(a.tx == b.tx);
  CHECK(a.ty == b.ty);
  CHECK(a.ref_features != c.ref_features);
  CHECK(a.query_x != c.query_x);
  CHECK(a.theta != c.theta);
  CHECK(a.field.cx != d.field.cx);
  // Sub-streams: a noise level changes only the noise, not the field, placement or transform.
  AlignmentWorldOptions quiet = o;
  quiet.feature_noise = 0.0;
  quiet.position_noise = 0.0;
  const auto q = make_alignment_world(quiet, 7, 3);
  CHECK(q.field.cx == a.field.cx);
  CHECK(q.query_true_x == a.query_true_x);
  CHECK(q.theta == a.theta);
  CHECK(q.ref_features != a.ref_features);
}

TEST_CASE("ground truth: R(θ) p_query + t = p_true; the query lies inside the reference square") {
  AlignmentWorldOptions o;
  o.position_noise = 0.0;
  const double half = 0.5 * o.reference_size;
  double min_theta = 10, max_theta = -10, max_t = 0;
  for (int s = 0; s < 200; ++s) {
    const auto w = make_alignment_world(o, 11, s);
    const double c = std::cos(w.theta), sn = std::sin(w.theta);
    REQUIRE(w.query_x.size() == w.query_true_x.size());
    double err = 0, extent = 0;
    for (std::size_t j = 0; j < w.query_x.size(); ++j) {
      err = std::max(err, std::fabs(c * w.query_x[j] - sn * w.query_y[j] + w.tx - w.query_true_x[j]));
      err = std::max(err, std::fabs(sn * w.query_x[j] + c * w.query_y[j] + w.ty - w.query_true_y[j]));
      extent = std::max({extent, std::fabs(w.query_true_x[j]), std::fabs(w.query_true_y[j])});
    }
    CHECK(err < 1e-12);
    CHECK(extent <= half);
    // Tracklines run at the heading ψ: the first two positions of the first line are sample_spacing apart
    // along it.
    CHECK(w.query_true_x[1] - w.query_true_x[0] ==
          doctest::Approx(o.sample_spacing * std::cos(w.query_heading)));
    CHECK(w.query_true_y[1] - w.query_true_y[0] ==
          doctest::Approx(o.sample_spacing * std::sin(w.query_heading)));
    CHECK(w.query_heading >= 0);
    CHECK(w.query_heading < kPi);
    min_theta = std::min(min_theta, w.theta);
    max_theta = std::max(max_theta, w.theta);
    max_t = std::max({max_t, std::fabs(w.tx), std::fabs(w.ty)});
    CHECK(w.theta >= -o.max_rotation);
    CHECK(w.theta < o.max_rotation);
  }
  CHECK(min_theta < -0.9 * kPi);  // the full circle is covered
  {
    o.query_random_heading = false;  // axis-aligned query square inside the reference square
    const auto w = make_alignment_world(o, 11, 0);
    CHECK(w.query_heading == 0.0);
    CHECK(w.query_x0 >= -half);
    CHECK(w.query_x0 + o.query_size <= half);
    CHECK(w.query_y0 >= -half);
    CHECK(w.query_y0 + o.query_size <= half);
  }
  CHECK(max_theta > 0.9 * kPi);
  CHECK(max_t <= o.max_translation);
  CHECK(max_t > 0.9 * o.max_translation);
}

TEST_CASE("point counts follow the lawn-mower geometry; reference positions are its grid") {
  AlignmentWorldOptions o;
  const auto w = make_alignment_world(o, 1, 1);
  CHECK(w.ref_x.size() == 31u * 61u);  // 60 m / 2 m + 1 tracks, 60 m / 1 m + 1 positions
  CHECK(w.query_x.size() == 13u * 25u);
  CHECK(w.ref_features.size() == w.ref_x.size() * 3);
  CHECK(w.query_features.size() == w.query_x.size() * 3);
  CHECK(w.feature_dim == 3);
  const auto l = lawn_mower(-30, -30, 60, 60, 2, 1);
  CHECK(w.ref_x == l.x);
  CHECK(w.ref_y == l.y);
  o.reference_size = 40.0;
  o.query_size = 10.0;
  o.track_spacing = 2.5;
  o.sample_spacing = 0.5;
  const auto v = make_alignment_world(o, 1, 1);
  CHECK(v.ref_x.size() == 17u * 81u);
  CHECK(v.query_x.size() == 5u * 21u);
}

TEST_CASE("query tracklines: offset by a random fraction of the spacing, or on the reference's lines") {
  AlignmentWorldOptions o;
  o.feature_noise = 0.0;
  std::vector<double> fractions;
  for (int s = 0; s < 100; ++s) {
    const auto w = make_alignment_world(o, 5, s);
    const double f = (w.query_y0 + 0.5 * o.reference_size) / o.track_spacing;
    fractions.push_back(f - std::floor(f));
  }
  std::sort(fractions.begin(), fractions.end());
  CHECK(fractions.front() < 0.05);
  CHECK(fractions.back() > 0.95);
  CHECK(fractions[50] == doctest::Approx(0.5).epsilon(0.2));

  o.query_track_offset = false;
  o.query_random_heading = false;
  for (int s = 0; s < 20; ++s) {
    const auto w = make_alignment_world(o, 5, s);
    // Every true query position is a reference position with the same (noiseless) feature vector.
    for (std::size_t j = 0; j < w.query_true_x.size(); j += 17) {
      double best = 1e9;
      std::size_t at = 0;
      for (std::size_t i = 0; i < w.ref_x.size(); ++i) {
        const double d = std::hypot(w.ref_x[i] - w.query_true_x[j], w.ref_y[i] - w.query_true_y[j]);
        if (d < best) best = d, at = i;
      }
      CHECK(best < 1e-9);
      for (int k = 0; k < 3; ++k)
        CHECK(w.query_features[j * 3 + k] == doctest::Approx(w.ref_features[at * 3 + k]));
    }
  }
}

TEST_CASE("features: the field at the true position plus N(0, feature_noise²); the field has unit RMS") {
  AlignmentWorldOptions o;
  o.feature_noise = 0.3;
  o.position_noise = 0.5;  // positions are noisy, features still come from the true positions
  double s1 = 0, s2 = 0, s4 = 0;
  long long n = 0;
  for (int s = 0; s < 20; ++s) {
    const auto w = make_alignment_world(o, 21, s);
    const double half = 0.5 * o.reference_size;
    const auto l =
        lawn_mower(-half, -half, o.reference_size, o.reference_size, o.track_spacing, o.sample_spacing);
    auto add = [&](double x, double y, const double* f) {
      const auto v = w.field.value(x, y);
      for (int k = 0; k < w.feature_dim; ++k) {
        const double r = f[k] - v[k];
        s1 += r;
        s2 += r * r;
        s4 += r * r * r * r;
        ++n;
      }
    };
    for (std::size_t i = 0; i < l.x.size(); ++i) add(l.x[i], l.y[i], &w.ref_features[i * 3]);
    for (std::size_t j = 0; j < w.query_true_x.size(); ++j)
      add(w.query_true_x[j], w.query_true_y[j], &w.query_features[j * 3]);
  }
  const double mean = s1 / n, var = s2 / n;
  CHECK(std::fabs(mean) < 4.0 * o.feature_noise / std::sqrt(static_cast<double>(n)));
  // Var of the sample variance of a normal is 2σ⁴/n: a 4-sigma band.
  CHECK(std::fabs(var - 0.09) < 4.0 * std::sqrt(2.0 / n) * 0.09);
  CHECK(s4 / n / (var * var) == doctest::Approx(3.0).epsilon(0.05));  // Gaussian kurtosis

  // The noiseless field: unit RMS about its mean per component over the reference square; smooth.
  o.feature_noise = 0.0;
  o.position_noise = 0.0;
  for (int s = 0; s < 10; ++s) {
    const auto w = make_alignment_world(o, 3, s);
    CHECK(w.field.dim == 3);
    CHECK(w.field.per_component == o.bumps);
    CHECK(w.field.cx.size() == 3u * o.bumps);
    for (int k = 0; k < 3; ++k) {
      double m = 0, m2 = 0;
      const std::size_t na = w.ref_x.size();
      for (std::size_t i = 0; i < na; ++i) {
        m += w.ref_features[i * 3 + k];
        m2 += w.ref_features[i * 3 + k] * w.ref_features[i * 3 + k];
      }
      m /= static_cast<double>(na);
      const double rms = std::sqrt(m2 / static_cast<double>(na) - m * m);
      CHECK(rms == doctest::Approx(1.0).epsilon(0.1));  // lawn-mower sampling vs the 64×64 grid
    }
    // Neighbouring positions on a trackline differ far less than the field's spread (smooth at 1 m).
    double diff2 = 0;
    for (std::size_t i = 1; i < 61; ++i)
      for (int k = 0; k < 3; ++k) {
        const double d = w.ref_features[i * 3 + k] - w.ref_features[(i - 1) * 3 + k];
        diff2 += d * d;
      }
    CHECK(std::sqrt(diff2 / 180.0) < 0.5);
  }
}

TEST_CASE("the field skips only bumps that cannot change the sum: bit for bit the sum over every bump") {
  // exp(−x) is +0 from x = 746 (1 − 4ε) on, the bound value_into relies on to skip a far bump.
  const double from = 746.0 * (1.0 - 4.0 * 2.220446049250313e-16);
  for (int i = 0; i <= 100000; ++i) {
    const double x = from + 0.01 * i;
    REQUIRE(std::exp(-x) == 0.0);
  }
  // A fine field (σ ∈ [0.3, 1] m, 2,000 bumps per component) at positions over the square and beyond it:
  // value_into against the plain sum in the same order, compared by bits.
  AlignmentWorldOptions o;
  o.bump_sigma_min = 0.3;
  o.bump_sigma_max = 1.0;
  o.bumps = 2000;
  int far_bumps = 0, tiny_bumps = 0;
  for (int s = 0; s < 3; ++s) {
    const auto w = make_alignment_world(o, 17, s);
    const FeatureField& f = w.field;
    std::vector<double> got(3);
    for (int i = 0; i < 400; ++i) {
      const double x = -40.0 + 0.2 * i, y = -35.0 + 0.17 * i + 7.0 * std::sin(0.1 * i);
      f.value_into(x, y, got.data());
      for (int k = 0; k < f.dim; ++k) {
        double v = f.offset;
        for (int b = k * f.per_component; b < (k + 1) * f.per_component; ++b) {
          const double dx = x - f.cx[b], dy = y - f.cy[b];
          const double e = (dx * dx + dy * dy) / (2.0 * f.sigma[b] * f.sigma[b]);
          far_bumps += e > 746.0 ? 1 : 0;
          tiny_bumps += e > 60.0 && e <= 746.0 ? 1 : 0;  // a nonzero term below 1e−26: skipped against v
          v += f.amplitude[b] * std::exp(-e);
        }
        REQUIRE(std::bit_cast<std::uint64_t>(got[k]) == std::bit_cast<std::uint64_t>(v));
      }
    }
  }
  CHECK(far_bumps > 3 * 400 * 3 * 2000 / 2);    // most bumps underflow: the test exercises that skip
  CHECK(tiny_bumps > 3 * 400 * 3 * 2000 / 10);  // and many more add less than an ulp of the sum
}

TEST_CASE("the field's skip against the sum is exact for amplitudes, offsets and sums of any magnitude") {
  // Adversarial fields: amplitudes from 1e−200 to 1e200 of either sign (and zero), offsets that make the sum
  // zero, subnormal, huge or negative, σ over four decades; value_into against the plain loop by bits.
  keel::core::Rng rng(20261207);
  const double offsets[] = {0.0, 4e-320, -3.5, 1e30, -1e-300, 0.25};
  int terms = 0;
  for (int trial = 0; trial < 60; ++trial) {
    FeatureField f;
    f.dim = 2;
    f.per_component = 1 + static_cast<int>(rng.uniform() * 300);
    f.offset = offsets[trial % 6];
    for (int b = 0; b < f.dim * f.per_component; ++b) {
      f.cx.push_back(rng.uniform(-30.0, 30.0));
      f.cy.push_back(rng.uniform(-30.0, 30.0));
      f.sigma.push_back(std::pow(10.0, rng.uniform(-2.0, 2.0)));
      const double a = std::pow(10.0, rng.uniform(-200.0, 200.0));
      f.amplitude.push_back(rng.uniform() < 0.05 ? 0.0 : rng.uniform() < 0.5 ? -a : a);
    }
    std::vector<double> got(2);
    for (int i = 0; i < 50; ++i) {
      const double x = rng.uniform(-40.0, 40.0), y = rng.uniform(-40.0, 40.0);
      f.value_into(x, y, got.data());
      for (int k = 0; k < f.dim; ++k) {
        double v = f.offset;
        for (int b = k * f.per_component; b < (k + 1) * f.per_component; ++b) {
          const double dx = x - f.cx[b], dy = y - f.cy[b];
          v += f.amplitude[b] * std::exp(-(dx * dx + dy * dy) / (2.0 * f.sigma[b] * f.sigma[b]));
          ++terms;
        }
        REQUIRE(std::bit_cast<std::uint64_t>(got[k]) == std::bit_cast<std::uint64_t>(v));
      }
    }
  }
  CHECK(terms > 100000);
}

TEST_CASE("position noise: N(0, position_noise²) per coordinate on both trajectories") {
  AlignmentWorldOptions o;
  o.position_noise = 0.4;
  double s2 = 0;
  long long n = 0;
  for (int s = 0; s < 10; ++s) {
    const auto w = make_alignment_world(o, 9, s);
    const double half = 0.5 * o.reference_size;
    const auto l =
        lawn_mower(-half, -half, o.reference_size, o.reference_size, o.track_spacing, o.sample_spacing);
    for (std::size_t i = 0; i < l.x.size(); ++i) {
      s2 += (w.ref_x[i] - l.x[i]) * (w.ref_x[i] - l.x[i]) + (w.ref_y[i] - l.y[i]) * (w.ref_y[i] - l.y[i]);
      n += 2;
    }
    // The query's noise, seen in the reference frame, is isotropic with the same std.
    const double c = std::cos(w.theta), sn = std::sin(w.theta);
    for (std::size_t j = 0; j < w.query_x.size(); ++j) {
      const double ex = c * w.query_x[j] - sn * w.query_y[j] + w.tx - w.query_true_x[j];
      const double ey = sn * w.query_x[j] + c * w.query_y[j] + w.ty - w.query_true_y[j];
      s2 += ex * ex + ey * ey;
      n += 2;
    }
  }
  CHECK(std::sqrt(s2 / n) == doctest::Approx(0.4).epsilon(0.02));
}

TEST_CASE("AlignmentWorldOptions::validate names the field and the value") {
  AlignmentWorldOptions o;
  CHECK(message_of([&] { o.validate(); }) == keel::testkit::kNoThrow);
  auto msg = [](auto edit) {
    AlignmentWorldOptions p;
    edit(p);
    return message_of([&] { (void)make_alignment_world(p, 1, 1); });
  };
  CHECK(contains(msg([](auto& p) { p.reference_size = 0; }), "AlignmentWorldOptions.reference_size = 0"));
  CHECK(contains(msg([](auto& p) { p.query_size = 70; }), "AlignmentWorldOptions.query_size = 70"));
  CHECK(contains(msg([](auto& p) { p.track_spacing = -1; }), "AlignmentWorldOptions.track_spacing = -1"));
  CHECK(contains(msg([](auto& p) { p.sample_spacing = NAN; }), "AlignmentWorldOptions.sample_spacing"));
  CHECK(contains(msg([](auto& p) { p.feature_dim = 0; }), "AlignmentWorldOptions.feature_dim = 0"));
  CHECK(contains(msg([](auto& p) { p.bumps = 0; }), "AlignmentWorldOptions.bumps = 0"));
  CHECK(contains(msg([](auto& p) { p.bump_sigma_min = 0; }), "AlignmentWorldOptions.bump_sigma_min"));
  CHECK(contains(msg([](auto& p) { p.bump_sigma_max = 2; }), "AlignmentWorldOptions.bump_sigma_max = 2"));
  CHECK(contains(msg([](auto& p) { p.feature_noise = -0.1; }), "AlignmentWorldOptions.feature_noise"));
  CHECK(contains(msg([](auto& p) { p.position_noise = INFINITY; }), "AlignmentWorldOptions.position_noise"));
  CHECK(contains(msg([](auto& p) { p.max_translation = -1; }), "AlignmentWorldOptions.max_translation"));
  CHECK(contains(msg([](auto& p) { p.max_rotation = 4; }), "AlignmentWorldOptions.max_rotation = 4"));
}
