// Alignment problems and checks shared by the unit tests of engine/align (test helper: not part of the
// keel.align facade): exact copies of a grid under a known rigid motion, a check on an error's message, the
// distance of two angles.
#pragma once

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "align/align.hpp"
#include "core/random.hpp"
#include "kit/test_kit.hpp"

namespace keel::align::test {

inline constexpr double kPi = 3.14159265358979323846;

// A smooth 3-component field of Gaussian bumps (distinctive enough that the dissimilarity has one zero).
struct Field {
  std::vector<double> cx, cy, sg, amp;
  explicit Field(std::uint64_t seed, double size) {
    core::Rng rng(seed);
    for (int k = 0; k < 3 * 12; ++k) {
      cx.push_back(rng.uniform(-2, size + 2));
      cy.push_back(rng.uniform(-2, size + 2));
      sg.push_back(rng.uniform(2.0, 4.0));
      amp.push_back(rng.uniform(-1, 1));
    }
  }
  void value(double x, double y, double* f) const {
    for (int d = 0; d < 3; ++d) {
      f[d] = 0;
      for (int k = d * 12; k < (d + 1) * 12; ++k)
        f[d] +=
            amp[k] * std::exp(-((x - cx[k]) * (x - cx[k]) + (y - cy[k]) * (y - cy[k])) / (2 * sg[k] * sg[k]));
    }
  }
};

// Reference: a grid of n × n points (spacing 1 m); query: a copy of the reference seen through the inverse of
// (theta, tx, ty), so align must return (theta, tx, ty).
// With margin > 0 the query copies only the reference points at least `margin` from the grid's edge.
inline AlignmentProblem exact_copy(int n, double theta, double tx, double ty, std::uint64_t seed = 7,
                                   int margin = 0) {
  Field field(seed, n - 1.0);
  AlignmentProblem p;
  std::vector<double> fa;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      p.ref_x.push_back(a);
      p.ref_y.push_back(b);
      double f[3];
      field.value(a, b, f);
      fa.insert(fa.end(), f, f + 3);
    }
  const double c = std::cos(theta), s = std::sin(theta);
  std::vector<double> fb;
  for (std::size_t i = 0; i < p.ref_x.size(); ++i) {  // p_query = Rᵀ (p_ref − t)
    if (p.ref_x[i] < margin || p.ref_x[i] > n - 1 - margin || p.ref_y[i] < margin ||
        p.ref_y[i] > n - 1 - margin)
      continue;
    const double dx = p.ref_x[i] - tx, dy = p.ref_y[i] - ty;
    p.query_x.push_back(c * dx + s * dy);
    p.query_y.push_back(-s * dx + c * dy);
    fb.insert(fb.end(), fa.begin() + 3 * i, fa.begin() + 3 * i + 3);
  }
  p.dissimilarity = euclidean_dissimilarity(fa, fb, 3);
  return p;
}

// Checks that f throws a std::invalid_argument whose message contains `needle`.
template <class F>
void check_message(F&& f, const char* needle) {
  const std::string m = testkit::message_of(std::forward<F>(f));
  CHECK_MESSAGE(testkit::contains(m, needle), m);
}

inline double angle_error(double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)); }

}  // namespace keel::align::test
