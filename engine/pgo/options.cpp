#include "pgo/options.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include <ceres/types.h>

namespace keel::pgo {

namespace {

// One name table per enum: to_string and from_string read the same table, so they cannot disagree.
template <class E, std::size_t N>
using Names = std::array<std::pair<E, std::string_view>, N>;

constexpr Names<Method, 2> kMethod{{{Method::levenberg_marquardt, "levenberg_marquardt"}, {Method::dogleg, "dogleg"}}};
constexpr Names<LinearSolver, 7> kLinearSolver{{{LinearSolver::sparse_normal_cholesky, "sparse_normal_cholesky"},
                                                {LinearSolver::sparse_schur, "sparse_schur"},
                                                {LinearSolver::dense_normal_cholesky, "dense_normal_cholesky"},
                                                {LinearSolver::dense_qr, "dense_qr"},
                                                {LinearSolver::dense_schur, "dense_schur"},
                                                {LinearSolver::cgnr, "cgnr"},
                                                {LinearSolver::iterative_schur, "iterative_schur"}}};
constexpr Names<SparseLibrary, 3> kSparseLibrary{{{SparseLibrary::suite_sparse, "suite_sparse"},
                                                  {SparseLibrary::eigen_sparse, "eigen_sparse"},
                                                  {SparseLibrary::cx_sparse, "cx_sparse"}}};
constexpr Names<InitialGuess, 4> kInitialGuess{{{InitialGuess::as_read, "as_read"},
                                                {InitialGuess::odometry, "odometry"},
                                                {InitialGuess::supplied, "supplied"},
                                                {InitialGuess::random, "random"}}};
constexpr Names<RobustKernel, 4> kRobustKernel{{{RobustKernel::none, "none"},
                                                {RobustKernel::huber, "huber"},
                                                {RobustKernel::cauchy, "cauchy"},
                                                {RobustKernel::dcs, "dcs"}}};
constexpr Names<RobustScope, 3> kRobustScope{{{RobustScope::all_edges, "all_edges"},
                                              {RobustScope::loop_closures, "loop_closures"},
                                              {RobustScope::inter_robot, "inter_robot"}}};
constexpr Names<AnchorGuess, 2> kAnchorGuess{{{AnchorGuess::as_given, "as_given"},
                                              {AnchorGuess::inter_robot_edges, "inter_robot_edges"}}};
constexpr Names<Termination, 3> kTermination{{{Termination::converged, "converged"},
                                              {Termination::no_convergence, "no_convergence"},
                                              {Termination::failure, "failure"}}};

template <class E, std::size_t N>
std::string_view name_of(const Names<E, N>& names, E v) {
  for (const auto& [e, s] : names)
    if (e == v) return s;
  return "unknown";
}

template <class E, std::size_t N>
bool parse(const Names<E, N>& names, std::string_view text, E& out) {
  for (const auto& [e, s] : names)
    if (s == text) {
      out = e;
      return true;
    }
  return false;
}

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument("pgo::Options: " + what); }

}  // namespace

std::string_view to_string(Method v) { return name_of(kMethod, v); }
std::string_view to_string(LinearSolver v) { return name_of(kLinearSolver, v); }
std::string_view to_string(SparseLibrary v) { return name_of(kSparseLibrary, v); }
std::string_view to_string(InitialGuess v) { return name_of(kInitialGuess, v); }
std::string_view to_string(RobustKernel v) { return name_of(kRobustKernel, v); }
std::string_view to_string(RobustScope v) { return name_of(kRobustScope, v); }
std::string_view to_string(AnchorGuess v) { return name_of(kAnchorGuess, v); }
std::string_view to_string(Termination v) { return name_of(kTermination, v); }

bool from_string(std::string_view text, Method& out) { return parse(kMethod, text, out); }
bool from_string(std::string_view text, LinearSolver& out) { return parse(kLinearSolver, text, out); }
bool from_string(std::string_view text, SparseLibrary& out) { return parse(kSparseLibrary, text, out); }
bool from_string(std::string_view text, InitialGuess& out) { return parse(kInitialGuess, text, out); }
bool from_string(std::string_view text, RobustKernel& out) { return parse(kRobustKernel, text, out); }
bool from_string(std::string_view text, RobustScope& out) { return parse(kRobustScope, text, out); }
bool from_string(std::string_view text, AnchorGuess& out) { return parse(kAnchorGuess, text, out); }
bool from_string(std::string_view text, Termination& out) { return parse(kTermination, text, out); }

void Options::validate() const {
  if (max_iterations < 0) fail("max_iterations must be >= 0 (got " + std::to_string(max_iterations) + ")");
  if (!(max_time_s > 0.0)) fail("max_time_s must be > 0 (got " + std::to_string(max_time_s) + ")");
  if (!(function_tolerance >= 0.0)) fail("function_tolerance must be >= 0 (got " + std::to_string(function_tolerance) + ")");
  if (!(gradient_tolerance >= 0.0)) fail("gradient_tolerance must be >= 0 (got " + std::to_string(gradient_tolerance) + ")");
  if (!(parameter_tolerance >= 0.0))
    fail("parameter_tolerance must be >= 0 (got " + std::to_string(parameter_tolerance) + ")");
  if (threads < 1) fail("threads must be >= 1 (got " + std::to_string(threads) + ")");
  if (initial_guess == InitialGuess::random && !(random_extent > 0.0 && std::isfinite(random_extent)))
    fail("random_extent must be finite and > 0 for initial_guess = random (got " + std::to_string(random_extent) + ")");
  if (robust_kernel != RobustKernel::none && !(robust_parameter > 0.0 && std::isfinite(robust_parameter)))
    fail("robust_parameter must be finite and > 0 for robust_kernel = " + std::string(to_string(robust_kernel)) +
         " (got " + std::to_string(robust_parameter) + ")");
  for (int k : constant_poses)
    if (k < 0) fail("constant_poses must hold pose indices >= 0 (got " + std::to_string(k) + ")");
  if (method == Method::dogleg && (linear_solver == LinearSolver::cgnr || linear_solver == LinearSolver::iterative_schur))
    fail("method = dogleg needs a factorization-based linear_solver (got " + std::string(to_string(linear_solver)) + ")");
  const bool sparse = linear_solver == LinearSolver::sparse_normal_cholesky || linear_solver == LinearSolver::sparse_schur;
  if (sparse) {
    const ceres::SparseLinearAlgebraLibraryType lib =
        sparse_library == SparseLibrary::suite_sparse   ? ceres::SUITE_SPARSE
        : sparse_library == SparseLibrary::eigen_sparse ? ceres::EIGEN_SPARSE
                                                        : ceres::CX_SPARSE;
    if (!ceres::IsSparseLinearAlgebraLibraryTypeAvailable(lib))
      fail("sparse_library = " + std::string(to_string(sparse_library)) + " is not available in this Ceres build");
  }
}

}  // namespace keel::pgo
