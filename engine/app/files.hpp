// keel::app — what a user's pose-graph files hold, and the files of a two-robot set-up (docs/USING.md),
// shared by the `keel` command and the Python module:
//   graph_dimension / summarize   what a file holds (format, counts, connected components, noise levels);
//   split_files / read_labels     a two-robot split of a single-robot data set with generated outliers (the
//                                 §2.7.2 construction of Table 2.1), written as the files app::pcm reads.
// The other doors of keel.app: solve.hpp (app::solve), marginals.hpp (app::marginals), pcm.hpp (app::pcm).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "graph/pose_graph.hpp"
#include "sim/loop_closures.hpp"
#include "sim/two_robot.hpp"

namespace keel::app {

/// 2 or 3: the dimension of a pose-graph file, from the tag of its first record (EDGE_SE3:QUAT,
/// VERTEX_SE3:QUAT and EDGE3 are 3D; everything else, and a file without records, is read as 2D, whose reader
/// then names what is wrong). The file variant throws graph::ParseError for an unreadable file.
[[nodiscard]] int graph_dimension(const std::filesystem::path& file);
/// The same for a file's text (`name` for messages).
[[nodiscard]] int graph_dimension(std::string_view text, const std::string& name);

/// What `keel check` prints about a graph file.
struct GraphSummary {
  std::string file;
  std::string format;  // "g2o" or "isam"
  int dimension = 2;
  int poses = 0, edges = 0;
  int odometry = 0;       // edges (i, i+1)
  int loop_closures = 0;  // the other pose–pose edges
  int landmarks = 0, landmark_measurements = 0;
  bool has_initial_poses = false;  // the file carries vertex estimates (else: chained odometry)
  int components = 0;              // connected components of poses and landmarks
  int largest_component = 0;       // variables in the largest one
  int duplicate_edges = 0;         // edges whose (i, j) (or (j, i)) an earlier edge already measures
  int cross_term_edges = 0;        // edges whose information has off-diagonal entries
  // Standard deviations implied by the information (√diag Ω⁻¹), over all edges: translation (m, per axis)
  // and rotation (rad, per axis).
  double sigma_translation_min = 0.0, sigma_translation_max = 0.0;
  double sigma_rotation_min = 0.0, sigma_rotation_max = 0.0;
  double condition_max = 0.0;  // largest condition number of an edge's information
};
/// Reads the file (g2o or iSAM, 2D or 3D, by content) and summarizes it. The readers check every record
/// (finite numbers, symmetric positive definite information, ids) and throw graph::ParseError naming file,
/// line and field.
[[nodiscard]] GraphSummary summarize(const std::filesystem::path& file);

/// Refuses a graph whose least-squares cost (eq. 2.1) a solver cannot evaluate in double precision: the rule
/// is λ_max(Ω_e) · (ε · M)² ≤ 1 for every edge e (and landmark measurement), where ε = 2⁻⁵² is the rounding
/// unit and M = max(1, the largest vertex coordinate, the sum of the measured translations' largest
/// components) bounds the coordinates a solve can reach. Beyond it one rounding unit of a coordinate costs
/// more than 1 (a unit of χ²), so the computed optimum is rounding noise (a measurement of 1e100 on a tree
/// gives a cost of 5e170 instead of 0) or overflows (an information of 1e308). Throws std::invalid_argument
/// "file:line: TAG: ..." naming the edge, its weight, M and the limit.
void check_numeric_range(const graph::PoseGraph2D& g);
void check_numeric_range(const graph::PoseGraph3D& g);

struct SplitFilesOptions {
  sim::SplitOptions split;           // robot a = poses [first, split), robot b = [split, last)
  sim::CandidateOptions candidates;  // inliers, aliased groups, random outliers (§2.7.2)
  std::uint64_t seed = 1;            // the candidate draw: core::Rng::stream(seed, 0)
};

/// Splits a single-robot graph with ground truth (one pose per graph pose) into two robots and draws one
/// candidate set, then writes into `dir` (created if missing): a.g2o and b.g2o (the local graphs, vertices
/// chained from odometry), candidates.g2o (edge file, robot a's ids first), labels.txt (one line per
/// candidate: index, kind inlier/aliased/random, group) and truth.txt (T_ab, b's frame in a's). Returns the
/// candidate set. Throws std::invalid_argument for a bad split or options.
sim::CandidateSet2 split_files(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& ground_truth,
                               const SplitFilesOptions& options, const std::filesystem::path& dir);

struct RobotFilesOptions {
  int robots = 2;            // robots of consecutive poses (>= 1, at most the pose count)
  sim::WrongClosures wrong;  // wrong loop closures added before the cut (rate 0: none)
  std::uint64_t seed = 1;    // their draw: stream 0 of core::Streams(seed)
};

/// One graph (2D or 3D) with wrong loop closures added (sim::add_wrong_loop_closures) and cut into robots of
/// consecutive poses (sim::split_into_robots), written into `dir` (created if missing) for `keel robust`:
/// robot<r>.g2o per robot (its poses re-indexed from 0, its odometry and its own loop closures, wrong ones
/// among them), candidates.g2o with two robots or more (the loop closures between robots, ids global: robot
/// r's pose k is k plus the poses of the robots before it), and closures.txt (one line per loop closure: its
/// global ids, the file it went to and its edge index there, `true` or `wrong`). Returns the number of wrong
/// closures. Throws std::invalid_argument for bad options (naming the field), a graph whose odometry does not
/// chain its poses, or wrong closures asked of a graph without loop closures.
int robot_files(const graph::PoseGraph2D& graph, const RobotFilesOptions& options,
                const std::filesystem::path& dir);
int robot_files(const graph::PoseGraph3D& graph, const RobotFilesOptions& options,
                const std::filesystem::path& dir);

/// Reads labels.txt (written by split_files): true where the candidate is an inlier. Throws graph::ParseError
/// naming file and line for a malformed line, a kind other than inlier/aliased/random, or indices that are
/// not 0, 1, 2, … in order.
[[nodiscard]] std::vector<bool> read_labels(const std::filesystem::path& file);

}  // namespace keel::app
