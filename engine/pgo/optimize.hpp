// keel::pgo — batch maximum-likelihood pose-graph SLAM (thesis eq. 2.1; with anchors eq. 2.2).
//
// The solution minimizes  ½ Σ_e ρ_e(χ²_e),  χ²_e = r_eᵀ Ω_e r_e,  with the residuals of graph/pose_graph.hpp:
//   pose–pose edge (i, j):  E = z⁻¹ T_i⁻¹ T_j;  2D r = (x_E, y_E, wrap(θ_E)),  3D r = (t_E, Log R_E);
//   2D landmark:            r = R_iᵀ (l − t_i) − z;
//   inter-robot edge:       the pose–pose residual of Δ_a T^a_i and Δ_b T^b_j (multi_robot.hpp).
// Each residual is whitened by the Cholesky factor U of its information (Ω = UᵀU, whitened r = U r) and ρ_e
// is the robust kernel (robust.hpp) for edges in Options::robust_scope, the identity for the others. Poses in
// Options::constant_poses (and robot 0's anchor) are held constant: the gauge.
//
// Parameterization (solver side only): 2D poses are (x, y, θ) with θ wrapped on every update; 3D poses are a
// unit quaternion and a translation, updated on SO(3) × R³ (Ceres' EigenQuaternionManifold and
// EuclideanManifold<3>). The solver is Ceres 2.1 (only the .cpp files see it). Errors in the inputs (indices
// out of range, information not positive semi-definite, estimate sizes) throw std::invalid_argument naming
// the edge (and its source line); solver failures come back in Summary::termination / message.
#pragma once

#include <tuple>
#include <string>
#include <vector>

#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"
#include "pgo/multi_robot.hpp"
#include "pgo/options.hpp"
#include "core/fields.hpp"

namespace keel::pgo {

// ---------------------------------------------------------------------------------------------------------------
// Estimates (the unknowns).
struct Estimate2D {
  std::vector<lie::SE2> poses;
  std::vector<lie::Vec2> landmarks;  // world frame
};

struct Estimate3D {
  std::vector<lie::SE3> poses;
};

struct MultiRobotEstimate2D {
  std::vector<lie::SE2> anchors;   // Δ_r, the pose of robot r's local frame in the global frame
  std::vector<Estimate2D> robots;  // local poses and landmarks of each robot
};

struct MultiRobotEstimate3D {
  std::vector<lie::SE3> anchors;
  std::vector<Estimate3D> robots;
};

// Global poses Δ_r T^r_i of robot r (landmarks: Δ_r l).
[[nodiscard]] std::vector<lie::SE2> global_poses(const MultiRobotEstimate2D& estimate, int robot);
[[nodiscard]] std::vector<lie::SE3> global_poses(const MultiRobotEstimate3D& estimate, int robot);
[[nodiscard]] std::vector<lie::Vec2> global_landmarks(const MultiRobotEstimate2D& estimate, int robot);

// ---------------------------------------------------------------------------------------------------------------
// What a robust layer needs per measurement (DESIGN convention 5).
struct EdgeReport {
  double chi2 = 0.0;    // χ² = rᵀΩr at the estimate (no kernel)
  double weight = 1.0;  // ρ'(χ²): the weight the kernel gives the measurement (1 where no kernel applies)
  double scale = 1.0;   // √weight; for DCS the scaling s = min(1, 2φ/(φ + χ²)) of Agarwal et al.
  bool robust = false;  // whether the kernel applied to this measurement (RobustKernel ≠ none and in scope)
};

// One trust-region iteration (iteration 0 is the initial point).
struct IterationRecord {
  int iteration = 0;
  double cost = 0.0;               // ½ Σ ρ(χ²) after the iteration
  double cost_change = 0.0;        // decrease of the cost in this iteration
  double gradient_max_norm = 0.0;  // ‖g‖∞
  double step_norm = 0.0;          // ‖Δx‖₂
  double trust_region_radius = 0.0;
  bool step_is_successful = false;
  int linear_solver_iterations = 0;
  double iteration_time_s = 0.0;
};

struct Summary {
  Termination termination = Termination::failure;
  std::string message;        // the solver's reason for stopping
  double initial_cost = 0.0;  // ½ Σ ρ(χ²) at the initial estimate
  double final_cost = 0.0;    // ½ Σ ρ(χ²) at the solution
  double final_chi2 =
      0.0;  // Σ χ² at the solution, without the kernel (= 2·final_cost when no kernel applies)
  int residual_dimension =
      0;  // Σ of the residual sizes (3 per 2D edge, 2 per landmark measurement, 6 per 3D edge)
  int free_parameter_dimension =
      0;  // tangent dimensions of the free unknowns that appear in some residual
          // (3 per 2D pose, 2 per landmark, 6 per 3D pose or anchor; constant ones excluded)
  // Normalized χ² = 2·final_cost / (residual_dimension − free_parameter_dimension): the cost per degree of
  // freedom, ≈ 1 when the noise model is right (thesis §2.7 "Chi2"). With a robust kernel it uses the
  // robustified cost (use final_chi2 for the plain one). NaN when there are no degrees of freedom.
  double normalized_chi2 = 0.0;
  int iterations = 0;  // trust-region iterations (successful + unsuccessful steps)
  int successful_steps = 0;
  int unsuccessful_steps = 0;
  // Time in seconds: total, and the solver's phases (preprocessing, minimization, postprocessing; inside the
  // minimizer the linear solves and the residual and Jacobian evaluations).
  double total_time_s = 0.0;
  double preprocessor_time_s = 0.0;
  double minimizer_time_s = 0.0;
  double postprocessor_time_s = 0.0;
  double linear_solver_time_s = 0.0;
  double residual_evaluation_time_s = 0.0;
  double jacobian_evaluation_time_s = 0.0;
  std::vector<IterationRecord> trace;  // per-iteration record, iteration 0 first
  std::string report;                  // the solver's one-line report
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(termination, message, initial_cost, final_cost, final_chi2, residual_dimension,
              free_parameter_dimension, normalized_chi2, iterations, successful_steps, unsuccessful_steps,
              total_time_s, preprocessor_time_s, minimizer_time_s, postprocessor_time_s, linear_solver_time_s,
              residual_evaluation_time_s, jacobian_evaluation_time_s, trace, report)
};

struct Result2D {
  Summary summary;
  Estimate2D estimate;                     // solved poses and landmarks
  std::vector<EdgeReport> edges;           // one per graph.edges, same order
  std::vector<EdgeReport> landmark_edges;  // one per graph.landmark_measurements
};

struct Result3D {
  Summary summary;
  Estimate3D estimate;
  std::vector<EdgeReport> edges;
};

struct MultiRobotResult2D {
  Summary summary;
  MultiRobotEstimate2D estimate;                        // anchors and local poses/landmarks
  std::vector<std::vector<EdgeReport>> edges;           // [robot][edge]
  std::vector<std::vector<EdgeReport>> landmark_edges;  // [robot][measurement]
  std::vector<EdgeReport> inter_robot_edges;
};

struct MultiRobotResult3D {
  Summary summary;
  MultiRobotEstimate3D estimate;
  std::vector<std::vector<EdgeReport>> edges;
  std::vector<EdgeReport> inter_robot_edges;
};

// ---------------------------------------------------------------------------------------------------------------
// The initial estimate that optimize() starts from (Options::initial_guess, seed, random_extent,
// anchor_guess). The number of poses is max(graph.poses.size(), 1 + the largest pose index used); landmarks
// likewise. Landmarks come from graph.landmarks (as_read) or supplied->landmarks (supplied) when those have
// the right size, otherwise from their first measurement at the initial pose (l = T_i z). `supplied` is
// required for InitialGuess::supplied.
[[nodiscard]] Estimate2D initial_estimate(const graph::PoseGraph2D& graph, const Options& options,
                                          const Estimate2D* supplied = nullptr);
[[nodiscard]] Estimate3D initial_estimate(const graph::PoseGraph3D& graph, const Options& options,
                                          const Estimate3D* supplied = nullptr);
// Multi-robot: robot r's local estimate as above (random: stream r); anchors by Options::anchor_guess, or
// supplied->anchors under InitialGuess::supplied.
[[nodiscard]] MultiRobotEstimate2D initial_estimate(const MultiRobotGraph2D& graph, const Options& options,
                                                    const MultiRobotEstimate2D* supplied = nullptr);
[[nodiscard]] MultiRobotEstimate3D initial_estimate(const MultiRobotGraph3D& graph, const Options& options,
                                                    const MultiRobotEstimate3D* supplied = nullptr);

// One batch solve. Throws std::invalid_argument for invalid options or graphs (see above).
[[nodiscard]] Result2D optimize(const graph::PoseGraph2D& graph, const Options& options = {},
                                const Estimate2D* supplied = nullptr);
[[nodiscard]] Result3D optimize(const graph::PoseGraph3D& graph, const Options& options = {},
                                const Estimate3D* supplied = nullptr);
[[nodiscard]] MultiRobotResult2D optimize(const MultiRobotGraph2D& graph, const Options& options = {},
                                          const MultiRobotEstimate2D* supplied = nullptr);
[[nodiscard]] MultiRobotResult3D optimize(const MultiRobotGraph3D& graph, const Options& options = {},
                                          const MultiRobotEstimate3D* supplied = nullptr);

// ---------------------------------------------------------------------------------------------------------------
// The residuals and cost of a graph at a given estimate, without solving (no Ceres involved). The kernel, its
// scope and the gauge (for the degrees of freedom) are taken from `options`; everything else in it is
// ignored.
struct Evaluation {
  double cost = 0.0;           // ½ Σ ρ(χ²): what optimize() minimizes (its Summary::final_cost at a solution)
  double chi2 = 0.0;           // Σ χ² without the kernel
  int residual_dimension = 0;  // as in Summary
  int free_parameter_dimension = 0;  // as in Summary
  double normalized_chi2 = 0.0;  // 2·cost / (residual_dimension − free_parameter_dimension); NaN if ≤ 0 dof
};

struct Evaluation2D : Evaluation {
  std::vector<lie::Vec3> residuals;           // r (not whitened) per graph.edges entry
  std::vector<lie::Vec2> landmark_residuals;  // r per graph.landmark_measurements entry
  std::vector<EdgeReport> edges;
  std::vector<EdgeReport> landmark_edges;
};

struct Evaluation3D : Evaluation {
  std::vector<lie::Vec6> residuals;
  std::vector<EdgeReport> edges;
};

struct MultiRobotEvaluation2D : Evaluation {
  std::vector<Evaluation2D> robots;  // per robot (their cost/chi2 fields cover that robot's measurements)
  std::vector<lie::Vec3> inter_robot_residuals;
  std::vector<EdgeReport> inter_robot_edges;
};

struct MultiRobotEvaluation3D : Evaluation {
  std::vector<Evaluation3D> robots;
  std::vector<lie::Vec6> inter_robot_residuals;
  std::vector<EdgeReport> inter_robot_edges;
};

[[nodiscard]] Evaluation2D evaluate(const graph::PoseGraph2D& graph, const Estimate2D& at,
                                    const Options& options = {});
[[nodiscard]] Evaluation3D evaluate(const graph::PoseGraph3D& graph, const Estimate3D& at,
                                    const Options& options = {});
[[nodiscard]] MultiRobotEvaluation2D evaluate(const MultiRobotGraph2D& graph, const MultiRobotEstimate2D& at,
                                              const Options& options = {});
[[nodiscard]] MultiRobotEvaluation3D evaluate(const MultiRobotGraph3D& graph, const MultiRobotEstimate3D& at,
                                              const Options& options = {});

}  // namespace keel::pgo
