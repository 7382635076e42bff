// ATE and RPE (graph/trajectory_error.hpp): zero for a rigidly moved copy, the closed-form alignment no worse
// than a brute-force search over planar rotations, RPE of a known displacement, and bad inputs.
#include <doctest/doctest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "core/random.hpp"
#include "graph/trajectory_error.hpp"
#include "kit/test_kit.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/so3.hpp"

using namespace keel;
using graph::SE2;
using graph::SE3;

namespace {

std::vector<SE2> random_walk_2d(core::Rng& rng, int n) {
  std::vector<SE2> p{SE2()};
  for (int k = 1; k < n; ++k)
    p.push_back(p.back() * SE2(rng.uniform(0.5, 1.5), rng.uniform(-0.3, 0.3), rng.uniform(-0.5, 0.5)));
  return p;
}

std::vector<SE3> random_walk_3d(core::Rng& rng, int n) {
  std::vector<SE3> p{SE3()};
  for (int k = 1; k < n; ++k) {
    const lie::Vec3 w(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
    const lie::Vec3 t(rng.uniform(0.5, 1.5), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
    p.push_back(p.back() * SE3(lie::SO3::exp(w), t));
  }
  return p;
}

std::vector<std::pair<int, int>> consecutive_pairs(int n) {
  std::vector<std::pair<int, int>> out;
  for (int k = 0; k + 1 < n; ++k) out.emplace_back(k, k + 1);
  return out;
}

}  // namespace

TEST_CASE("ATE and RPE are zero for a rigidly moved copy, 2D and 3D") {
  core::Rng rng = core::Rng::stream(7, 0);
  const auto a = random_walk_2d(rng, 40);
  const SE2 M(3.0, -2.0, 2.1);
  std::vector<SE2> moved;
  for (const auto& T : a) moved.push_back(M * T);
  CHECK(graph::absolute_trajectory_error(a, moved) < 1e-12);
  CHECK(graph::relative_pose_error(a, moved, consecutive_pairs(40)) < 1e-12);

  const auto b = random_walk_3d(rng, 40);
  const SE3 N(lie::SO3::exp(lie::Vec3(0.4, -1.2, 2.5)), lie::Vec3(1.0, 2.0, -3.0));
  std::vector<SE3> moved3;
  for (const auto& T : b) moved3.push_back(N * T);
  CHECK(graph::absolute_trajectory_error(b, moved3) < 1e-11);
  CHECK(graph::relative_pose_error(b, moved3, consecutive_pairs(40)) < 1e-11);
}

TEST_CASE("ATE's closed-form alignment is no worse than a brute-force search over planar rotations") {
  core::Rng rng = core::Rng::stream(7, 1);
  for (int trial = 0; trial < 5; ++trial) {
    const auto ref = random_walk_2d(rng, 30);
    std::vector<SE2> est;
    for (const auto& T : ref)
      est.push_back(SE2(rng.uniform(-4, 4), rng.uniform(-4, 4), 0.7) * T *
                    SE2(rng.normal() * 0.3, rng.normal() * 0.3, 0.0));
    const double ate = graph::absolute_trajectory_error(ref, est);
    // For a rotation θ the best translation matches the centroids; search θ on a fine grid.
    double best = 1e300;
    for (int s = 0; s < 36000; ++s) {
      const double th = 2 * lie::kPi * s / 36000.0;
      const lie::Mat2 R = lie::SO2(th).matrix();
      lie::Vec2 mr = lie::Vec2::Zero(), me = lie::Vec2::Zero();
      for (std::size_t k = 0; k < ref.size(); ++k) mr += ref[k].translation(), me += est[k].translation();
      mr /= 30.0, me /= 30.0;
      double sum = 0;
      for (std::size_t k = 0; k < ref.size(); ++k)
        sum += (ref[k].translation() - mr - R * (est[k].translation() - me)).squaredNorm();
      best = std::min(best, std::sqrt(sum / 30.0));
    }
    CHECK(ate <= best + 1e-12);
    CHECK(ate >= best - 1e-3);  // the grid's resolution
  }
}

TEST_CASE("RPE of one displaced pose, and bad inputs") {
  std::vector<SE2> ref;
  for (int k = 0; k < 11; ++k) ref.push_back(SE2(k, 0.0, 0.0));
  auto est = ref;
  est[5] = SE2(5.0, 0.3, 0.0);  // moved 0.3 m sideways: pairs (4, 5) and (5, 6) each see 0.3 m
  CHECK(graph::relative_pose_error(ref, est, consecutive_pairs(11)) ==
        doctest::Approx(std::sqrt(2 * 0.09 / 10)).epsilon(1e-12));
  CHECK(graph::absolute_trajectory_error(ref, est) > 0.0);

  using testkit::contains;
  using testkit::message_of;
  const std::vector<SE2> shorter(ref.begin(), ref.begin() + 3);
  CHECK(contains(message_of([&] { (void)graph::absolute_trajectory_error(ref, shorter); }),
                 "11 reference poses but 3 estimated"));
  CHECK(contains(message_of([&] { (void)graph::absolute_trajectory_error(std::vector<SE2>{}, {}); }),
                 "no pose"));
  CHECK(contains(message_of([&] { (void)graph::relative_pose_error(ref, est, {{0, 11}}); }),
                 "pair (0, 11) names a pose out of 0 … 10"));
  CHECK(contains(message_of([&] { (void)graph::relative_pose_error(ref, est, {}); }), "no pair"));
}
