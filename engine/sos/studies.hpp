// keel::sos — the chapter-4 studies (§4.6) and the test of the exactness claim (Theorems 4.5.3–4.5.4).
//
// Segment study: a planar data set cut into segments of consecutive poses (§4.6: 100), every segment kept
// (the thesis kept only those where MOSEK did not fail; here a failure is a row of the result). Per segment
// three estimates: SBSOS with its certificate (certify.hpp), Levenberg–Marquardt from a random initialization
// (the thesis's comparison) and from chained odometry (what a user runs). Errors against ground truth in the
// frame of the segment's first pose; costs on the thesis's cost (problem.hpp), so the three are comparable.
//
// Exactness study: random small graphs in families (poses, edge density, rotation noise), each solved by the
// order-1 relaxation with escalation; the share where order 1 is tight and where order 2 certifies the rest.
#pragma once

#include <tuple>
#include <cstdint>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "graph/pose_graph.hpp"
#include "pgo/options.hpp"
#include "sos/certify.hpp"

namespace keel::sos {

struct SegmentStudyOptions {
  int segment_length = 100;     // poses per segment (> 1)
  int stride = 100;             // first pose of segment k is k · stride (> 0)
  int max_segments = 0;         // 0: every segment that fits in the data set
  CertifyOptions sbsos;         // SBSOS-SLAM and its certificate
  pgo::Options lm;              // the LM baselines (their initial guesses are set per baseline)
  double random_extent = 50.0;  // LM random: translations uniform in ±extent m, angles uniform (> 0)
  std::uint64_t seed = 0;       // LM random: segment k uses pgo seed `seed + k`
  unsigned threads = 1;         // segments solved in parallel (DSDP calls are serialised); 0 = default
  void validate() const;
};

struct MethodOutcome {
  double trans_error = 0.0;     // mean over poses of ‖t − t_true‖ (m), truth in the first pose's frame
  double rot_error = 0.0;       // mean over poses of |θ − θ_true| (rad, wrapped)
  double landmark_error = 0.0;  // mean ‖l − l_true‖ over the segment's landmarks (0 without landmarks)
  double cost = 0.0;            // the thesis's cost f at the estimate (problem.hpp)
  double time_s = 0.0;
  std::vector<lie::SE2> poses;
  std::vector<lie::Vec2> landmarks;
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  auto fields() { return std::tie(trans_error, rot_error, landmark_error, cost, time_s, poses, landmarks); }
  auto fields() const {
    return std::tie(trans_error, rot_error, landmark_error, cost, time_s, poses, landmarks);
  }
};

struct SegmentOutcome {
  int first = 0, poses = 0, edges = 0, landmarks = 0, landmark_measurements = 0;
  bool failed = false;  // SBSOS threw (the message is in `error`)
  std::string error;
  MethodOutcome sbsos, lm_random, lm_odometry;
  core::SearchStatus status = core::SearchStatus::unproven;
  int certified_order = 0;
  double relative_gap = 0.0, rank_ratio = 0.0, lower_bound = 0.0;
  double primal_residual = 0.0, s_min_eigenvalue = 0.0;
  bool solver_claims_optimal = false, escalated = false;
  std::string note;
  double sdp_time_s = 0.0;  // the SDP solver call of the first relaxation
  std::vector<lie::SE2> truth;
  std::vector<lie::Vec2> truth_landmarks;
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  auto fields() {
    return std::tie(first, poses, edges, landmarks, landmark_measurements, failed, error, sbsos, lm_random,
                    lm_odometry, status, certified_order, relative_gap, rank_ratio, lower_bound,
                    primal_residual, s_min_eigenvalue, solver_claims_optimal, escalated, note, sdp_time_s,
                    truth, truth_landmarks);
  }
  auto fields() const {
    return std::tie(first, poses, edges, landmarks, landmark_measurements, failed, error, sbsos, lm_random,
                    lm_odometry, status, certified_order, relative_gap, rank_ratio, lower_bound,
                    primal_residual, s_min_eigenvalue, solver_claims_optimal, escalated, note, sdp_time_s,
                    truth, truth_landmarks);
  }
};

struct SegmentStudyOutcome {
  std::vector<SegmentOutcome> segments;
};

[[nodiscard]] SegmentStudyOutcome run_segment_study(const graph::PoseGraph2D& graph,
                                                    const std::vector<lie::SE2>& truth,
                                                    const std::vector<lie::Vec2>& truth_landmarks,
                                                    const SegmentStudyOptions& options,
                                                    core::Progress* progress = nullptr);

// One family of random small graphs for the exactness test.
struct ExactnessFamily {
  std::string name;
  int poses = 4;                   // ≥ 2; pose 0 is the anchor
  double edge_probability = 1.0;   // each non-odometry pair is an edge with this probability (1: complete)
  double rotation_noise = 0.1;     // rad, normal; ≤ 0 with uniform_rotations
  bool uniform_rotations = false;  // rotation measurements uniform on the circle (no consistent truth)
  double translation_noise = 0.1;  // m, normal
  double extent = 3.0;             // true positions uniform in [0, extent]²
  int trials = 50;
};

struct ExactnessOptions {
  std::vector<ExactnessFamily> families;
  CertifyOptions certify;  // escalation settings included
  std::uint64_t seed = 0;  // family f, trial t draws from stream (seed, f · 2^20 + t)
  unsigned threads = 1;    // 0 = default
  void validate() const;
};

struct ExactnessTrial {
  bool tight_order1 = false;  // certified by order 1
  bool certified = false;     // by order 1 or 2
  bool escalated = false, escalation_skipped = false;
  double gap_order1 = 0.0;  // relative gap after order 1
  double rank_ratio = 0.0;  // order 1
};

struct ExactnessOutcome {
  std::vector<std::vector<ExactnessTrial>> trials;  // [family][trial]
};

[[nodiscard]] ExactnessOutcome run_exactness_study(const ExactnessOptions& options,
                                                   core::Progress* progress = nullptr);

// The counterexample to Theorem 4.5.3: 4 poses, complete graph, rotation-only measurements
// θ = (0.23, 0.43, 1.13, −1.81, 1.36, −1.35) rad on (0,1), (0,2), (0,3), (1,2), (1,3), (2,3), unit weights.
[[nodiscard]] graph::PoseGraph2D exactness_counterexample();

}  // namespace keel::sos
