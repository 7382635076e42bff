// keel::sos — SBSOS-SLAM with an honest certificate (thesis §4.5–4.6, checked rather than assumed).
//
// solve_certified(): relax (relaxation.hpp) → round (project every (c_i, s_i) to the circle, translations and
// landmarks by least squares) → polish with keel.pgo's Levenberg–Marquardt → refine on the thesis's own cost
// (problem.hpp: chordal rotation term) → certificate: the relaxation's lower bound LB against the cost UB of
// the polished solution, relative gap (UB − LB) / max(UB, 1) (the cost is a χ², so below one σ² the gap is
// absolute). The answer is certified optimal only if that gap is within `gap_tolerance`; the lower bound is
// built from the returned matrices (relaxation.hpp), never from the solver's status word. When order 1 is not
// tight, the next level of the hierarchy (order-2 moments on the same structure: for the dense one, over the
// rotations with the translations minimised out) is tried if its moment count is affordable, and the report
// says whether it certifies.
//
// Theorems 4.5.3–4.5.4 claim order 1 is always exact; it is not (the order-1 feasible set is the convex hull
// of the circle, and the circle enters only through a concave constraint), which is why every answer carries
// this certificate.
#pragma once

#include <string>
#include <string_view>

#include "core/bound.hpp"
#include "graph/pose_graph.hpp"
#include "pgo/options.hpp"
#include "sos/problem.hpp"
#include "sos/relaxation.hpp"

namespace keel::sos {

struct CertifyOptions {
  RelaxationOptions relaxation;  // the first relaxation (default: dense, order 1 = Sparse-BSOS d = k = 1)
  pgo::Options polish;  // Levenberg–Marquardt polish of the rounded solution (initial guess: supplied)
  double gap_tolerance =
      1e-6;  // relative gap (UB − LB) / max(UB, 1) at or below which the answer is certified (> 0)
  bool escalate = true;                // try order 2 (same structure) when order 1 does not certify
  long escalation_max_moments = 4000;  // order 2 is attempted only up to this many moments (DSDP's Schur
                                       // complement is dense in the moments)
  void validate() const;
};

struct CertifiedSolution {
  PlanarEstimate estimate;  // pose 0 at the identity, original units
  Eigen::VectorXd z;        // the same as unknowns
  // upper: f at the solution (the thesis's cost, problem.hpp); lower: the best lower bound over the
  // relaxations tried (core/bound.hpp), numerical: recomputed in double from the SDP's returned matrices
  // without a rounding margin ("certified" in the thesis's sense, not proven like sos/verify.hpp's).
  core::Bound bound{0.0, 0.0};
  // optimal: a relaxation's lower bound is within gap_tolerance of the solution's cost; unproven: no
  // relaxation tried closed the gap (the note says which were tried or skipped), or the structure is cliques,
  // whose bound rests on an unproven translation box (relaxation.hpp) and is reported, never certified.
  core::SearchStatus status = core::SearchStatus::unproven;
  [[nodiscard]] double relative_gap() const { return bound.relative_gap(); }
  int certified_order = 0;    // 1 or 2 when certified, else 0
  RelaxationResult first;     // the first relaxation
  bool escalated = false;     // whether order 2 was solved
  RelaxationResult second;    // valid when escalated
  std::string note;           // why escalation was skipped or failed; empty otherwise
  double rounded_cost = 0.0;  // f at the rounded relaxation estimate, before polishing
  double relax_time_s = 0.0, polish_time_s = 0.0, escalation_time_s = 0.0, time_s = 0.0;
};

// Throws std::invalid_argument for a bad graph (planar_problem) or options; solver errors propagate.
[[nodiscard]] CertifiedSolution solve_certified(const graph::PoseGraph2D& graph,
                                                const CertifyOptions& options = {});
[[nodiscard]] CertifiedSolution solve_certified(const graph::PoseGraph2D& graph, const PlanarProblem& problem,
                                                const CertifyOptions& options);

// The counterexample to Theorem 4.5.3: 4 poses, complete graph, rotation-only measurements
// θ = (0.23, 0.43, 1.13, −1.81, 1.36, −1.35) rad on (0,1), (0,2), (0,3), (1,2), (1,3), (2,3), unit weights.
[[nodiscard]] graph::PoseGraph2D exactness_counterexample();

}  // namespace keel::sos
