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
#include <string_view>
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

// Wrong loop closures added to a graph (a robust back end's input; Kimera-RPGO's and the thesis's §2.7
// setting): the graph keeps its L loop closures, and m = round(rate / (1 − rate) · L) wrong ones are
// appended, so that `rate` is the share of wrong closures among all of them.
//   random   each between a random pose pair (i, j), |i − j| ≥ 2 (both uniform over the poses kept), its
//            measurement a rotation uniform on SO(d) and each translation coordinate uniform in [−s, s], s as
//            in LoopClosureCorruption;
//   aliased  perceptual aliasing, groups of `group_size` mutually consistent wrong closures: a group draws
//   two
//            blocks of poses a … a + g − 1 and b … b + g − 1 that do not overlap or touch, and a false
//            relative pose A (drawn as a random closure's measurement); member k joins a + k to b + k with
//            z̄_k = O_{a+k}⁻¹ O_a A O_b⁻¹ O_{b+k}, O the poses chained from the odometry (pose 0 at the
//            identity), so the group agrees with one wrong alignment of the two blocks exactly as the
//            odometry maps see them. The last group is cut short so that m is exact.
// Every wrong closure copies the information Ω of a true loop closure drawn uniformly (it is as confident as
// the true ones); an aliased member is also perturbed like a measurement, z = z̄ ρ⁻¹(r)⁻¹ with r ~ N(0, Ω⁻¹).
// The draws of one index come in order from one stream, so a higher rate adds to a lower rate's wrong
// closures (common random numbers).
enum class WrongClosureKind { random, aliased };
[[nodiscard]] std::string_view to_string(WrongClosureKind kind);                       // "random" | "aliased"
[[nodiscard]] WrongClosureKind wrong_closure_kind_from_string(std::string_view text);  // throws on others

struct WrongClosures {
  int first_poses = 0;  // as LoopClosureCorruption::first_poses
  double rate = 0.0;    // the share of wrong closures among all loop closures, in [0, 1)
  WrongClosureKind kind = WrongClosureKind::random;
  int group_size = 5;     // aliased: members per group (>= 1; the thesis's §2.7.2 groups have 5)
  void validate() const;  // throws std::invalid_argument naming the field
};

// The graph with its wrong closures appended (`outliers`: their indices, the last m edges) from stream
// `index` of `streams`' child "wrong". Throws std::invalid_argument for invalid options, landmarks,
// first_poses above the pose count, a pose kept without an odometry edge from its predecessor, wrong closures
// asked of a graph with no loop closure (nothing to copy the information of), or an aliased group that does
// not fit.
[[nodiscard]] CorruptedGraph2 add_wrong_loop_closures(const graph::PoseGraph2D& g, const WrongClosures& o,
                                                      const core::Streams& streams, std::uint64_t index);
[[nodiscard]] CorruptedGraph3 add_wrong_loop_closures(const graph::PoseGraph3D& g, const WrongClosures& o,
                                                      const core::Streams& streams, std::uint64_t index);

// One graph cut into `robots` robots, each a block of consecutive poses: robot r holds poses
// [⌊r n / R⌋, ⌊(r + 1) n / R⌋), re-indexed from 0, and the edges inside its block. An edge between two
// blocks is an inter-robot candidate with its ids as in the graph (which are merge::robust's global ids: the
// robots' poses numbered one after another), except the odometry edges (|i − j| = 1) that join two blocks,
// which are dropped: the robots' trajectories are not joined by odometry.
template <class Graph>
struct RobotSplit {
  std::vector<Graph> robots;
  std::vector<typename decltype(Graph::edges)::value_type> inter;
  std::vector<std::vector<int>> robot_edge;  // robot_edge[r][k]: the graph's edge that robot r's edge k is
  std::vector<int> inter_edge;               // the graph's edge that inter-robot candidate k is
};
// Throws std::invalid_argument when robots < 1 or robots exceeds the pose count.
[[nodiscard]] RobotSplit<graph::PoseGraph2D> split_into_robots(const graph::PoseGraph2D& g, int robots);
[[nodiscard]] RobotSplit<graph::PoseGraph3D> split_into_robots(const graph::PoseGraph3D& g, int robots);
// The robot that split_into_robots gives pose `id` of `poses` cut into `robots` (0 <= id < poses).
[[nodiscard]] int robot_of_pose(int id, int poses, int robots);

}  // namespace keel::sim
