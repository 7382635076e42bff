// optimize(): builds the Ceres problem of a (multi-robot) pose graph, solves it and reports.
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <fmt/format.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/blas.hpp"
#include "core/parallel.hpp"
#include "pgo/ceres_factors.hpp"
#include "pgo/internal.hpp"

namespace keel::pgo {

namespace detail {

namespace {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(fmt::format("pgo: {}", what)); }

template <class D>
struct ResultOf;
template <>
struct ResultOf<D2> {
  using type = MultiRobotResult2D;
  using Params = Pose2Params;
};
template <>
struct ResultOf<D3> {
  using type = MultiRobotResult3D;
  using Params = Pose3Params;
};

ceres::LinearSolverType linear_solver_of(LinearSolver v) {
  switch (v) {
    case LinearSolver::sparse_normal_cholesky:
      return ceres::SPARSE_NORMAL_CHOLESKY;
    case LinearSolver::sparse_schur:
      return ceres::SPARSE_SCHUR;
    case LinearSolver::dense_normal_cholesky:
      return ceres::DENSE_NORMAL_CHOLESKY;
    case LinearSolver::dense_qr:
      return ceres::DENSE_QR;
    case LinearSolver::dense_schur:
      return ceres::DENSE_SCHUR;
    case LinearSolver::cgnr:
      return ceres::CGNR;
    case LinearSolver::iterative_schur:
      return ceres::ITERATIVE_SCHUR;
  }
  return ceres::SPARSE_NORMAL_CHOLESKY;
}

ceres::SparseLinearAlgebraLibraryType sparse_library_of(SparseLibrary v) {
  switch (v) {
    case SparseLibrary::suite_sparse:
      return ceres::SUITE_SPARSE;
    case SparseLibrary::eigen_sparse:
      return ceres::EIGEN_SPARSE;
    case SparseLibrary::cx_sparse:
      return ceres::CX_SPARSE;
  }
  return ceres::SUITE_SPARSE;
}

Termination termination_of(ceres::TerminationType t) {
  switch (t) {
    case ceres::CONVERGENCE:
    case ceres::USER_SUCCESS:
      return Termination::converged;
    case ceres::NO_CONVERGENCE:
      return Termination::no_convergence;
    default:
      return Termination::failure;
  }
}

ceres::Solver::Options solver_options(const Options& o) {
  ceres::Solver::Options s;
  s.minimizer_type = ceres::TRUST_REGION;
  s.trust_region_strategy_type = o.method == Method::dogleg ? ceres::DOGLEG : ceres::LEVENBERG_MARQUARDT;
  s.linear_solver_type = linear_solver_of(o.linear_solver);
  s.sparse_linear_algebra_library_type = sparse_library_of(o.sparse_library);
  s.max_num_iterations = o.max_iterations;
  s.max_solver_time_in_seconds = o.max_time_s;
  s.function_tolerance = o.function_tolerance;
  s.gradient_tolerance = o.gradient_tolerance;
  s.parameter_tolerance = o.parameter_tolerance;
  s.num_threads = static_cast<int>(o.threads == 0 ? core::default_threads() : o.threads);
  s.minimizer_progress_to_stdout = o.verbose;
  s.logging_type = o.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  return s;
}

Summary summary_of(const ceres::Solver::Summary& s) {
  Summary out;
  out.termination = termination_of(s.termination_type);
  out.message = s.message;
  out.initial_cost = s.initial_cost;
  out.final_cost = s.final_cost;
  out.successful_steps = s.num_successful_steps;
  out.unsuccessful_steps = s.num_unsuccessful_steps;
  out.iterations = s.num_successful_steps + s.num_unsuccessful_steps;
  out.total_time_s = s.total_time_in_seconds;
  out.preprocessor_time_s = s.preprocessor_time_in_seconds;
  out.minimizer_time_s = s.minimizer_time_in_seconds;
  out.postprocessor_time_s = s.postprocessor_time_in_seconds;
  out.linear_solver_time_s = s.linear_solver_time_in_seconds;
  out.residual_evaluation_time_s = s.residual_evaluation_time_in_seconds;
  out.jacobian_evaluation_time_s = s.jacobian_evaluation_time_in_seconds;
  for (const auto& it : s.iterations) {
    IterationRecord r;
    r.iteration = it.iteration;
    r.cost = it.cost;
    r.cost_change = it.cost_change;
    r.gradient_max_norm = it.gradient_max_norm;
    r.step_norm = it.step_norm;
    r.trust_region_radius = it.trust_region_radius;
    r.step_is_successful = it.step_is_successful;
    r.linear_solver_iterations = it.linear_solver_iterations;
    r.iteration_time_s = it.iteration_time_in_seconds;
    out.trace.push_back(r);
  }
  out.report = s.BriefReport();
  return out;
}

template <class D>
typename ResultOf<D>::type solve_view(const RobotsView<D>& view,
                                      const std::vector<typename D::Pose>& given_anchors, const Options& o,
                                      const typename D::MultiEstimate* supplied) {
  using Params = typename ResultOf<D>::Params;
  constexpr int kAmbient = static_cast<int>(std::tuple_size_v<Params>);
  const auto init = initial_view<D>(view, given_anchors, o, supplied);  // validates options and graph
  const int robots = static_cast<int>(view.robots.size());
  for (int r = 0; r < robots; ++r) {
    const int n = static_cast<int>(init.robots[r].poses.size());
    for (int k : o.constant_poses)
      if (k >= n)
        fail(fmt::format("constant_poses: pose {} is out of range (robot {} has {} poses)", k, r, n));
  }

  // Parameter storage (stable addresses: sized once, never resized).
  std::vector<std::vector<Params>> poses(robots);
  std::vector<std::vector<std::array<double, 2>>> landmarks(robots);
  std::vector<Params> anchors(init.anchors.size());
  for (int r = 0; r < robots; ++r) {
    for (const auto& T : init.robots[r].poses) poses[r].push_back(to_params(T));
    if constexpr (D::kLandmarks)
      for (const auto& l : init.robots[r].landmarks) landmarks[r].push_back({l(0), l(1)});
  }
  for (std::size_t r = 0; r < init.anchors.size(); ++r) anchors[r] = to_params(init.anchors[r]);

  std::unique_ptr<ceres::Manifold> manifold;
  if constexpr (D::kPoseDof == 3)
    manifold = std::make_unique<Se2Manifold>();
  else
    manifold = std::make_unique<Se3Manifold>();
  std::unique_ptr<ceres::LossFunction> loss;
  if (o.robust_kernel != RobustKernel::none)
    loss = std::make_unique<KernelLoss>(o.robust_kernel, o.robust_parameter);

  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (int r = 0; r < robots; ++r) {
    for (auto& p : poses[r]) problem.AddParameterBlock(p.data(), kAmbient, manifold.get());
    for (auto& l : landmarks[r]) problem.AddParameterBlock(l.data(), 2);
  }
  if (view.with_anchors)
    for (auto& a : anchors) problem.AddParameterBlock(a.data(), kAmbient, manifold.get());

  for (int r = 0; r < robots; ++r) {
    const auto& g = *view.robots[r];
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      const auto& e = g.edges[k];
      const auto U = sqrt_information(e.information, edge_label("edge", k, e.line, g.source));
      ceres::CostFunction* cost;
      if constexpr (D::kPoseDof == 3)
        cost = new PoseEdge2Cost(e.measurement, U);
      else
        cost = make_pose_edge3(e.measurement, U);
      problem.AddResidualBlock(cost, robust_edge(o, e.i, e.j) ? loss.get() : nullptr, poses[r][e.i].data(),
                               poses[r][e.j].data());
    }
    if constexpr (D::kLandmarks) {
      for (std::size_t k = 0; k < g.landmark_measurements.size(); ++k) {
        const auto& m = g.landmark_measurements[k];
        const auto U =
            sqrt_information(m.information, edge_label("landmark measurement", k, m.line, g.source));
        problem.AddResidualBlock(new Landmark2Cost(m.position, U), robust_landmark(o) ? loss.get() : nullptr,
                                 poses[r][m.pose].data(), landmarks[r][m.landmark].data());
      }
    }
  }
  if (view.inter) {
    for (std::size_t k = 0; k < view.inter->size(); ++k) {
      const auto& e = (*view.inter)[k];
      const auto U = sqrt_information(e.information, edge_label("inter-robot edge", k, e.line, ""));
      ceres::CostFunction* cost;
      if constexpr (D::kPoseDof == 3)
        cost = make_inter_robot2(e.measurement, U);
      else
        cost = make_inter_robot3(e.measurement, U);
      problem.AddResidualBlock(cost, robust_inter_robot(o) ? loss.get() : nullptr, anchors[e.robot_a].data(),
                               poses[e.robot_a][e.pose_a].data(), anchors[e.robot_b].data(),
                               poses[e.robot_b][e.pose_b].data());
    }
  }
  // Gauge.
  for (int r = 0; r < robots; ++r)
    for (int k : o.constant_poses) problem.SetParameterBlockConstant(poses[r][k].data());
  if (view.with_anchors && !anchors.empty()) problem.SetParameterBlockConstant(anchors[0].data());

  ceres::Solver::Summary cs;
  {
    // CHOLMOD's supernodal factorizations inside Ceres call the BLAS: on one BLAS thread and without
    // CHOLMOD's OpenMP teams, as the certified solver (core/blas.hpp); Options::threads is Ceres's own.
    const core::SingleThreadedBlas one_blas_thread;
    const core::SerialOpenMp serial_openmp;
    ceres::Solve(solver_options(o), &problem, &cs);
  }
  if (o.verbose) fmt::print("{}\n", cs.FullReport());

  typename ResultOf<D>::type result;
  result.summary = summary_of(cs);
  auto& est = result.estimate;
  est.robots.resize(robots);
  for (int r = 0; r < robots; ++r) {
    for (const auto& p : poses[r]) est.robots[r].poses.push_back(from_params(p));
    if constexpr (D::kLandmarks)
      for (const auto& l : landmarks[r]) est.robots[r].landmarks.emplace_back(l[0], l[1]);
  }
  for (const auto& a : anchors) est.anchors.push_back(from_params(a));

  // Reports at the solution (the same residual definitions, evaluated without Ceres).
  auto ev = evaluate_view<D>(view, est, o);
  result.summary.final_chi2 = ev.chi2;
  result.summary.residual_dimension = ev.residual_dimension;
  result.summary.free_parameter_dimension = ev.free_parameter_dimension;
  result.summary.normalized_chi2 =
      normalized_chi2(result.summary.final_cost, ev.residual_dimension, ev.free_parameter_dimension);
  for (auto& rev : ev.robots) {
    result.edges.push_back(std::move(rev.edges));
    if constexpr (D::kLandmarks) result.landmark_edges.push_back(std::move(rev.landmark_edges));
  }
  result.inter_robot_edges = std::move(ev.inter_robot_edges);
  return result;
}

}  // namespace

}  // namespace detail

Result2D optimize(const graph::PoseGraph2D& graph, const Options& options, const Estimate2D* supplied) {
  MultiRobotEstimate2D m;
  if (supplied) m.robots.push_back(*supplied);
  auto mr = detail::solve_view<detail::D2>(detail::view_of(graph), {}, options, supplied ? &m : nullptr);
  Result2D r;
  r.summary = std::move(mr.summary);
  r.estimate = std::move(mr.estimate.robots[0]);
  r.edges = std::move(mr.edges[0]);
  r.landmark_edges = std::move(mr.landmark_edges[0]);
  return r;
}

Result3D optimize(const graph::PoseGraph3D& graph, const Options& options, const Estimate3D* supplied) {
  MultiRobotEstimate3D m;
  if (supplied) m.robots.push_back(*supplied);
  auto mr = detail::solve_view<detail::D3>(detail::view_of(graph), {}, options, supplied ? &m : nullptr);
  Result3D r;
  r.summary = std::move(mr.summary);
  r.estimate = std::move(mr.estimate.robots[0]);
  r.edges = std::move(mr.edges[0]);
  return r;
}

MultiRobotResult2D optimize(const MultiRobotGraph2D& graph, const Options& options,
                            const MultiRobotEstimate2D* supplied) {
  return detail::solve_view<detail::D2>(detail::view_of(graph), graph.anchors, options, supplied);
}

MultiRobotResult3D optimize(const MultiRobotGraph3D& graph, const Options& options,
                            const MultiRobotEstimate3D* supplied) {
  return detail::solve_view<detail::D3>(detail::view_of(graph), graph.anchors, options, supplied);
}

}  // namespace keel::pgo
