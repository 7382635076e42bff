// Hard inputs for the certified solver (beyond the thesis): a real pose graph, or its first poses, with its
// loop closures corrupted — rotation noise on every loop closure, and a fraction of them replaced by random
// poses (outliers). The odometry chain is left as it is.
//
// A loop closure is an edge (i, j) with |i − j| ≠ 1 (consecutive ids are odometry, as in Kimera-RPGO and the
// thesis's §2.7). The draws use common random numbers: a loop closure's noise direction and its outlier pose
// are drawn for every loop closure whatever the level, so two levels of the same stream differ only in the
// scale of the noise, and a larger outlier fraction replaces a superset of the closures a smaller one does.
#pragma once

#include <cstdint>
#include <vector>

#include "core/random.hpp"
#include "graph/pose_graph.hpp"

namespace keel::sim {

struct LoopClosureCorruption {
  // Keep poses [0, first_poses) and the edges among them (0: every pose). The poses kept must stay connected
  // for a solver to accept the result; that is the solver's check, not this one's.
  int first_poses = 0;
  // σ (rad). 2D: θ̃ ← θ̃ + σ n; 3D: R̃ ← R̃ Exp(σ n), n ~ N(0, I₃). Translations keep their measured values.
  double rotation_noise = 0.0;
  // round(fraction · L) of the L loop closures (a uniformly random subset) get a random measurement instead:
  // a rotation uniform on SO(d) and a translation with each coordinate uniform in [−s, s], s the largest
  // absolute coordinate of any loop closure's measured translation (1 if all are zero). Their information
  // matrices are kept: an outlier is as confident as the closure it replaces.
  double outlier_fraction = 0.0;
  void validate() const;  // throws std::invalid_argument naming the field
};

template <class Graph>
struct CorruptedGraph {
  Graph graph;
  std::vector<int> loop_closures;  // indices into graph.edges, ascending
  std::vector<int> outliers;       // indices into graph.edges, ascending (a subset of loop_closures)
};
using CorruptedGraph2 = CorruptedGraph<graph::PoseGraph2D>;
using CorruptedGraph3 = CorruptedGraph<graph::PoseGraph3D>;

// The corrupted graph of draw `index` of `streams` (three named children: "order" shuffles the loop closures,
// "noise" draws their noise directions, "outlier" their random poses, each one stream per index). Throws
// std::invalid_argument for invalid options, a 2D graph with landmarks, or first_poses above the pose count.
[[nodiscard]] CorruptedGraph2 corrupt_loop_closures(const graph::PoseGraph2D& g,
                                                    const LoopClosureCorruption& o,
                                                    const core::Streams& streams, std::uint64_t index);
[[nodiscard]] CorruptedGraph3 corrupt_loop_closures(const graph::PoseGraph3D& g,
                                                    const LoopClosureCorruption& o,
                                                    const core::Streams& streams, std::uint64_t index);

}  // namespace keel::sim
