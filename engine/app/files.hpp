// keel::app — operations on a user's pose-graph files (docs/USING.md), shared by the `keel` command and the
// Python module:
//   graph_dimension / summarize   what a file holds (format, counts, connected components, noise levels);
//   run_pcm                       the two-robot map merging of thesis §2.6 on user files: local solves, joint
//                                 marginals, the consistency matrix Q of eq. 2.4, the maximum clique
//                                 (eq. 2.5) and, optionally, the merged solve with the selected candidates;
//   split_files                   a two-robot split of a single-robot data set with generated outliers (the
//                                 §2.7.2 construction of Table 2.1), written as the files run_pcm reads.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "merge/merge.hpp"
#include "graph/pose_graph.hpp"
#include "pcm/clique.hpp"
#include "pcm/consistency.hpp"
#include "pcm/selection.hpp"
#include "pgo/options.hpp"
#include "sim/two_robot.hpp"

namespace keel::app {

/// 2 or 3: the dimension of a pose-graph file, from the tag of its first record (EDGE_SE3:QUAT,
/// VERTEX_SE3:QUAT and EDGE3 are 3D; everything else, and a file without records, is read as 2D, whose reader
/// then names what is wrong). The file variant throws graph::ParseError for an unreadable file.
[[nodiscard]] int graph_dimension(const std::filesystem::path& file);
/// The same for a file's text (`name` for messages).
[[nodiscard]] int graph_dimension(std::string_view text, const std::string& name);

/// The solver options of `keel solve` and Python's keel.solve: pgo's defaults with only these fields set, so
/// the two give bit-identical results. `init` names a pgo::InitialGuess ('-' may stand for '_': "as-read"),
/// `robust` a pgo::RobustKernel. Throws std::invalid_argument for an unknown name or an invalid value.
[[nodiscard]] pgo::Options solve_options(std::string init, std::string_view robust, double robust_parameter,
                                         std::uint64_t seed, unsigned threads, int max_iterations);

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

/// Called with a short description of each stage as it starts (progress on long runs); may be empty.
using Progress = std::function<void(std::string_view stage)>;

struct PcmOptions {
  double p =
      0.11;  // γ = F⁻¹_χ²(dof)(1 − p), the consistency threshold (thesis §2.7: PCM-Exact-11 %), in (0, 1)
  pcm::Composition composition = pcm::Composition::joint;  // x̂_ij from the joint marginals (eq. 2.4)
  pcm::CliqueAlgorithm algorithm = pcm::CliqueAlgorithm::exact;
  double time_limit_s = 0.0;          // exact clique search limit; <= 0: none (the result says if it stopped)
  merge::LocalSolveOptions local;     // the two local solves (odometry initial guess, pose 0 fixed)
  bool merge = false;                 // also solve the merged two-robot graph with the selected candidates
  merge::MergeOptions merge_options;  // of that solve
  unsigned threads = 1;               // consistency matrix; 0 = keel::core::default_threads()
  // Throws std::invalid_argument naming the field (including the nested options' own checks).
  void validate() const;
};

template <class G>
struct PcmRun {
  merge::LocalSolution<G> a, b;                           // the solved local maps
  std::vector<pcm::InterRobotMeasurement<G>> candidates;  // with left covariances (consistency.hpp)
  pcm::ConsistencyMatrix q;
  double gamma = 0.0;
  pcm::Selection selection;  // selection.search holds the clique search (status, bound)
  std::optional<merge::MergeResult<G>> merged;
  double marginals_time_s = 0.0, consistency_time_s = 0.0;
};
using PcmRun2 = PcmRun<lie::SE2>;
using PcmRun3 = PcmRun<lie::SE3>;

/// The candidate edges as keel.pcm needs them: each id checked against its robot (the message names the
/// candidate index and source line), the left covariance from the residual information
/// (pcm::left_covariance_from_information). Throws std::invalid_argument for an empty list, an id out of
/// range or an information that is not positive definite.
[[nodiscard]] std::vector<pcm::InterRobotMeasurement2> inter_robot_candidates(
    const graph::PoseGraph2D& a, const graph::PoseGraph2D& b, const std::vector<graph::Edge2>& edges);
[[nodiscard]] std::vector<pcm::InterRobotMeasurement3> inter_robot_candidates(
    const graph::PoseGraph3D& a, const graph::PoseGraph3D& b, const std::vector<graph::Edge3>& edges);

/// §2.6 steps i–iii (and iv with options.merge) on two robots' graphs and a candidate list whose edges
/// measure z ≈ (T^a_i)⁻¹ T^b_j with residual information Ω (graph::read_g2o_edges_*). Throws
/// std::invalid_argument for invalid options, a candidate naming a pose its robot does not have (candidate
/// index and source line), or an information that is not positive definite; std::runtime_error when a solve
/// fails or a local map is not connected.
[[nodiscard]] PcmRun2 run_pcm(const graph::PoseGraph2D& a, const graph::PoseGraph2D& b,
                              const std::vector<graph::Edge2>& candidates, const PcmOptions& options = {},
                              const Progress& progress = {});
[[nodiscard]] PcmRun3 run_pcm(const graph::PoseGraph3D& a, const graph::PoseGraph3D& b,
                              const std::vector<graph::Edge3>& candidates, const PcmOptions& options = {},
                              const Progress& progress = {});

/// The merged map as one graph: a's poses keep their ids 0 … n_a − 1, b's become n_a … n_a + n_b − 1, both in
/// a's frame; the edges of both local graphs, then the selected candidates. Throws std::invalid_argument when
/// the run has no merged solve.
[[nodiscard]] graph::PoseGraph2D merged_graph(const PcmRun2& run);
[[nodiscard]] graph::PoseGraph3D merged_graph(const PcmRun3& run);

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

/// Reads labels.txt (written by split_files): true where the candidate is an inlier. Throws graph::ParseError
/// naming file and line for a malformed line, a kind other than inlier/aliased/random, or indices that are
/// not 0, 1, 2, … in order.
[[nodiscard]] std::vector<bool> read_labels(const std::filesystem::path& file);

}  // namespace keel::app
