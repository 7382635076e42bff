// The machinery of the chapter-4 studies (§4.6) and the test of the exactness claim (Theorems 4.5.3–4.5.4),
// run on a RunContext (studies.hpp has the studies themselves).
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

#include <cstdint>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "core/progress.hpp"
#include "graph/pose_graph.hpp"
#include "pgo/options.hpp"
#include "repro/run.hpp"
#include "sos/certify.hpp"
#include "sos/verify.hpp"
#include "core/fields.hpp"

namespace keel::study::ch4 {

using sos::CertifiedSolution;
using sos::CertifyOptions;
using sos::GlobalCertificate;
using sos::GlobalCertificateOptions;
using sos::RefineOptions;
using sos::RefineReport;

struct SegmentStudyOptions {
  int segment_length = 100;     // poses per segment (> 1)
  int stride = 100;             // first pose of segment k is k · stride (> 0)
  int max_segments = 0;         // 0: every segment that fits in the data set
  CertifyOptions sbsos;         // SBSOS-SLAM and its certificate
  pgo::Options lm;              // the LM baselines (their initial guesses are set per baseline)
  double random_extent = 50.0;  // LM random: translations uniform in ±extent m, angles uniform (> 0)
  void validate() const;
};

struct MethodOutcome {
  double trans_error = 0.0;     // mean over poses of ‖t − t_true‖ (m), truth in the first pose's frame
  double rot_error = 0.0;       // mean over poses of |θ − θ_true| (rad, wrapped)
  double landmark_error = 0.0;  // mean ‖l − l_true‖ over the segment's landmarks (0 without landmarks)
  double cost = 0.0;            // the thesis's cost f at the estimate (problem.hpp)
  double time_s = 0.0;
  // Levenberg–Marquardt only: iterations and whether it met a tolerance (pgo::Termination::converged) rather
  // than stopping at its iteration cap or failing.
  int iterations = 0;
  bool converged = false;
  std::vector<lie::SE2> poses;
  std::vector<lie::Vec2> landmarks;
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(trans_error, rot_error, landmark_error, cost, time_s, iterations, converged, poses, landmarks)
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
  KEEL_FIELDS(first, poses, edges, landmarks, landmark_measurements, failed, error, sbsos, lm_random,
              lm_odometry, status, certified_order, relative_gap, rank_ratio, lower_bound, primal_residual,
              s_min_eigenvalue, solver_claims_optimal, escalated, note, sdp_time_s, truth, truth_landmarks)
};

struct SegmentStudyOutcome {
  std::vector<SegmentOutcome> segments;
};

// Segments in one sharded trial loop on the context's threads (DSDP calls are serialised: one thread is what
// the per-segment times of the thesis's comparison mean); LM from a random start on segment k uses pgo seed
// context.streams().seed() + k.
[[nodiscard]] SegmentStudyOutcome run_segment_study(const graph::PoseGraph2D& graph,
                                                    const std::vector<lie::SE2>& truth,
                                                    const std::vector<lie::Vec2>& truth_landmarks,
                                                    const SegmentStudyOptions& options,
                                                    const repro::RunContext& context,
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
  bool escalate = true;    // try order 2 when order 1 does not certify (and CertifyOptions::escalate)
  bool noise_map = false;  // a cell of the noise map (order 1 only), not one of the listed families
};

struct ExactnessOptions {
  std::vector<ExactnessFamily> families;  // the listed families, then the noise map's cells
  CertifyOptions certify;                 // escalation settings included
  // The independent global minimum: Newton on f (sos::refine_solution) from `multistart_starts` starts with
  // every angle uniform and every translation zero, the lowest cost kept.
  int multistart_starts = 50;
  RefineOptions multistart_refine;
  GlobalCertificateOptions dual;  // the dual certificate at the best minimum found (sos/verify.hpp)
  void validate() const;
};

struct ExactnessTrial {
  bool tight_order1 =
      false;  // a bound on order 1's value (DSDP's or the dual's) within gap_tolerance of the best minimum
  bool certified_order1 = false;  // order 1's certificate (its rounded, polished answer within tolerance)
  bool certified = false;         // by order 1 or 2
  bool escalated = false, escalation_skipped = false;
  bool dual_certified = false;  // the dual certificate proves the best minimum found globally optimal
  double gap_order1 = 0.0;      // (best − max(lower_order1, lower_dual)) / max(best, 1); +inf without a bound
  double rank_ratio = 0.0;      // order 1
  // The relaxations' bounds recomputed from DSDP's returned matrices (order 2: 0 unless run).
  double lower_order1 = 0.0, lower_order2 = 0.0;
  double upper = 0.0;              // f at solve_certified's answer
  double multistart = 0.0;         // the lowest f over the multistart
  double best = 0.0;               // min(upper, multistart): the minimum that tightness is judged against
  int multistart_hits = 0;         // starts that ended within 1e-8 relative of the multistart's lowest f
  double dual_gap = 0.0;           // the dual certificate's proven relative gap
  double lower_dual = 0.0;         // its proven bound Σλ − η · poses (−inf when no shift was proven)
  double dual_failed_shift = 0.0;  // the largest shift whose PSD proof failed (0: none), λ_min(S) ≲ −it
};

struct ExactnessOutcome {
  std::vector<std::vector<ExactnessTrial>> trials;  // [family][trial]
};

// Family f, trial t draws from context.streams().stream(f · 2^20 + t); one sharded trial loop.
[[nodiscard]] ExactnessOutcome run_exactness_study(const ExactnessOptions& options,
                                                   const repro::RunContext& context,
                                                   core::Progress* progress = nullptr);

// ---------------------------------------------------------------------------------------------------------------
// The dual certificate of a whole data set's solution (sos/verify.hpp), on LM's answers.

// The study: per data set, keel.pgo's Levenberg–Marquardt from chained odometry and from a random
// initialization, each refined on f and certified.
struct GlobalCertificateDataset {
  std::string name;  // a label for results
  std::string file;  // as given in the config (for messages)
  graph::PoseGraph2D graph;
};

struct GlobalCertificateStudyOptions {
  pgo::Options lm;                       // both LM runs (initial guess and seed set per run)
  double random_extent = 50.0;           // LM random: translations uniform in ±extent m, angles uniform (> 0)
  RefineOptions refine;                  // refinement on f before certifying
  GlobalCertificateOptions certificate;  // the certificate
  void validate() const;
};

struct GlobalCertificateRun {
  bool failed = false;  // LM, refinement or the certificate threw (message in `error`)
  std::string error;
  double lm_cost = 0.0;  // f at keel.pgo's answer, before refinement
  int lm_iterations = 0;
  RefineReport refine;
  GlobalCertificate certificate;
  double solve_time_s = 0.0;  // keel.pgo's LM (the refinement is in refine.time_s)
};

struct GlobalCertificateOutcome {
  std::string name;
  int poses = 0, edges = 0, landmarks = 0, unknowns = 0;
  bool failed = false;  // planar_problem refused the data set (message in `error`); no run was made
  std::string error;
  GlobalCertificateRun odometry, random;
};

struct GlobalCertificateStudyOutcome {
  std::vector<GlobalCertificateOutcome> datasets;
};

// Data sets are processed one after another (each certificate is one large factorization); LM from a random
// start on data set k uses pgo seed context.streams().seed() + k.
[[nodiscard]] GlobalCertificateStudyOutcome run_global_certificate_study(
    const std::vector<GlobalCertificateDataset>& datasets, const GlobalCertificateStudyOptions& options,
    const repro::RunContext& context, core::Progress* progress = nullptr);

// Config readers of the study. Keys: lm_max_iterations, random_extent, refine_max_iterations,
// refine_gradient_tolerance, stationarity_tolerance, gap_tolerance, bound_factorizations.
[[nodiscard]] GlobalCertificateStudyOptions read_global_certificate_study_options(const core::ConfigTable& t);
// Keys: datasets (names) and a table graph_files with one key per name: the graph file (every entry of
// graph_files must be a string). Returns (name, file) pairs of the listed data sets.
[[nodiscard]] std::vector<std::pair<std::string, std::string>> read_global_certificate_files(
    const core::ConfigTable& t);
// Each file resolved by keel::datasets::resolve_dataset_file(name, file) and read by
// keel::graph::read_pose_graph_2d.
[[nodiscard]] std::vector<GlobalCertificateDataset> load_global_certificate_datasets(
    const std::vector<std::pair<std::string, std::string>>& files);

// ---------------------------------------------------------------------------------------------------------------
// Config readers (one per options struct; errors located at file, table, key and line by core::ConfigTable).

// Keys: structure, solver, sdp_gap_tolerance, gap_tolerance, escalate, escalation_max_moments,
// polish_max_iterations.
[[nodiscard]] CertifyOptions read_certify_options(const core::ConfigTable& t);

// Keys: segment_length, stride, max_segments, random_extent, lm_max_iterations, and read_certify_options's.
[[nodiscard]] SegmentStudyOptions read_segment_study_options(const core::ConfigTable& t);

// A planar data set and its ground truth: where the files are (keys dataset, graph_file, ground_truth_file
// and, for landmark data, ground_truth_landmarks_file), and the data read from them (files resolved by
// keel::datasets::resolve_dataset_file).
struct PlanarDatasetFiles {
  std::string name, graph_file, ground_truth_file, ground_truth_landmarks_file;  // the last may be empty
  std::string ground_truth_key;  // where ground_truth_file was read (for the message of a size mismatch)
  static PlanarDatasetFiles read(const core::ConfigTable& t);
};
struct PlanarDataset {
  graph::PoseGraph2D graph;
  std::vector<lie::SE2> truth;
  std::vector<lie::Vec2> truth_landmarks;
  std::string name;
};
[[nodiscard]] PlanarDataset load_planar_dataset(const PlanarDatasetFiles& files);

// Keys: families (names), one [<table>.<name>] per family with poses, edge_probability, rotation_noise (rad),
// optional rotation_noise_kind ("normal", or "uniform": rotation measurements uniform on the circle),
// translation_noise, extent, optional escalate (default true); trials (per family, one key for all);
// multistart_starts, multistart_gradient_tolerance, multistart_max_iterations, dual_bound_factorizations;
// read_certify_options's; and an optional [noise_map] table: poses (list), rotation_noise (list, rad),
// edge_probability, translation_noise, extent, expanded into one family per (poses, noise) cell named
// "map_k<poses>_s<1000·noise>" with escalation off.
[[nodiscard]] ExactnessOptions read_exactness_options(const core::ConfigTable& t,
                                                      const std::string& families_table);

}  // namespace keel::study::ch4
