// Two-robot map-merging scenarios (thesis §2.7.2, City10000 split; and a 3D substitute for §2.7.3, whose NCLT
// sessions are not available here).
//
// split_two_robots() cuts the poses [first, last) of a single-robot pose graph with ground truth at `split`
// into robot a = [first, split) and robot b = [split, last) (thesis §2.7.2: "took a portion of the City10000
// dataset ... and split it to form two separate robot trajectories"):
//   * each robot keeps its internal edges (odometry and its own loop closures), re-indexed from 0;
//   * each robot's graph and ground truth are expressed in its own frame: its first pose is the identity
//     (T^a_i = G_first⁻¹ G_{first+i}, T^b_k = G_split⁻¹ G_{split+k}, G = ground truth in the dataset's
//     frame);
//   * every factor between the two robots is removed. The dataset's own loop closures between a and b (with
//   their
//     real noise) form the POOL of true inter-robot loop closures; the single odometry edge (split−1, split)
//     that joins the two trajectories is dropped and not put in the pool (it is odometry, not a loop
//     closure);
//   * the true anchor is T_ab = G_first⁻¹ G_split, the pose of b's local frame in a's local frame, so the
//   merged
//     global frame is a's frame (robot a's anchor is the identity; pgo holds it constant).
// Candidates follow InterRobotMeasurement (consistency.hpp): z ≈ (T^a_i)⁻¹ T_ab T^b_k. A pool edge stored as
// (b → a) in the file is inverted (z⁻¹, its covariance transported by Ad(z⁻¹)).
//
// generate_candidates() makes one data set of §2.7.2 from the pool (deterministic: core::Rng::stream(seed,
// index)):
//   * `num_inliers` pool edges drawn without replacement (real measurements with real noise);
//   * `aliased_groups` groups of `aliased_group_size` mutually consistent outliers (perceptual aliasing):
//   each group
//     draws a false anchor A_g (translation uniform in the bounding box of the ground-truth positions of both
//     robots in a's frame, heading uniform in [−π, π) in 2D, rotation uniform on SO(3) in 3D), then for
//     random pose pairs (i, k) (i uniform over a's poses, k over b's) the measurement z̄ = (T^a_i)⁻¹ A_g T^b_k
//     with the ground-truth local poses, perturbed like an inlier: the residual information Ω of a pool edge
//     drawn at random, and z = z̄ ρ⁻¹(r)⁻¹ with r ~ N(0, Ω⁻¹), so that the residual ρ(z⁻¹ (T^a_i)⁻¹ A_g T^b_k)
//     of the measurement at the false alignment is exactly r (ρ as in graph/pose_graph.hpp). Each group is
//     thus a consistent set for the wrong anchor, like a true group is for the right one;
//   * `random_outliers` with random pose pairs, random means and random covariances: translation uniform in
//     [−d, d] per axis, d = the side lengths of that bounding box (the range of differences of two map
//     points), heading uniform in [−π, π) (2D) or rotation uniform on SO(3) (3D); residual information Ω =
//     diag(σ_t⁻² I, σ_r⁻² I) with σ_t log-uniform on [random_sigma_translation_min, _max] (m) and σ_r
//     log-uniform on [random_sigma_rotation_min, _max] (rad), drawn per candidate (log-uniform: the scale of
//     a random covariance is equally likely in every decade, from registration-like to map-scale
//     uncertainty).
// Every candidate carries its residual information Ω (for the merged solve) and its left-perturbation
// covariance Σ = Ad(z) Ω⁻¹ Ad(z)ᵀ (left_covariance_from_information, for the consistency metric), and a
// label. The candidates are shuffled (Fisher–Yates, same stream) unless `shuffle` is false, so that no method
// can profit from the order (the clique solvers break ties by index).
//
// 3D substitute for Table 2.2 (§2.7.3: two NCLT sessions, not available here). The same split applies to
// sphere2500 (isam/sphere2500.txt with isam/groundtruth/sphere2500_groundtruth.txt,
// read_isam_ground_truth_3d): its trajectory runs in rings of 50 poses and every loop closure joins a pose to
// the one 50 later (the ring below), so ANY split leaves exactly 50 true a–b loop closures, all between the
// two rings that meet at the split — enough for the 10 inliers of Table 2.2 without generating any (10
// inliers + 2 aliased groups of 5 + 88 random = 98 outliers). Robot a = the first half, robot b = the second
// half: two "sessions" of one sphere that meet along a ring, the overlap a place-recognition front end would
// find. Measured here (one Ceres thread): split (0, 1250, 2500) — local solves 0.4 s, factorization 0.06 s,
// covariance extraction 0.06 s and Q 0.015 s per data set, merged solves 0.35–0.6 s (DCS from the identity
// 4–5 s); split (500, 1250, 2000) halves those times, also with a pool of 50.
#pragma once

#include <tuple>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"
#include "pcm/consistency.hpp"
#include "sim/world1d.hpp"
#include "core/fields.hpp"

namespace keel::sim {

// Where to cut the single-robot graph (original pose indices).
struct SplitOptions {
  int first = 0;    // first pose of robot a
  int split = 500;  // first pose of robot b (robot a = [first, split))
  int last = 1000;  // one past the last pose of robot b (robot b = [split, last))
  // Throws std::invalid_argument unless 0 ≤ first, split − first ≥ 2, last − split ≥ 2 and last ≤ num_poses.
  void validate(int num_poses) const;
};

template <class G>
struct TwoRobotScenario {
  graph::PoseGraphOf<G> robot_a,
      robot_b;                      // local graphs, poses 0.. in each robot's own frame (pose 0 = identity)
  std::vector<G> truth_a, truth_b;  // ground-truth local poses (truth_a[0] = truth_b[0] = identity)
  G true_anchor;  // T_ab: pose of b's local frame in a's frame (= ground truth G_first⁻¹ G_split)
  std::vector<pcm::InterRobotMeasurement<G>> pool;  // the dataset's true a–b loop closures (left covariance)
  std::vector<typename G::Jacobian> pool_information;  // their residual information Ω (same order)
  std::vector<int> pool_lines;                         // their source lines (0 if unknown)
  SplitOptions split;
  int dropped_odometry = 0;  // a–b odometry edges removed and not put in the pool (normally 1)
  typename G::Point extent_min, extent_max;  // bounding box of all ground-truth positions in a's frame
};
using TwoRobotScenario2 = TwoRobotScenario<lie::SE2>;
using TwoRobotScenario3 = TwoRobotScenario<lie::SE3>;

// See the header comment. `ground_truth` holds the dataset's ground-truth poses (one per pose of the graph).
// Throws std::invalid_argument for a bad split, a ground truth of the wrong size, a non-finite ground-truth
// pose, or a robot whose local graph is not connected (named with the first unreachable pose).
TwoRobotScenario2 split_two_robots(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& ground_truth,
                                   const SplitOptions& options);
TwoRobotScenario3 split_two_robots(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& ground_truth,
                                   const SplitOptions& options);

// What a candidate is (the label kinds are those of the 1D world, world1d.hpp: inlier, aliased, random).
struct CandidateLabel {
  MeasurementLabel kind = MeasurementLabel::inlier;
  int group = -1;       // aliased: its group 0 … aliased_groups−1; −1 otherwise
  int pool_index = -1;  // inlier: index into TwoRobotScenario::pool; −1 otherwise
  bool is_inlier() const { return kind == MeasurementLabel::inlier; }
};

struct CandidateOptions {
  int num_inliers = 15;    // true loop closures drawn from the pool without replacement (≥ 0, ≤ pool size)
  int aliased_groups = 2;  // groups of mutually consistent outliers (≥ 0)
  int aliased_group_size = 5;  // outliers per group (≥ 1 when aliased_groups > 0)
  int random_outliers = 90;    // random outliers (≥ 0)
  double random_sigma_translation_min =
      0.01;  // m; σ_t of a random outlier, log-uniform on [min, max] (0 < min ≤ max)
  double random_sigma_translation_max = 10.0;
  double random_sigma_rotation_min =
      0.005;  // rad; σ_r of a random outlier, log-uniform on [min, max] (0 < min ≤ max)
  double random_sigma_rotation_max = 1.0;
  double aliased_noise_scale = 1.0;  // aliased members: residual r ~ N(0, s² Ω⁻¹) with this s (> 0); 1 = like
                                     // an inlier of the dataset; < 1 with resample_measurements() (same s)
  // Near-miss aliased groups (beyond §2.7.2; off while near_miss_translation_max = 0): each group's false
  // alignment is the true one, T_ab, moved by δ — a translation of length U[min, max] (m) in a uniform
  // direction and a rotation by an angle U[min, max] (rad) about a uniform axis — so A = T_ab δ: a
  // registration that converged close to, but not at, the truth, agreed on by every member of the group.
  double near_miss_translation_min = 0.0, near_miss_translation_max = 0.0;
  double near_miss_rotation_min = 0.0, near_miss_rotation_max = 0.0;
  bool shuffle = true;  // random candidate order (else: inliers, aliased groups in order, random outliers)
  int total() const { return num_inliers + aliased_groups * aliased_group_size + random_outliers; }
  // Throws std::invalid_argument naming the violated constraint (negative counts, bad σ ranges, no
  // candidate).
  void validate() const;
};

template <class G>
struct CandidateSet {
  std::vector<pcm::InterRobotMeasurement<G>> candidates;  // z ≈ (T^a_i)⁻¹ T_ab T^b_k with left covariance
  std::vector<typename G::Jacobian> information;          // residual information Ω of each candidate
  std::vector<CandidateLabel> labels;                     // one per candidate
  std::vector<G> false_anchors;  // per aliased group: the anchor its members agree on
  // Indices of the inlier candidates, ascending (the NO-OUT selection).
  std::vector<int> inliers() const {
    std::vector<int> v;
    for (int k = 0; k < static_cast<int>(labels.size()); ++k)
      if (labels[k].is_inlier()) v.push_back(k);
    return v;
  }
  // 0 … n−1 (every candidate, e.g. for DCS).
  std::vector<int> all() const {
    std::vector<int> v;
    for (int k = 0; k < static_cast<int>(candidates.size()); ++k) v.push_back(k);
    return v;
  }
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(candidates, information, labels, false_anchors)
};
using CandidateSet2 = CandidateSet<lie::SE2>;
using CandidateSet3 = CandidateSet<lie::SE3>;

// One data set (see the header comment), drawn from core::Rng::stream(seed, index). Throws
// std::invalid_argument for invalid options or more inliers than the scenario's pool.
CandidateSet2 generate_candidates(const TwoRobotScenario2& scenario, const CandidateOptions& options,
                                  std::uint64_t seed, std::uint64_t index);
CandidateSet3 generate_candidates(const TwoRobotScenario3& scenario, const CandidateOptions& options,
                                  std::uint64_t seed, std::uint64_t index);

// Replaces every measurement of both local graphs and of the pool by a fresh draw around the ground truth,
// keeping the declared information Ω: edge (i, j) gets z = X ρ⁻¹(r)⁻¹ with X the true relative pose and r ~
// N(0, s² Ω⁻¹) (so its residual at the truth is exactly r); pool edges are redrawn about X = (T^a_i)⁻¹ T_ab
// T^b_k and their left covariances recomputed. s = noise_scale > 0: 1 draws a fresh realisation at the stated
// noise level, s < 1 makes the measurements less noisy than their covariance claims (normalized χ² ≈ s²) —
// the regime the thesis's Table 2.1 χ² values (0.013–0.018) indicate. Deterministic: robot a, robot b and the
// pool draw from Rng::stream(seed, 0/1/2). Throws std::invalid_argument for s ≤ 0 or non-finite, or a graph
// with landmark measurements (not supported).
void resample_measurements(TwoRobotScenario2& scenario, double noise_scale, std::uint64_t seed);
void resample_measurements(TwoRobotScenario3& scenario, double noise_scale, std::uint64_t seed);

}  // namespace keel::sim
