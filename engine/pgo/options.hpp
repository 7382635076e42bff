// keel::pgo — options of the batch pose-graph optimizer (DESIGN conventions 1 and 2).
//
// Every choice is an enum class with to_string / <enum>_from_string so that experiment configs round-trip;
// Options has in-class defaults, one comment per field, and validate() names the struct, the violated
// constraint and the value.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace keel::pgo {

// Trust-region strategy of the nonlinear least-squares solver.
enum class Method {
  levenberg_marquardt,  // Levenberg–Marquardt
  dogleg,               // Powell's (traditional) dogleg; needs a factorization-based linear solver
};

// Linear solver used inside each trust-region step (Ceres' names, lower case).
enum class LinearSolver {
  sparse_normal_cholesky,  // sparse Cholesky of JᵀJ (the default: pose graphs are sparse)
  sparse_schur,
  dense_normal_cholesky,
  dense_qr,
  dense_schur,
  cgnr,             // conjugate gradients on the normal equations (iterative; not with dogleg)
  iterative_schur,  // iterative; not with dogleg
};

// Sparse linear-algebra library for the sparse solvers.
enum class SparseLibrary {
  suite_sparse,  // CHOLMOD (the default)
  eigen_sparse,
  cx_sparse,  // deprecated in Ceres 2.1; usually not compiled in
};

// Where the initial estimate comes from.
enum class InitialGuess {
  as_read,   // the poses (and landmarks) stored in the graph (PoseGraph2D::poses ...)
  odometry,  // chain the odometry edges (k-1, k) from the first of constant_poses (pose 0 by default), which
             // keeps its as-read value (identity if the graph has none)
  supplied,  // an estimate passed by the caller, e.g. ground truth (the `supplied` argument of optimize)
  random,    // uniformly random poses from `seed` (deterministic); gauge poses keep their as-read values
};

// Robust kernel ρ applied to the squared whitened residual χ² of an edge (see robust.hpp).
enum class RobustKernel {
  none,    // ρ(χ²) = χ² (plain least squares)
  huber,   // Huber, parameter a: quadratic for χ² ≤ a²
  cauchy,  // Cauchy, parameter a: ρ = a² log(1 + χ²/a²)
  dcs,     // Dynamic Covariance Scaling (Agarwal et al. 2013), parameter φ
};

// Which measurements the robust kernel applies to (the others stay Gaussian).
enum class RobustScope {
  all_edges,      // every edge and landmark measurement
  loop_closures,  // everything except odometry (an intra-robot edge (i, j) with |i − j| = 1); inter-robot
                  // edges and landmark measurements count as loop closures
  inter_robot,    // only the inter-robot edges of a multi-robot graph (nothing in a single-robot graph)
};

// Initial anchors of a multi-robot graph (Kim et al. 2010).
enum class AnchorGuess {
  as_given,           // MultiRobotGraph::anchors (identity for all when that vector is empty)
  inter_robot_edges,  // robot 0 as given; every other robot from the first inter-robot edge that links it to
                      // a robot already placed (breadth-first), using the initial local poses
};

// How a solve ended.
enum class Termination {
  converged,       // a function, gradient or parameter tolerance was met
  no_convergence,  // the iteration or time limit was reached first
  failure,         // the solver failed (numerical failure, invalid values); see Summary::message
};

std::string_view to_string(Method v);
std::string_view to_string(LinearSolver v);
std::string_view to_string(SparseLibrary v);
std::string_view to_string(InitialGuess v);
std::string_view to_string(RobustKernel v);
std::string_view to_string(RobustScope v);
std::string_view to_string(AnchorGuess v);
std::string_view to_string(Termination v);

// Parse the exact names printed by to_string; anything else throws std::invalid_argument naming the type, the
// text and every valid name ("unknown pgo::Method 'lm' (valid: levenberg_marquardt, dogleg)").
[[nodiscard]] Method method_from_string(std::string_view text);
[[nodiscard]] LinearSolver linear_solver_from_string(std::string_view text);
[[nodiscard]] SparseLibrary sparse_library_from_string(std::string_view text);
[[nodiscard]] InitialGuess initial_guess_from_string(std::string_view text);
[[nodiscard]] RobustKernel robust_kernel_from_string(std::string_view text);
[[nodiscard]] RobustScope robust_scope_from_string(std::string_view text);
[[nodiscard]] AnchorGuess anchor_guess_from_string(std::string_view text);
[[nodiscard]] Termination termination_from_string(std::string_view text);

// The range of Options::robust_parameter: a² (Huber, Cauchy) and φ² stay normal doubles, so the kernels'
// values and weights are representable.
inline constexpr double kMinRobustParameter = 1e-150;
inline constexpr double kMaxRobustParameter = 1e150;

struct Options {
  Method method = Method::levenberg_marquardt;                        // trust-region strategy
  LinearSolver linear_solver = LinearSolver::sparse_normal_cholesky;  // linear solver of each step
  SparseLibrary sparse_library = SparseLibrary::suite_sparse;         // library of the sparse solvers
  int max_iterations = 100;           // maximum number of trust-region iterations (≥ 0)
  double max_time_s = 1e6;            // wall-clock limit of the minimizer in seconds (> 0)
  double function_tolerance = 1e-6;   // stop when |Δcost| / cost < this (≥ 0)
  double gradient_tolerance = 1e-10;  // stop when max|projected gradient| < this (≥ 0)
  double parameter_tolerance = 1e-8;  // stop when |Δx| < this · (|x| + this) (≥ 0)
  unsigned threads = 1;  // threads for residual/Jacobian evaluation; 0 = keel::core::default_threads().
                         // The result depends on the thread count: Ceres reduces cost and gradient
                         // per thread, so 1 and 2 threads differ in the last bits. Results are
                         // bitwise reproducible for a fixed count; keep it fixed (default 1) where
                         // result files are compared across machines or thread counts
  InitialGuess initial_guess = InitialGuess::as_read;  // source of the initial estimate
  std::uint64_t seed = 0;       // seed of InitialGuess::random (robot r draws from Rng::stream(seed, r))
  double random_extent = 10.0;  // InitialGuess::random: translations uniform in [−extent, extent] (> 0);
                                // angles uniform in (−π, π], 3D rotations uniform on SO(3)
  RobustKernel robust_kernel = RobustKernel::none;  // kernel ρ on the χ² of each edge in robust_scope
  double robust_parameter = 5.0;  // DCS φ (Agarwal et al. and thesis §2.7 use 5) or Huber/Cauchy a, in
                                  // [kMinRobustParameter, kMaxRobustParameter]
  RobustScope robust_scope = RobustScope::loop_closures;  // which measurements get the kernel
  std::vector<int> constant_poses = {0};  // pose indices held constant (gauge); in a multi-robot graph they
                                          // apply to every robot, and robot 0's anchor is always constant
  AnchorGuess anchor_guess = AnchorGuess::as_given;  // initial anchors of a multi-robot graph
  bool verbose = false;  // print the solver's per-iteration progress and its report to stdout

  // Throws std::invalid_argument naming the violated constraint (e.g. "pgo::Options: max_iterations must be
  // >= 0 (got -1)"). Constraints that depend on the graph (constant pose indices in range, supplied estimate
  // sizes) are checked by optimize().
  void validate() const;
};

}  // namespace keel::pgo
