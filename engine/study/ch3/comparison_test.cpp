// Unit tests of the chapter-3 machinery (comparison.hpp): the standardised known-depth problem of the hull
// substitute (§3.8) and the comparison over hull worlds.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "study/ch3/comparison.hpp"
#include "study/ch3/regime_grid.hpp"
#include "study/ch3/sensitivity.hpp"
#include "kit/test_kit.hpp"
#include "sim/hull_world.hpp"

using namespace keel::align;
using namespace keel::study::ch3;
using keel::core::Streams;
using keel::repro::RunContext;
using keel::sim::HullWorld;
using keel::sim::HullWorldOptions;

namespace {

// Three reference points and two query points with hand-picked features (dimension 3).
HullWorld tiny_world() {
  HullWorld w;
  w.ref_x = {0, 4, 0}, w.ref_y = {0, 0, 3}, w.ref_z = {5, 5.2, 5.1};
  w.query_x = {1, 2}, w.query_y = {1, 0.5}, w.query_z = {5.05, 5.15};
  // component 0 spread 0.02 (κ-like), component 1 spread 0.1, component 2 spread 0.4 (slope-like)
  w.ref_features = {-0.02, -0.1, 0.0,  //
                    0.0,   0.0,  0.4,  //
                    0.02,  0.1,  0.8};
  w.query_features = {0.01,  -0.05, 0.2,  //
                      -0.01, 0.05,  0.6};
  return w;
}

double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  REQUIRE(a.size() == b.size());
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    worst = std::max(worst, std::abs(a[k] - b[k]) / std::max(1.0, std::abs(b[k])));
  return worst;
}

}  // namespace

TEST_CASE("reference_feature_scales is the population std of each component over the reference") {
  const HullWorld w = tiny_world();
  const auto s = reference_feature_scales(w);
  REQUIRE(s.size() == 3);
  // values {-a, 0, a}: population std = a·√(2/3)
  CHECK(s[0] == doctest::Approx(0.02 * std::sqrt(2.0 / 3.0)).epsilon(1e-12));
  CHECK(s[1] == doctest::Approx(0.1 * std::sqrt(2.0 / 3.0)).epsilon(1e-12));
  CHECK(s[2] == doctest::Approx(0.4 * std::sqrt(2.0 / 3.0)).epsilon(1e-12));
}

TEST_CASE("standardized_problem_of divides every component by the reference's std, both surveys") {
  const HullWorld w = tiny_world();
  const AlignmentProblem p = standardized_problem_of(w);
  CHECK(p.ref_x == w.ref_x);
  CHECK(p.ref_y == w.ref_y);
  CHECK(p.ref_z == w.ref_z);
  CHECK(p.query_x == w.query_x);
  CHECK(p.query_y == w.query_y);
  CHECK(p.query_z == w.query_z);
  REQUIRE(p.dissimilarity.size() == 3 * 2);
  const auto s = reference_feature_scales(w);
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 2; ++j) {
      double d2 = 0;
      for (std::size_t k = 0; k < 3; ++k) {
        const double e = (w.ref_features[i * 3 + k] - w.query_features[j * 3 + k]) / s[k];
        d2 += e * e;
      }
      CHECK(p.c(i, j) == doctest::Approx(std::sqrt(d2)).epsilon(1e-12));
    }
  // Unscaled, the slope-like component dominates; standardised, the differences (0.03, 0.05, 0.2) become
  // (1.5, 0.5, 0.5) / √(2/3): the curvature-like component now counts most.
  const AlignmentProblem raw = problem_of(w);
  CHECK(raw.c(0, 0) == doctest::Approx(std::sqrt(0.03 * 0.03 + 0.05 * 0.05 + 0.2 * 0.2)).epsilon(1e-12));
  CHECK(p.c(0, 0) == doctest::Approx(std::sqrt((2.25 + 0.25 + 0.25) * 1.5)).epsilon(1e-12));
}

TEST_CASE("standardisation is invariant to the units of each component and keeps zero-spread components") {
  const HullWorld w = keel::sim::make_hull_world(HullWorldOptions{}, 3, 1);
  const AlignmentProblem p = standardized_problem_of(w);
  const AlignmentProblem raw = problem_of(w);
  CHECK(p.ref_z == raw.ref_z);
  CHECK(p.query_z == raw.query_z);
  // Rescaling one component of both surveys (e.g. curvature in 1/cm instead of 1/m) changes nothing.
  HullWorld scaled = w;
  for (std::size_t n = 0; n < scaled.ref_features.size(); n += 3) scaled.ref_features[n + 1] *= 0.01;
  for (std::size_t n = 0; n < scaled.query_features.size(); n += 3) scaled.query_features[n + 1] *= 0.01;
  CHECK(relative_difference(standardized_problem_of(scaled).dissimilarity, p.dissimilarity) < 1e-12);
  // The standardised reference features have unit spread.
  for (double s : reference_feature_scales(w)) CHECK(s > 0);

  // A component constant over the reference is left unscaled (no division by zero).
  HullWorld flat = tiny_world();
  for (std::size_t i = 0; i < 3; ++i) flat.ref_features[i * 3] = 0.5;
  const auto s = reference_feature_scales(flat);
  CHECK(s[0] == 0.0);
  const AlignmentProblem q = standardized_problem_of(flat);
  const double e0 = 0.5 - flat.query_features[0], e1 = (-0.1 - -0.05) / s[1], e2 = (0.0 - 0.2) / s[2];
  CHECK(q.c(0, 0) == doctest::Approx(std::sqrt(e0 * e0 + e1 * e1 + e2 * e2)).epsilon(1e-12));
  for (double v : q.dissimilarity) CHECK(std::isfinite(v));
}

TEST_CASE("standardized_problem_of rejects features that do not match the positions") {
  HullWorld w = tiny_world();
  w.query_features.pop_back();
  CHECK_THROWS_AS((void)standardized_problem_of(w), std::invalid_argument);
  HullWorld empty;
  CHECK_THROWS_AS((void)reference_feature_scales(empty), std::invalid_argument);
}

TEST_CASE("run_hull_study scores every method on every world, independent of threads") {
  HullStudyOptions o;
  o.compare.methods = {Method::proposed, Method::affine};
  o.compare.align.depth_gate = 1.0;
  o.compare.align.region.max_rounds = 2;
  o.worlds = 2;
  const HullStudyOutcome a = run_hull_study(o, RunContext(Streams(11), 1));
  const HullStudyOutcome b = run_hull_study(o, RunContext(Streams(11), 2));
  REQUIRE(a.outcomes.size() == 2);
  for (std::size_t m = 0; m < 2; ++m) {
    REQUIRE(a.outcomes[m].size() == 2);
    for (std::size_t w = 0; w < 2; ++w) {
      CHECK(a.outcomes[m][w].rot_se == b.outcomes[m][w].rot_se);
      CHECK(a.outcomes[m][w].trans_se == b.outcomes[m][w].trans_se);
      CHECK(std::isfinite(a.outcomes[m][w].cost));
      CHECK(a.outcomes[m][w].rounds >= 1);
    }
  }
  // World w is make_hull_world(seed, w), scored as score_alignment scores align's answer.
  const HullWorld w1 = keel::sim::make_hull_world(o.world, 11, 1);
  CHECK(a.world_theta[1] == w1.theta);
  CHECK(a.query_points[1] == w1.query_x.size());
  AlignOptions ao = o.compare.align;
  const AlignmentProblem p = standardized_problem_of(w1);
  const MethodOutcome direct =
      score_alignment(p, align(p, ao), w1.theta, w1.tx, w1.ty, o.compare.valid_tolerance);
  CHECK(direct.rot_se == a.outcomes[0][1].rot_se);
  CHECK(direct.trans_se == a.outcomes[0][1].trans_se);
  // Every round is scored, and the last round's estimate is the final answer.
  REQUIRE(direct.round_scores.size() == static_cast<std::size_t>(direct.rounds));
  CHECK(direct.round_scores.back().rot_se == direct.rot_se);
  CHECK(direct.round_scores.back().trans_se == direct.trans_se);
  CHECK(direct.round_scores.front().half_width > direct.round_scores.back().half_width);
  CHECK(a.outcomes[0][1].round_scores.size() == direct.round_scores.size());  // carried through the archive

  o.worlds = 0;
  CHECK_THROWS_AS((void)run_hull_study(o, RunContext(Streams(11))), std::invalid_argument);
  CHECK(keel::testkit::contains(
      keel::testkit::message_of([&] { (void)run_hull_study(o, RunContext(Streams(11))); }),
      "HullStudyOptions.worlds"));
}

TEST_CASE("score_estimate: the primary errors and their variants on known transforms") {
  AlignmentProblem p;
  p.query_x = {10, 12, 14}, p.query_y = {20, 20, 23};  // centroid (12, 21)
  const double theta = 0.3, tx = 5, ty = -2;
  // The truth itself: every error 0, radius 1, valid.
  Transform2 t{std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta), tx, ty};
  EstimateScore e = score_estimate(p, t, theta, tx, ty, 0.05);
  CHECK(e.rot_se == doctest::Approx(0).scale(1));
  CHECK(e.trans_se == doctest::Approx(0).scale(1));
  CHECK(e.trans_se_origin == doctest::Approx(0).scale(1));
  CHECK(e.radius == doctest::Approx(1));
  CHECK(e.valid);
  // A rotation error δ about the centroid: rotation SE δ² both ways, no translation error at the centroid,
  // and at the origin the lever arm |R(θ + δ) p̄ − R(θ) p̄|² = 4 sin²(δ/2) |p̄|².
  const double d = 0.01, cx = 12, cy = 21;
  const double c = std::cos(theta + d), s = std::sin(theta + d);
  const double gx = std::cos(theta) * cx - std::sin(theta) * cy + tx,
               gy = std::sin(theta) * cx + std::cos(theta) * cy + ty;
  Transform2 r{c, -s, s, c, gx - (c * cx - s * cy), gy - (s * cx + c * cy)};
  e = score_estimate(p, r, theta, tx, ty, 0.05);
  CHECK(e.rot_error == doctest::Approx(d));
  CHECK(e.rot_se == doctest::Approx(d * d));
  CHECK(e.rot_se_atan2 == doctest::Approx(d * d));
  CHECK(e.trans_se == doctest::Approx(0).scale(1));
  CHECK(e.trans_se_origin == doctest::Approx(4 * std::sin(d / 2) * std::sin(d / 2) * (cx * cx + cy * cy)));
  // A scaled rotation (the octagon's edge midpoint radius): the polar angle is the rotation's, the radius the
  // scale, and it is valid at a tolerance above 4 % but not at 1 %.
  const double k = 0.9619;
  Transform2 sc{k * std::cos(theta), -k * std::sin(theta), k * std::sin(theta), k * std::cos(theta), tx, ty};
  e = score_estimate(p, sc, theta, tx, ty, 0.05);
  CHECK(e.radius == doctest::Approx(k));
  CHECK(e.rot_se == doctest::Approx(0).scale(1));
  CHECK(e.valid);
  CHECK_FALSE(score_estimate(p, sc, theta, tx, ty, 0.01).valid);
  // A shear: atan2(a21, a11) and the polar projection disagree.
  Transform2 sh{1, 0.3, 0, 1, tx, ty};
  e = score_estimate(p, sh, 0.0, tx, ty, 0.05);
  CHECK(e.rot_se_atan2 == doctest::Approx(0).scale(1));
  CHECK(e.rot_se > 1e-3);
}

TEST_CASE("sensitivity: the length-scale sweep keeps the field's coverage and shares the base point") {
  keel::study::ch3::Sensitivity::Options o;
  o.study.world.bumps = 40, o.study.world.bump_sigma_min = 3, o.study.world.bump_sigma_max = 8;
  o.study.world.feature_noise = 0.3, o.study.world.query_size = 24;
  o.noises = {0.1, 0.3}, o.sizes = {12, 24}, o.scales = {{0.5, 1.0}, {3.0, 8.0}};
  const auto points = o.axis(2);
  REQUIRE(points.size() == 2);
  CHECK(points[0].noise == 0.3);
  CHECK(points[0].size == 24);
  // E[σ²] of U[3, 8] is 97/3, of U[0.5, 1] 1.75/3: 40 · 97 / 1.75 = 2217.1 bumps.
  const keel::sim::AlignmentWorldOptions fine = o.world_at(points[0]);
  CHECK(fine.bumps == 2217);
  CHECK(fine.bump_sigma_min == 0.5);
  CHECK(fine.bump_sigma_max == 1.0);
  // The base range is the base world itself: the same point as the other sweeps' base.
  CHECK(o.world_at(points[1]).bumps == 40);
  CHECK_FALSE(points[1] < o.axis(0)[1]);
  CHECK_FALSE(o.axis(0)[1] < points[1]);
  CHECK(o.axis(1)[0].size == 12);
}

namespace {
// ch3_table3_1_regimes' [params] as a run reads them (a profile's `worlds` merged in), with the line of
// `replacement`'s key replaced by it (empty: as committed).
keel::core::ConfigTable regime_params(const std::string& replacement = "") {
  const std::filesystem::path source =
      std::filesystem::path(KEEL_SOURCE_DIR) / "experiments/ch3_table3_1_regimes/experiment.toml";
  std::ifstream in(source);
  std::stringstream text;
  const std::string key = replacement.substr(0, replacement.find(' '));
  for (std::string l; std::getline(in, l);) {
    text << (!key.empty() && l.rfind(key + " ", 0) == 0 ? replacement : l) << '\n';
    if (l == "[params]") text << "worlds = 2\n";
  }
  const auto dir = std::filesystem::temp_directory_path() / "keel_regime_grid_test";
  std::filesystem::create_directories(dir);
  const auto file = dir / "experiment.toml";
  std::ofstream(file) << text.str();
  keel::core::ConfigTable p = keel::core::load_toml(file).table("params");
  std::filesystem::remove_all(dir);
  return p;
}
}  // namespace

TEST_CASE(
    "regime grid: the pre-registered grid holds the table's operating point and scales as the sweep does") {
  const keel::core::ConfigTable p = regime_params();
  const RegimeGrid::Options o = RegimeGrid::Options::read(p);
  const auto cells = o.cells();
  REQUIRE(cells.size() == o.scales.size() * o.noises.size() * o.sizes.size());
  // σ range fastest, then noise, then query size.
  CHECK(cells[0].sigma_min == o.scales[0].first);
  CHECK(cells[1].sigma_min == o.scales[1].first);
  CHECK(cells[o.scales.size()].noise == o.noises[1]);
  CHECK(cells[o.scales.size() * o.noises.size()].size == o.sizes[1]);
  // The headline operating point of ch3_table3_1_alignment is one cell, and its world is the base world
  // itself.
  const RegimeGrid::Point base{o.study.world.feature_noise, o.study.world.query_size,
                               o.study.world.bump_sigma_min, o.study.world.bump_sigma_max};
  const auto it =
      std::find_if(cells.begin(), cells.end(), [&](const auto& c) { return !(c < base) && !(base < c); });
  REQUIRE(it != cells.end());
  CHECK(o.world_at(*it).bumps == o.study.world.bumps);
  // Every cell's world is what the one-axis sweep builds for the same point.
  Sensitivity::Options s;
  s.study = o.study;
  for (const auto& c : cells) {
    const auto a = o.world_at(c), b = s.world_at(c);
    CHECK(a.bumps == b.bumps);
    CHECK(a.feature_noise == c.noise);
    CHECK(a.query_size == c.size);
    CHECK(a.bump_sigma_min == c.sigma_min);
  }
  CHECK_FALSE(o.study.compare.certify);
}

TEST_CASE("regime grid: a bad grid is refused with the key named") {
  const auto refused = [](const std::string& line, const std::string& key) {
    try {
      (void)RegimeGrid::Options::read(regime_params(line));
    } catch (const keel::core::ConfigError& e) {
      const std::string what = e.what();
      CHECK_MESSAGE(what.find(key) != std::string::npos, what);
      return true;
    }
    return false;
  };
  CHECK(refused("field_sigma_max = [1.0, 2.0, 4.0]", "field_sigma_max"));
  CHECK(refused("field_sigma_min = [2.0, 1.0, 2.0, 3.0]", "field_sigma_min"));
  CHECK(refused("noise_values = []", "noise_values"));
  CHECK(refused("query_sizes = [12.0, 80.0]", "query_sizes"));
  CHECK(refused("noise_values = [0.3, -0.1]", "noise_values"));
  CHECK_FALSE(refused("noise_values = [0.3, 0.6]", "noise_values"));
}
