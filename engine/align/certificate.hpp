// Beyond the thesis: a certificate of global optimality over SO(2) for the hull objective.
//
// With A = R(θ) exactly, the objective of eq. 3.2 with the hull functions of eq. 3.4,
//     F(θ) = min_{t, u} Σ_j u_j  s.t.  r_m f_j + s_m g_j + t_m ≤ u_j,  (f_j, g_j) in box j,
// is a linear program for each fixed θ. Branch and bound on θ intervals finds min_θ F(θ): over an interval
// [a, b] (width ≤ π/4) the points (cos θ, sin θ) lie in the convex hull of their arc, which is contained in
// the polygon {cos(m) c + sin(m) s ≥ cos(h)} ∩ {tangents at a, m, b: cos(φ) c + sin(φ) s ≤ 1} (m the
// midpoint, h the half-width); the LP over (c, s) in that polygon is a valid lower bound on F over the
// interval, and F at the midpoint and at the angle of the relaxed solution are upper bounds. Best-first,
// intervals halved, until the gap closes. The eight-sector answer of eq. 3.19 can then be scored against the
// certified optimum.
#pragma once

#include <cstddef>

#include "align/align.hpp"
#include "core/bound.hpp"

namespace keel::align {

struct CertificateOptions {
  double relative_gap = 1e-6;      // stop when UB − LB ≤ relative_gap · max(1, |UB|)
  std::size_t node_limit = 20000;  // interval LPs allowed (lower bounds); beyond: status node_limit
  int initial_intervals = 16;      // [−π, π) split evenly first (≥ 8, so every interval is at most π/4 wide)
  void validate() const;
};

struct Certificate {
  core::SearchStatus status = core::SearchStatus::node_limit;  // optimal, or node_limit (core/bound.hpp)
  core::Bound bound{0, 0};  // lower: proven, F(θ) ≥ lower for every θ; upper: F(theta), attained
  double theta = 0;         // best rotation found
  double tx = 0, ty = 0;    // its translation
  std::size_t nodes = 0;    // intervals bounded
  int lp_solves = 0;
  double time_s = 0;
};

// min over θ of F(θ) for the planes and boxes of `regions` (e.g. global_regions: the whole reference).
[[nodiscard]] Certificate certify_rotation(const AlignmentProblem& problem, const Regions& regions,
                                           const LpSettings& lp, const CertificateOptions& options);

// F(θ) for one θ; +inf when no translation keeps every point in its box.
[[nodiscard]] double rigid_objective(const AlignmentProblem& problem, const Regions& regions,
                                     const LpSettings& lp, double theta);

}  // namespace keel::align
