#include "pgo/options.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <ceres/types.h>
#include <fmt/format.h>

#include "core/names.hpp"

namespace keel::pgo {

namespace {

// One name table per enum: to_string and <enum>_from_string read the same table, so they cannot disagree.
constexpr core::NameTable<Method, 2> kMethod{
    "pgo::Method", {{{Method::levenberg_marquardt, "levenberg_marquardt"}, {Method::dogleg, "dogleg"}}}};
constexpr core::NameTable<LinearSolver, 7> kLinearSolver{
    "pgo::LinearSolver",
    {{{LinearSolver::sparse_normal_cholesky, "sparse_normal_cholesky"},
      {LinearSolver::sparse_schur, "sparse_schur"},
      {LinearSolver::dense_normal_cholesky, "dense_normal_cholesky"},
      {LinearSolver::dense_qr, "dense_qr"},
      {LinearSolver::dense_schur, "dense_schur"},
      {LinearSolver::cgnr, "cgnr"},
      {LinearSolver::iterative_schur, "iterative_schur"}}}};
constexpr core::NameTable<SparseLibrary, 3> kSparseLibrary{"pgo::SparseLibrary",
                                                           {{{SparseLibrary::suite_sparse, "suite_sparse"},
                                                             {SparseLibrary::eigen_sparse, "eigen_sparse"},
                                                             {SparseLibrary::cx_sparse, "cx_sparse"}}}};
constexpr core::NameTable<InitialGuess, 4> kInitialGuess{"pgo::InitialGuess",
                                                         {{{InitialGuess::as_read, "as_read"},
                                                           {InitialGuess::odometry, "odometry"},
                                                           {InitialGuess::supplied, "supplied"},
                                                           {InitialGuess::random, "random"}}}};
constexpr core::NameTable<RobustKernel, 4> kRobustKernel{"pgo::RobustKernel",
                                                         {{{RobustKernel::none, "none"},
                                                           {RobustKernel::huber, "huber"},
                                                           {RobustKernel::cauchy, "cauchy"},
                                                           {RobustKernel::dcs, "dcs"}}}};
constexpr core::NameTable<RobustScope, 3> kRobustScope{"pgo::RobustScope",
                                                       {{{RobustScope::all_edges, "all_edges"},
                                                         {RobustScope::loop_closures, "loop_closures"},
                                                         {RobustScope::inter_robot, "inter_robot"}}}};
constexpr core::NameTable<AnchorGuess, 2> kAnchorGuess{
    "pgo::AnchorGuess",
    {{{AnchorGuess::as_given, "as_given"}, {AnchorGuess::inter_robot_edges, "inter_robot_edges"}}}};
constexpr core::NameTable<Termination, 3> kTermination{"pgo::Termination",
                                                       {{{Termination::converged, "converged"},
                                                         {Termination::no_convergence, "no_convergence"},
                                                         {Termination::failure, "failure"}}}};

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument(fmt::format("pgo::Options: {}", what));
}

}  // namespace

std::string_view to_string(Method v) { return kMethod.name(v); }
std::string_view to_string(LinearSolver v) { return kLinearSolver.name(v); }
std::string_view to_string(SparseLibrary v) { return kSparseLibrary.name(v); }
std::string_view to_string(InitialGuess v) { return kInitialGuess.name(v); }
std::string_view to_string(RobustKernel v) { return kRobustKernel.name(v); }
std::string_view to_string(RobustScope v) { return kRobustScope.name(v); }
std::string_view to_string(AnchorGuess v) { return kAnchorGuess.name(v); }
std::string_view to_string(Termination v) { return kTermination.name(v); }

Method method_from_string(std::string_view text) { return kMethod.parse(text); }
LinearSolver linear_solver_from_string(std::string_view text) { return kLinearSolver.parse(text); }
SparseLibrary sparse_library_from_string(std::string_view text) { return kSparseLibrary.parse(text); }
InitialGuess initial_guess_from_string(std::string_view text) { return kInitialGuess.parse(text); }
RobustKernel robust_kernel_from_string(std::string_view text) { return kRobustKernel.parse(text); }
RobustScope robust_scope_from_string(std::string_view text) { return kRobustScope.parse(text); }
AnchorGuess anchor_guess_from_string(std::string_view text) { return kAnchorGuess.parse(text); }
Termination termination_from_string(std::string_view text) { return kTermination.parse(text); }

void Options::validate() const {
  if (max_iterations < 0) fail(fmt::format("max_iterations must be >= 0 (got {})", max_iterations));
  if (!(max_time_s > 0.0)) fail(fmt::format("max_time_s must be > 0 (got {})", max_time_s));
  if (!(function_tolerance >= 0.0))
    fail(fmt::format("function_tolerance must be >= 0 (got {})", function_tolerance));
  if (!(gradient_tolerance >= 0.0))
    fail(fmt::format("gradient_tolerance must be >= 0 (got {})", gradient_tolerance));
  if (!(parameter_tolerance >= 0.0))
    fail(fmt::format("parameter_tolerance must be >= 0 (got {})", parameter_tolerance));
  if (initial_guess == InitialGuess::random && !(random_extent > 0.0 && std::isfinite(random_extent)))
    fail(fmt::format("random_extent must be finite and > 0 for initial_guess = random (got {})",
                     random_extent));
  if (robust_kernel != RobustKernel::none && !(robust_parameter > 0.0 && std::isfinite(robust_parameter)))
    fail(fmt::format("robust_parameter must be finite and > 0 for robust_kernel = {} (got {})",
                     to_string(robust_kernel), robust_parameter));
  // The kernels square their parameter (Huber and Cauchy b = a², DCS 2φ/(φ + χ²)): within this range b and
  // the weights are normal doubles for every χ² a graph can give, so ρ' > 0 as Ceres requires.
  if (robust_kernel != RobustKernel::none &&
      !(robust_parameter >= kMinRobustParameter && robust_parameter <= kMaxRobustParameter))
    fail(fmt::format("robust_parameter must be in [{:g}, {:g}] for robust_kernel = {} (got {})",
                     kMinRobustParameter, kMaxRobustParameter, to_string(robust_kernel), robust_parameter));
  for (int k : constant_poses)
    if (k < 0) fail(fmt::format("constant_poses must hold pose indices >= 0 (got {})", k));
  if (method == Method::dogleg &&
      (linear_solver == LinearSolver::cgnr || linear_solver == LinearSolver::iterative_schur))
    fail(fmt::format("method = dogleg needs a factorization-based linear_solver (got {})",
                     to_string(linear_solver)));
  const bool sparse =
      linear_solver == LinearSolver::sparse_normal_cholesky || linear_solver == LinearSolver::sparse_schur;
  if (sparse) {
    const ceres::SparseLinearAlgebraLibraryType lib =
        sparse_library == SparseLibrary::suite_sparse   ? ceres::SUITE_SPARSE
        : sparse_library == SparseLibrary::eigen_sparse ? ceres::EIGEN_SPARSE
                                                        : ceres::CX_SPARSE;
    if (!ceres::IsSparseLinearAlgebraLibraryTypeAvailable(lib))
      fail(
          fmt::format("sparse_library = {} is not available in this Ceres build", to_string(sparse_library)));
  }
}

}  // namespace keel::pgo
