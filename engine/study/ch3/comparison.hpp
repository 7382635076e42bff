// The machinery of the chapter-3 studies (§3.7, §3.8): a simulated world as an alignment problem, every
// method on every world with round 0's regions shared, and how each method is scored. The studies
// (studies.hpp) run these on their RunContext: world w draws from context.streams().stream(w) (sim's (seed,
// index) pair).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include "align/align.hpp"
#include "align/certificate.hpp"
#include "repro/run.hpp"
#include "sim/alignment_world.hpp"
#include "sim/hull_world.hpp"
#include "core/fields.hpp"

namespace keel::study::ch3 {

using align::AlignmentProblem;
using align::AlignOptions;
using align::AlignResult;
using align::Certificate;
using align::CertificateOptions;
using align::Method;
using align::Rigid2;
using align::Transform2;

// The problem of a simulated world: positions, and the Euclidean distance between feature vectors as the
// dissimilarity (§3.4.1 leaves C_ij to the user).
[[nodiscard]] AlignmentProblem problem_of(const sim::AlignmentWorld& world);
// The known-depth problem of a hull world (eq. 3.9): positions with depths.
[[nodiscard]] AlignmentProblem problem_of(const sim::HullWorld& world);

// One estimate scored against the truth (θ, t): the final answer, or one round's of the shrinking schedule.
// Errors are those of Table 3.1 as we define them (the thesis does not). Primary: rotation SE = wrap(θ̂ − θ)²
// with θ̂ the polar projection of the estimate (the closest rotation to A in the Frobenius norm, whatever the
// parameterization); translation SE = |T̂(p̄) − T(p̄)|² at the query centroid p̄ (removes the lever arm of the
// rotation error, so a rotation error is not counted twice). Variants: θ̂ from atan2(a21, a11) (the angle of
// A's first column, which is what a reader of the raw matrix would take), and |t̂ − t|² at the query frame's
// origin (T's translation part itself).
struct EstimateScore {
  double rot_se = 0, trans_se = 0;               // primary
  double rot_se_atan2 = 0, trans_se_origin = 0;  // variants
  double rot_error = 0;                          // wrap(θ̂ − θ), signed (polar)
  double singular_min = 0, singular_max = 0;     // of the estimated A
  double radius = 0;                             // hypot(a11, a21): |(c, s)| for the rotation-like methods
  bool valid = false;                            // approximately_valid(A, valid_tolerance)
  double half_width = 0;                         // the round's box half-width (0 for the final answer)
};
[[nodiscard]] EstimateScore score_estimate(const AlignmentProblem& problem, const Transform2& estimate,
                                           double theta, double tx, double ty, double valid_tolerance);

// How one method did on one world: the final answer, and every round of the shrinking schedule (round 0 =
// every reference point, no shrinking).
struct MethodOutcome {
  Transform2 raw;
  Rigid2 rigid;
  double rot_se = 0, trans_se = 0;
  double singular_min = 0, singular_max = 0;  // of the estimated A
  bool valid = false;                         // approximately_valid(raw, valid_tolerance)
  double cost = 0;
  int sector = -1;
  int rounds = 0, lp_solves = 0;
  double time_s = 0;  // round-0 hulls (shared by the methods, counted for each) + align()
  EstimateScore final_score;
  std::vector<EstimateScore> round_scores;  // [round]
  KEEL_FIELDS(raw, rigid, rot_se, trans_se, singular_min, singular_max, valid, cost, sector, rounds,
              lp_solves, time_s, final_score, round_scores)
};
// The certificate of one world (beyond the thesis): the global optimum over SO(2) of round 0's hull
// objective (every reference point), against the proposed method's round-0 answer.
struct CertificateOutcome {
  Certificate certificate;
  double sector_theta = 0;      // polar angle of the 8-sector round-0 estimate
  double sector_objective = 0;  // F(sector_theta): the exact objective at that rotation
  double relative_gap = 0;      // (F(sector_theta) − F*) / max(1, |F*|), F* = certificate.bound.upper
  double theta_difference = 0;  // |wrap(sector_theta − certificate.theta)|
};

// SOConvHull's round 0 solved two ways (beyond the thesis's description): the LP with tangent cuts keel uses,
// and the 2 × 2 PSD block of eq. 3.12 by DSDP.
struct SdpCheck {
  double lp_cost = 0, sdp_cost = 0;
  double lp_time_s = 0, sdp_time_s = 0;
  bool sdp_converged = false;
};

// What a chapter-3 comparison runs on every world: the methods, how they are scored, and (beyond the thesis)
// the certificate and the SDP check.
struct ComparisonOptions {
  std::vector<Method> methods{Method::proposed, Method::so_conv_hull, Method::symmetric, Method::affine};
  AlignOptions align;  // method is set per method; align.threads is ignored (worlds run in parallel)
  double valid_tolerance = 0.05;  // "approximately valid": both singular values within this of 1, det > 0
  bool certify = false;           // run the certificate on every world (needs Method::proposed)
  CertificateOptions certificate;
  std::size_t sdp_check_worlds = 0;  // the first this many worlds also solve SOConvHull's round 0 by DSDP
  void validate() const;             // throws std::invalid_argument naming ComparisonOptions.<field>
};

struct AlignmentStudyOptions {
  sim::AlignmentWorldOptions world;
  ComparisonOptions compare;
  std::size_t worlds = 200;
  void validate() const;
};

struct AlignmentStudyOutcome {
  std::vector<Method> methods;
  std::vector<std::vector<MethodOutcome>> outcomes;         // [method][world]
  std::vector<CertificateOutcome> certificates;             // [world], when certify
  std::vector<SdpCheck> sdp_checks;                         // [world < sdp_check_worlds]
  std::vector<double> world_theta;                          // true rotations
  std::vector<std::size_t> reference_points, query_points;  // [world]
};

// One world: the problem and its ground truth p_ref = R(theta) p_query + (tx, ty).
struct WorldTruth {
  AlignmentProblem problem;
  double theta = 0, tx = 0, ty = 0;
};

// Runs `compare` on worlds 0 … worlds − 1 made by `world(w)` (called from worker threads: it must be safe to
// call concurrently), on the context's threads in one sharded trial loop, round 0's regions computed once
// per world and shared by the methods. Deterministic whatever the thread count.
[[nodiscard]] AlignmentStudyOutcome compare_methods(const ComparisonOptions& compare, std::size_t worlds,
                                                    const repro::RunContext& context,
                                                    const std::function<WorldTruth(std::size_t)>& world,
                                                    core::Progress* progress = nullptr);

// World w: sim::make_alignment_world(options.world, streams.seed(), streams.index(w)).
[[nodiscard]] AlignmentStudyOutcome run_alignment_study(const AlignmentStudyOptions& options,
                                                        const repro::RunContext& context,
                                                        core::Progress* progress = nullptr);

// Scores an alignment of a problem against a ground truth (θ, tx, ty).
[[nodiscard]] MethodOutcome score_alignment(const AlignmentProblem& problem, const AlignResult& result,
                                            double theta, double tx, double ty, double valid_tolerance);

// The summary of Table 3.1: the median, and the standard deviation after dropping values outside the
// 1.5·IQR fences [Q1 − 1.5 IQR, Q3 + 1.5 IQR] (quartiles by linear interpolation).
struct FencedSummary {
  double median = 0, std = 0, mean = 0;
  std::size_t n = 0, dropped = 0;
};
[[nodiscard]] FencedSummary fenced_summary(std::vector<double> values);

// ---------------------------------------------------------------------------------------------------------------
// The hull substitute of §3.8 (Fig. 3.5) — the known-depth alignment (eq. 3.9) of two synthetic HAUV surveys
// of a ship hull (sim::HullWorld; the thesis's USCGC Spencer data are not available), with the DVL curvature
// features standardised before the Euclidean dissimilarity.
//
// Why standardise: the hull world's features are (κ1, κ2, slope) with κ of order 0.01–0.1 1/m and slope of
// order 0.3 (dimensionless), so a plain Euclidean distance (problem_of(HullWorld)) is dominated by the slope.
// Dividing every component by its standard deviation over the reference survey weighs the three equally; the
// scale comes from the reference alone (the query robot receives the reference's scales with its data, three
// numbers), and the same scale is applied to both surveys so equal features stay equal.

// Standard deviation of each feature component over the reference survey (population std, divisor n_a), one
// value per component (HullWorld::feature_dim). Throws std::invalid_argument for an empty reference or
// feature arrays whose size is not n × feature_dim.
[[nodiscard]] std::vector<double> reference_feature_scales(const sim::HullWorld& world);

// The known-depth problem of eq. 3.9 (positions with depths, as problem_of(HullWorld)) with the Euclidean
// dissimilarity of the standardised features: component k of both surveys divided by
// reference_feature_scales(world)[k]. A component with zero (or non-finite) spread over the reference is left
// unscaled.
[[nodiscard]] AlignmentProblem standardized_problem_of(const sim::HullWorld& world);

struct HullStudyOptions {
  sim::HullWorldOptions world;
  ComparisonOptions compare;  // compare.align.depth_gate is γ of §3.4.3 (0: no gate)
  std::size_t worlds = 20;
  // Throws std::invalid_argument "HullStudyOptions.worlds = 0: ..." (and validates world, compare).
  void validate() const;
};

using HullStudyOutcome = AlignmentStudyOutcome;

// Every world (make_hull_world(options.world, streams.seed(), streams.index(w))) aligned by every method on
// its standardized_problem_of, round 0's regions shared by the methods.
[[nodiscard]] HullStudyOutcome run_hull_study(const HullStudyOptions& options,
                                              const repro::RunContext& context,
                                              core::Progress* progress = nullptr);

}  // namespace keel::study::ch3
