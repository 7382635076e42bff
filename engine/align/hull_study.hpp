// The hull substitute of §3.8 (Fig. 3.5): the known-depth alignment (eq. 3.9) of two synthetic HAUV surveys
// of a ship hull (sim::HullWorld; the thesis's USCGC Spencer data are not available), with the DVL curvature
// features standardised before the Euclidean dissimilarity. The engine side of ch3_fig3_5_hull_substitute.
//
// Why standardise: the hull world's features are (κ1, κ2, slope) with κ of order 0.01–0.1 1/m and slope of
// order 0.3 (dimensionless), so a plain Euclidean distance (problem_of(HullWorld)) is dominated by the slope.
// Dividing every component by its standard deviation over the reference survey weighs the three equally; the
// scale comes from the reference alone (the query robot receives the reference's scales with its data, three
// numbers), and the same scale is applied to both surveys so equal features stay equal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "align/align.hpp"
#include "align/studies.hpp"
#include "sim/hull_world.hpp"

namespace keel::core {
class Progress;
}

namespace keel::align {

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
  std::uint64_t seed = 0;
  std::uint64_t stream_base = 0;  // world w uses sim stream stream_base + w
  unsigned threads = 0;           // worlds in parallel; results do not depend on it
  // Throws std::invalid_argument "HullStudyOptions.worlds = 0: ..." (and validates world, compare).
  void validate() const;
};

using HullStudyOutcome = AlignmentStudyOutcome;

// Every world (make_hull_world(options.world, seed, stream_base + w)) aligned by every method on its
// standardized_problem_of, round 0's regions shared by the methods.
[[nodiscard]] HullStudyOutcome run_hull_study(const HullStudyOptions& options,
                                              keel::core::Progress* progress = nullptr);

}  // namespace keel::align
