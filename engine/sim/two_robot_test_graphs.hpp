// Test-only synthetic pose graphs for the two-robot scenarios (scenario_test.cpp, merge_test.cpp): a robot
// drives `laps` laps of 40 poses around a 10 m × 10 m square (3D: climbing 0.02 m per step with a small roll
// wobble) and closes a loop (i, i + 40) at every `closure_stride`-th pose. Measurements follow
// graph/pose_graph.hpp: z ≈ T_i⁻¹ T_j with residual r = ρ(z⁻¹ T_i⁻¹ T_j) and information Ω; a noisy
// measurement is z = z̄ ρ⁻¹(r)⁻¹ with r ~ N(0, Ω⁻¹), so its residual at the ground truth is exactly r (the
// same noise model as the scenario's aliased outliers).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/random.hpp"
#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "sim/two_robot.hpp"

namespace keel::sim::testing {

template <class G>
struct SyntheticGraph {
  graph::PoseGraphOf<G> graph;
  std::vector<G> truth;
};

inline lie::SE2 lap_step(int i, const lie::SE2*) {
  return lie::SE2(1.0, 0.0, i % 10 == 9 ? lie::kPi / 2 : 0.0);
}
inline lie::SE3 lap_step(int i, const lie::SE3*) {
  const double yaw = i % 10 == 9 ? lie::kPi / 2 : 0.0, roll = 0.03 * std::sin(0.7 * i);
  return lie::SE3(lie::SO3::exp(lie::Vec3(0, 0, yaw)) * lie::SO3::exp(lie::Vec3(roll, 0, 0)),
                  lie::Vec3(1.0, 0.0, 0.02));
}

inline lie::SE2 pose_from_residual(const lie::Vec3& r) { return lie::SE2(r(0), r(1), r(2)); }
inline lie::SE3 pose_from_residual(const lie::Vec6& r) {
  return lie::SE3(lie::SO3::exp(lie::Vec3(r.tail<3>())), lie::Vec3(r.head<3>()));
}

// Residual standard deviations: odometry 0.02 m / 0.002 rad, loop closures 0.1 m / 0.01 rad (precise odometry
// keeps the local maps close to the truth, so the anchor error of a merge is dominated by the closures).
template <class G>
typename G::Tangent residual_sigmas(bool odometry) {
  typename G::Tangent s;
  constexpr int kT = G::Point::RowsAtCompileTime;
  for (int k = 0; k < G::DoF; ++k) s(k) = k < kT ? (odometry ? 0.02 : 0.1) : (odometry ? 0.002 : 0.01);
  return s;
}

template <class G>
SyntheticGraph<G> square_laps(int laps, int closure_stride, std::uint64_t seed, bool noisy = true,
                              bool with_poses = false) {
  using J = typename G::Jacobian;
  using T = typename G::Tangent;
  const int n = 40 * laps;
  SyntheticGraph<G> out;
  out.truth.push_back(G());
  for (int i = 0; i + 1 < n; ++i)
    out.truth.push_back(out.truth.back() * lap_step(i, static_cast<const G*>(nullptr)));
  const T sigma_odo = residual_sigmas<G>(true), sigma_loop = residual_sigmas<G>(false);
  const J info_odo = sigma_odo.cwiseInverse().cwiseAbs2().asDiagonal();
  const J info_loop = sigma_loop.cwiseInverse().cwiseAbs2().asDiagonal();
  auto rng = core::Rng::stream(seed, 0);
  // z = z̄ ρ⁻¹(r)⁻¹, r ~ N(0, Ω⁻¹): the residual ρ(z⁻¹ z̄) at the ground truth is r.
  auto measure = [&](int i, int j, const T& sigma) {
    const G z_bar = out.truth[i].inverse() * out.truth[j];
    T r;
    for (int k = 0; k < G::DoF; ++k) r(k) = noisy ? sigma(k) * rng.normal() : 0.0;
    return z_bar * pose_from_residual(r).inverse();
  };
  for (int i = 0; i + 1 < n; ++i)
    out.graph.edges.push_back({i, i + 1, measure(i, i + 1, sigma_odo), info_odo, 0});
  for (int i = 0; i + 40 < n; i += closure_stride)
    out.graph.edges.push_back({i, i + 40, measure(i, i + 40, sigma_loop), info_loop, 0});
  if (with_poses) {
    out.graph.poses = out.truth;
    out.graph.has_initial_poses = true;
  }
  out.graph.source = "square_laps";
  return out;
}

// A small candidate set for the square-laps scenarios: 10 inliers, 2 aliased groups of 5, 30 random outliers
// with covariances up to 10 % of the 10 m map (the defaults reach 10 m, the whole map here).
inline CandidateOptions small_candidate_options() {
  CandidateOptions o;
  o.num_inliers = 10;
  o.aliased_groups = 2;
  o.aliased_group_size = 5;
  o.random_outliers = 30;
  o.random_sigma_translation_max = 1.0;
  o.random_sigma_rotation_max = 0.1;
  return o;
}

}  // namespace keel::sim::testing
