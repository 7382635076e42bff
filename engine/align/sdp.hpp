// SOConvHull as a semidefinite program (DSDP): the conv SO(2) constraint of eq. 3.12 as the 2 × 2 block
// [[1 + c, s], [s, 1 − c]] ⪰ 0 (the thesis prints "≤ 0"; ⪰ 0 is meant: it is the unit disc c² + s² ≤ 1),
// every hull plane and box as linear inequalities (no lazy rows). keel's alignment uses the LP with tangent
// cuts (HullLp with disc_tolerance); this form is the independent check of that choice.
#pragma once

#include <vector>

#include "align/align.hpp"

namespace keel::align {

struct SdpSolution {
  bool converged = false;      // DSDP stopped with DSDP_CONVERGED and a feasible, bounded pair
  double cost = 0;             // Σ u_j at the optimum
  std::vector<double> params;  // (c, s, tx, ty)
  int iterations = 0;
  double time_s = 0;
};

// The round with `regions` (e.g. global_regions) solved by DSDP (convex::solve_sdp) to a relative gap of
// `gap_tolerance`.
[[nodiscard]] SdpSolution so_conv_hull_sdp(const AlignmentProblem& problem, const Regions& regions,
                                           double gap_tolerance = 1e-8);

}  // namespace keel::align
