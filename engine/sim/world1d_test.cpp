// The 1D world of §2.7.1: deterministic generation, the distributions it draws from, and its Q (the 1D case
// of eq. 2.4).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "kit/test_kit.hpp"
#include "pcm/consistency.hpp"
#include "sim/world1d.hpp"

using namespace keel::sim;
using keel::pcm::consistency_threshold;
using keel::pcm::ConsistencyMatrix;
using keel::testkit::contains;
using keel::testkit::message_of;

TEST_CASE("world generation is deterministic per (seed, index) and respects the counts") {
  World1DOptions o;
  const auto a = generate_world1d(o, 42, 7), b = generate_world1d(o, 42, 7), c = generate_world1d(o, 42, 8);
  CHECK(a.z == b.z);
  CHECK(a.sigma == b.sigma);
  CHECK(a.labels == b.labels);
  CHECK(a.z != c.z);
  for (int i = 0; i < 500; ++i) {
    const auto w = generate_world1d(o, 1, i);
    const int ni = w.count(MeasurementLabel::inlier), na = w.count(MeasurementLabel::aliased),
              nr = w.count(MeasurementLabel::random);
    REQUIRE(w.size() == ni + na + nr);
    CHECK(ni >= o.inliers_min);
    CHECK(ni <= o.inliers_max);
    CHECK(na >= o.aliased_min);
    CHECK(na <= o.aliased_max);
    CHECK(nr >= o.random_min);
    CHECK(nr <= o.random_max);
    CHECK(w.sigma.size() == w.z.size());
    for (int u = 0; u < w.size(); ++u) {
      if (w.labels[u] == MeasurementLabel::inlier) CHECK(w.sigma[u] == o.sigma_inlier);
      if (w.labels[u] == MeasurementLabel::aliased) CHECK(w.sigma[u] == w.aliased_sigma);
      if (w.labels[u] != MeasurementLabel::inlier) {
        CHECK(w.sigma[u] >= o.outlier_sigma_min);
        CHECK(w.sigma[u] <= o.outlier_sigma_max);
      }
    }
    CHECK(std::fabs(w.aliased_mean - o.x) <= o.outlier_mean_range);
  }
  // Without shuffling the groups come in order.
  o.shuffle = false;
  const auto w = generate_world1d(o, 3, 3);
  CHECK(std::is_sorted(w.labels.begin(), w.labels.end()));
}

TEST_CASE("inliers are N(x, σ_in²); an aliased group shares one Gaussian") {
  World1DOptions o;
  o.x = 3.5;
  o.sigma_inlier = 0.7;
  double s = 0, ss = 0, al = 0, al2 = 0;
  long long n = 0, m = 0;
  for (int i = 0; i < 4000; ++i) {
    const auto w = generate_world1d(o, 99, i);
    for (int u = 0; u < w.size(); ++u) {
      if (w.labels[u] == MeasurementLabel::inlier) {
        s += w.z[u] - o.x;
        ss += (w.z[u] - o.x) * (w.z[u] - o.x);
        ++n;
      } else if (w.labels[u] == MeasurementLabel::aliased) {
        const double t = (w.z[u] - w.aliased_mean) / w.aliased_sigma;  // standardised within its group
        al += t;
        al2 += t * t;
        ++m;
      }
    }
  }
  CHECK(std::fabs(s / n) < 4.0 * o.sigma_inlier / std::sqrt(static_cast<double>(n)));
  CHECK(std::sqrt(ss / n) == doctest::Approx(o.sigma_inlier).epsilon(0.02));
  CHECK(std::fabs(al / m) < 4.0 / std::sqrt(static_cast<double>(m)));
  CHECK(al2 / m == doctest::Approx(1.0).epsilon(0.03));
}

TEST_CASE("Q of a world: q_uv = (z_u − z_v)² / (σ_u² + σ_v²), dof 1") {
  World1D w;
  w.z = {0.0, 1.0, 4.0};
  w.sigma = {1.0, 2.0, 0.5};
  w.labels.assign(3, MeasurementLabel::random);
  const auto Q = world1d_consistency_matrix(w);
  CHECK(Q.n == 3);
  CHECK(Q.dof == 1);
  CHECK(Q.at(0, 1) == doctest::Approx(1.0 / 5.0));
  CHECK(Q.at(1, 2) == doctest::Approx(9.0 / 4.25));
  CHECK(Q.at(2, 0) == doctest::Approx(16.0 / 1.25));
  for (int u = 0; u < 3; ++u) {
    CHECK(Q.at(u, u) == 0.0);
    for (int v = 0; v < 3; ++v) CHECK(Q.at(u, v) == Q.at(v, u));
  }
  World1D bad = w;
  bad.sigma[1] = 0.0;
  CHECK(contains(message_of([&] { (void)world1d_consistency_matrix(bad); }), "standard deviation"));
  bad = w;
  bad.sigma.pop_back();
  CHECK(contains(message_of([&] { (void)world1d_consistency_matrix(bad); }), "3 measurements but 2"));
  CHECK(contains(message_of([&] { (void)world1d_consistency_matrix(World1D{}); }), "no measurements"));
}

TEST_CASE("inlier pairs follow χ²(1): the share consistent at γ(p) is 1 − p") {
  World1DOptions o;
  const double p = 0.11, gamma = consistency_threshold(p, 1);
  long long pairs = 0, consistent = 0;
  for (int i = 0; i < 3000; ++i) {
    const auto w = generate_world1d(o, 5, i);
    const auto Q = world1d_consistency_matrix(w);
    for (int u = 0; u < w.size(); ++u)
      for (int v = u + 1; v < w.size(); ++v)
        if (w.labels[u] == MeasurementLabel::inlier && w.labels[v] == MeasurementLabel::inlier) {
          ++pairs;
          consistent += Q.at(u, v) <= gamma;
        }
  }
  CHECK(static_cast<double>(consistent) / pairs == doctest::Approx(1.0 - p).epsilon(0.01));
}

TEST_CASE("World1DOptions validation and fixed-size options") {
  World1DOptions o;
  CHECK_NOTHROW(o.validate());
  o.sigma_inlier = 0.0;
  CHECK(contains(message_of([&] { o.validate(); }), "sigma_inlier"));
  o = {};
  o.aliased_min = 5;
  o.aliased_max = 4;
  CHECK(contains(message_of([&] { o.validate(); }), "aliased_min/_max"));
  o = {};
  o.inliers_min = o.inliers_max = o.aliased_min = o.aliased_max = o.random_min = o.random_max = 0;
  CHECK(contains(message_of([&] { o.validate(); }), "at least one measurement"));
  o = {};
  o.outlier_sigma_min = 2.0;
  o.outlier_sigma_max = 1.0;
  CHECK(contains(message_of([&] { o.validate(); }), "outlier_sigma"));
  o = {};
  o.outlier_mean_range = -1.0;
  CHECK(contains(message_of([&] { o.validate(); }), "outlier_mean_range"));

  const auto f = world1d_options_with_total(World1DOptions{}, 37, 0.5, 0.25);
  CHECK(f.inliers_min == 19);  // lround(18.5)
  CHECK(f.inliers_max == 19);
  CHECK(f.aliased_min == 9);
  CHECK(f.random_min == 9);
  for (int i = 0; i < 20; ++i) CHECK(generate_world1d(f, 1, i).size() == 37);
  CHECK(
      contains(message_of([] { (void)world1d_options_with_total(World1DOptions{}, 0, 0.5, 0.2); }), "total"));
  CHECK(contains(message_of([] { (void)world1d_options_with_total(World1DOptions{}, 10, 0.8, 0.3); }),
                 "fractions"));
  CHECK(to_string(MeasurementLabel::aliased) == "aliased");
}
