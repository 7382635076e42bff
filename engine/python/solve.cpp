// keel Python module — batch solve (keel::pgo) and joint marginal covariances (keel::cov).
#include <fmt/format.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "app/marginals.hpp"
#include "app/records.hpp"
#include "app/robust.hpp"
#include "app/solve.hpp"
#include "bindings.hpp"
#include "candidates.hpp"
#include "cov/marginal_covariance.hpp"
#include "pgo/optimize.hpp"

namespace keel::python {

namespace {

using graph::PoseGraph2D;
using graph::PoseGraph3D;

struct SolveResult {
  py::object graph;  // a Graph2D / Graph3D: the input with the solution as its poses
  Array poses;
  pgo::Summary summary;
  Array edge_chi2;     // per edge, χ² = rᵀΩr at the solution
  Array edge_weights;  // per edge, the kernel's weight ρ'(χ²)
  double solve_time_s = 0.0;
};

// The back end of `keel solve` (app::MaximumLikelihood); an array as `init` is a supplied initial guess.
app::MaximumLikelihood likelihood_backend(const py::object& init, const std::string& robust,
                                          double robust_param, std::uint64_t seed, unsigned threads,
                                          int max_iterations) {
  app::MaximumLikelihood b;
  auto& o = b.options;
  o.initial_guess = py::isinstance<py::str>(init) ? app::initial_guess_from_name(init.cast<std::string>())
                                                  : pgo::InitialGuess::supplied;
  o.robust_kernel = pgo::robust_kernel_from_string(robust);
  o.robust_parameter = robust_param;
  o.seed = seed;
  o.threads = threads;
  o.max_iterations = max_iterations;
  b.validate();  // invalid names and values raise ValueError before any work
  return b;
}

Array edge_field(const std::vector<pgo::EdgeReport>& edges, double pgo::EdgeReport::* field) {
  Array out(static_cast<py::ssize_t>(edges.size()));
  auto w = out.mutable_unchecked<1>();
  for (std::size_t k = 0; k < edges.size(); ++k) w(k) = edges[k].*field;
  return out;
}

template <class Graph, class Estimate>
SolveResult solve_graph(const Graph& g, const app::MaximumLikelihood& o,
                        const std::optional<Estimate>& supplied) {
  std::optional<app::Solution<Graph>> r;
  {
    py::gil_scoped_release release;
    r = app::solve(g, o, supplied ? &*supplied : nullptr);
  }
  SolveResult out;
  out.poses = poses_to_array(r->graph.poses);
  // A solution or cost of NaN / infinity (finite inputs that overflow) is an error, not a result.
  check_finite_result(out.poses.data(), static_cast<std::size_t>(out.poses.size()), "solve", "the solution");
  check_finite_result(&r->summary.final_cost, 1, "solve", "the final cost");
  out.summary = r->summary;
  out.edge_chi2 = edge_field(r->edges, &pgo::EdgeReport::chi2);
  out.edge_weights = edge_field(r->edges, &pgo::EdgeReport::weight);
  out.solve_time_s = r->solve_time_s;
  out.graph = py::cast(std::move(r->graph));
  return out;
}

// ---- certified solve (pgo::solve_certified through app::solve_certified)
struct CertifiedSolveResult {
  py::object graph;  // the input with the certified estimate as its poses
  Array poses;
  pgo::CertifiedSummary summary;
  double anisotropic_cost = 0.0;
  double solve_time_s = 0.0;
};

template <class Graph>
CertifiedSolveResult certify_graph(const Graph& g, const app::Certified& o) {
  std::optional<app::CertifiedSolution<Graph>> r;
  {
    py::gil_scoped_release release;
    r = app::solve_certified(g, o);
  }
  CertifiedSolveResult out;
  out.poses = poses_to_array(r->graph.poses);
  check_finite_result(out.poses.data(), static_cast<std::size_t>(out.poses.size()), "solve (certify)",
                      "the estimate");
  check_finite_result(&r->summary.final_cost, 1, "solve (certify)", "the cost F");
  out.summary = r->summary;
  out.anisotropic_cost = r->anisotropic_cost;
  out.solve_time_s = r->solve_time_s;
  out.graph = py::cast(std::move(r->graph));
  return out;
}

py::object finite_or_none(double x) {
  return std::isfinite(x) ? py::object(py::float_(x)) : py::object(py::none());
}

// app's records (app/records.hpp) as dicts: the field list `keel solve --json` walks too.
class DictWriter final : public app::FieldWriter {
 public:
  explicit DictWriter(py::dict& out) : out_(out) {}
  void null(std::string_view name) override { out_[key(name)] = py::none(); }
  void boolean(std::string_view name, bool v) override { out_[key(name)] = py::bool_(v); }
  void integer(std::string_view name, std::int64_t v) override { out_[key(name)] = py::int_(v); }
  void text(std::string_view name, std::string_view v) override { out_[key(name)] = py::str(std::string(v)); }
  void record(std::string_view name, const std::function<void(app::FieldWriter&)>& fill) override {
    py::dict r;
    DictWriter w(r);
    fill(w);
    out_[key(name)] = r;
  }
  void records(std::string_view name, std::size_t n,
               const std::function<void(std::size_t, app::FieldWriter&)>& fill) override {
    py::list list;
    for (std::size_t k = 0; k < n; ++k) {
      py::dict r;
      DictWriter w(r);
      fill(k, w);
      list.append(r);
    }
    out_[key(name)] = list;
  }

 protected:
  void finite_number(std::string_view name, double v) override { out_[key(name)] = py::float_(v); }

 private:
  static py::str key(std::string_view name) { return py::str(std::string(name)); }
  py::dict& out_;
};

template <class Summary>
py::dict record_dict(const Summary& s) {
  py::dict d;
  DictWriter w(d);
  app::write_record(s, w);
  return d;
}

// ---- marginal covariances
// -------------------------------------------------------------------------------------

cov::CovarianceOptions covariance_options(const std::string& ordering, const std::string& extraction) {
  cov::CovarianceOptions o;
  o.ordering = cov::ordering_from_string(ordering);
  o.extraction = cov::extraction_from_string(extraction);
  o.validate();
  return o;
}

void check_pose_count(std::size_t given, std::size_t graph) {
  if (given != graph)
    throw std::invalid_argument(
        fmt::format("marginals: poses has {} rows but the graph has {} poses", given, graph));
}

// The graph (2D or 3D) at `poses` (default: the graph's own estimate), factorized (app::factorize).
std::unique_ptr<cov::MarginalCovariance> make_marginals(const py::object& g, const py::object& poses,
                                                        const cov::CovarianceOptions& options) {
  if (py::isinstance<PoseGraph2D>(g)) {
    const auto& graph = g.cast<const PoseGraph2D&>();
    pgo::Estimate2D at{poses.is_none() ? graph.poses : poses2_from_array(poses, "marginals (poses)"),
                       graph.landmarks};
    check_pose_count(at.poses.size(), graph.poses.size());
    py::gil_scoped_release release;
    return std::make_unique<cov::MarginalCovariance>(app::factorize(graph, at, options));
  }
  if (py::isinstance<PoseGraph3D>(g)) {
    const auto& graph = g.cast<const PoseGraph3D&>();
    pgo::Estimate3D at{poses.is_none() ? graph.poses : poses3_from_array(poses, "marginals (poses)")};
    check_pose_count(at.poses.size(), graph.poses.size());
    py::gil_scoped_release release;
    return std::make_unique<cov::MarginalCovariance>(app::factorize(graph, at, options));
  }
  throw py::type_error("marginals: graph must be a keel.Graph2D or keel.Graph3D");
}

// (m, 6, 6) for 2D, (m, 12, 12) for 3D, handed to numpy without a copy (matrices_as_array).
// NaN or infinity in a covariance (poses or information that overflow double precision) raises
// NonFiniteResult naming the pair.
template <class Query>
py::array pairs_as_array(const Query& query) {
  decltype(query()) out;
  {
    py::gil_scoped_release release;
    out = query();
  }
  for (std::size_t k = 0; k < out.size(); ++k)
    check_finite_result(out[k].data(), static_cast<std::size_t>(out[k].size()), "marginals",
                        fmt::format("the covariance of pairs[{}]", k));
  return matrices_as_array(std::move(out));
}

py::array pair_query(const cov::MarginalCovariance& mc, const py::object& pairs_obj, unsigned threads) {
  // Ids outside the graph raise IndexError here, before the engine's own check (a ValueError).
  const auto pairs = pairs_from_object(pairs_obj, "marginals", mc.num_poses());
  if (mc.num_poses() > 0 && mc.variable_dim(0) == 6)
    return pairs_as_array([&] { return cov::pair_marginals_3d(mc, pairs, threads); });
  return pairs_as_array([&] { return cov::pair_marginals_2d(mc, pairs, threads); });
}

// Variable ids (poses, then 2D landmarks): integers (TypeError otherwise), a 1-D sequence (ValueError),
// each within the factorization (IndexError: ids_from_object for negative ones, the engine's check for the
// rest).
std::vector<int> variable_ids(const py::object& o, const std::string& who) {
  Ids ids = ids_from_object(o, who, "ids", -1, "variable id");
  if (ids.shape.size() != 1)
    throw std::invalid_argument(fmt::format(
        "{}: ids must be a 1-D sequence of variable ids (got {} dimensions)", who, ids.shape.size()));
  return std::move(ids.values);
}

Array ids_query(const cov::MarginalCovariance& mc, const std::vector<int>& ids) {
  lie::MatX out;
  {
    py::gil_scoped_release release;
    out = mc.joint(ids);
  }
  check_finite_result(out.data(), static_cast<std::size_t>(out.size()), "marginals",
                      "the joint covariance of ids");
  return matrix_to_array(out);
}

const char* kMarginalsDoc = R"doc(
Joint marginal covariances of poses of a graph in the Lie algebra of the LEFT perturbation T = exp(xi^) T_bar
(thesis eq. 5.14; the joint Sigma_1:n of eq. 5.28 taken from a MAP solution, section 5.8.2), from the sparse
information matrix H = sum A^T Omega A linearized at `poses` (default: the graph's poses), gauge = the graph's
gauge_pose fixed (pose 0 unless set or read from a g2o FIX line; its covariance and cross-covariances are zero),
factorized once with CHOLMOD (default options: CHOLMOD's
ordering, supernodal, forward extraction).

Exactly one of:
  pairs  (m, 2) ints or a list of (i, j): 2D -> (m, 6, 6) joint covariances [S_ii S_ij; S_ji S_jj]
         (cov::pair_marginals_2d); 3D -> (m, 12, 12) (cov::pair_marginals_3d). `threads` spreads the
         work; the result does not depend on it.
  ids    a list of pose ids (repeats allowed): the (d k, d k) joint covariance, blocks in the order given.
Ids must be integers (an integer dtype or Python ints: a float array raises TypeError, nothing is truncated);
an id out of range raises IndexError, one beyond the C++ int range OverflowError; `poses` with another number
of rows than the graph raises ValueError; a graph that is not connected to pose 0 raises RuntimeError naming the
variable where the factorization broke down; a covariance holding NaN or infinity (e.g. poses of 1e308, whose
Jacobians overflow) raises FloatingPointError (an ArithmeticError) instead of being returned.)doc";

}  // namespace

void bind_solve(py::module_& m) {
  py::class_<SolveResult>(m, "SolveResult", R"doc(
The result of keel.solve: the solution, and the solver's summary (pgo::Summary). Costs follow Ceres'
convention: cost = 1/2 sum rho(chi2_e), chi2_e = r_e^T Omega_e r_e.)doc")
      .def_readonly("poses", &SolveResult::poses, "The solution: (n, 3) [x, y, theta] or (n, 7) [t, q].")
      .def_readonly("graph", &SolveResult::graph, "A copy of the input graph with the solution as its poses.")
      .def_property_readonly(
          "cost", [](const SolveResult& r) { return r.summary.final_cost; },
          "1/2 sum rho(chi2) at the solution.")
      .def_property_readonly(
          "initial_cost", [](const SolveResult& r) { return r.summary.initial_cost; },
          "1/2 sum rho(chi2) at the initial estimate.")
      .def_property_readonly(
          "chi2", [](const SolveResult& r) { return r.summary.final_chi2; },
          "sum chi2 at the solution without the kernel (= 2 cost when no kernel applies).")
      .def_property_readonly(
          "normalized_chi2", [](const SolveResult& r) { return r.summary.normalized_chi2; },
          "2 cost / (residual dimension - free parameter dimension): ~1 when the noise model is right "
          "(thesis "
          "section 2.7 'Chi2'); NaN without degrees of freedom.")
      .def_property_readonly(
          "residual_dimension", [](const SolveResult& r) { return r.summary.residual_dimension; },
          "Sum of the residual sizes.")
      .def_property_readonly(
          "free_parameter_dimension", [](const SolveResult& r) { return r.summary.free_parameter_dimension; },
          "Tangent dimensions of the free unknowns.")
      .def_property_readonly(
          "iterations", [](const SolveResult& r) { return r.summary.iterations; },
          "Trust-region iterations (successful + unsuccessful steps).")
      .def_property_readonly(
          "successful_steps", [](const SolveResult& r) { return r.summary.successful_steps; },
          "Accepted steps.")
      .def_property_readonly(
          "termination",
          [](const SolveResult& r) { return std::string(pgo::to_string(r.summary.termination)); },
          "'converged', 'no_convergence' or 'failure' (pgo::Termination).")
      .def_property_readonly(
          "message", [](const SolveResult& r) { return r.summary.message; },
          "The solver's reason for stopping.")
      .def_property_readonly(
          "report", [](const SolveResult& r) { return r.summary.report; }, "The solver's one-line report.")
      .def_property_readonly(
          "summary", [](const SolveResult& r) { return record_dict(r.summary); },
          "The solver's summary as a dict, the fields of `keel solve --json`'s \"summary\" "
          "(app/records.hpp): termination, message, initial_cost, final_cost, final_chi2, normalized_chi2 "
          "(None without degrees of freedom), residual_dimension, free_parameter_dimension, iterations, "
          "successful_steps, total_time_s, linear_solver_time_s, jacobian_evaluation_time_s.")
      .def_readonly("solve_time_s", &SolveResult::solve_time_s,
                    "Wall time of pgo::optimize in seconds (initial estimate, problem set-up and solve).")
      .def_property_readonly(
          "solver_time_s", [](const SolveResult& r) { return r.summary.total_time_s; },
          "The solver's own total time in seconds (Summary::total_time_s).")
      .def_property_readonly(
          "linear_solver_time_s", [](const SolveResult& r) { return r.summary.linear_solver_time_s; },
          "Time in the linear solves, seconds.")
      .def_property_readonly(
          "jacobian_evaluation_time_s",
          [](const SolveResult& r) { return r.summary.jacobian_evaluation_time_s; },
          "Time evaluating residuals and Jacobians, seconds.")
      .def_readonly("edge_chi2", &SolveResult::edge_chi2,
                    "(m,) chi2 = r^T Omega r of each edge at the solution.")
      .def_readonly("edge_weights", &SolveResult::edge_weights,
                    "(m,) weight rho'(chi2) the kernel gives each edge (1 where no kernel applies).")
      .def("__repr__", [](const SolveResult& r) {
        return fmt::format("SolveResult(termination='{}', cost={:.17g}, iterations={})",
                           pgo::to_string(r.summary.termination), r.summary.final_cost, r.summary.iterations);
      });

  py::class_<CertifiedSolveResult>(m, "CertifiedSolveResult", R"doc(
The result of keel.solve(..., certify=True) (pgo::solve_certified): the estimate of the isotropic (chordal)
problem sum kappa ||R_j - R_i R_ij||_F^2 + tau ||t_j - t_i - R_i t_ij||^2 (SE-Sync's, with its kappa and tau from
each edge's information) and its certificate: a lower bound on the global minimum that survives rounding.)doc")
      .def_readonly("poses", &CertifiedSolveResult::poses,
                    "The estimate: (n, 3) [x, y, theta] or (n, 7) [t, q].")
      .def_readonly("graph", &CertifiedSolveResult::graph,
                    "A copy of the input graph with the estimate as its poses.")
      .def_property_readonly(
          "cost", [](const CertifiedSolveResult& r) { return r.summary.final_cost; },
          "The isotropic cost F at the estimate (the certificate's upper bound).")
      .def_property_readonly(
          "initial_cost", [](const CertifiedSolveResult& r) { return r.summary.initial_cost; },
          "F at the chordal initialization.")
      .def_property_readonly(
          "anisotropic_cost",
          [](const CertifiedSolveResult& r) { return finite_or_none(r.anisotropic_cost); },
          "1/2 sum r^T Omega r (what keel.solve minimizes without certify) at the estimate; None when some "
          "information matrix is not positive definite.")
      .def_property_readonly(
          "certified", [](const CertifiedSolveResult& r) { return r.summary.certificate.certified; },
          "True when the relative gap between cost and the proven lower bound is within gap_tolerance.")
      .def_property_readonly(
          "certificate", [](const CertifiedSolveResult& r) { return record_dict(r.summary); },
          "The certified solve's record as a dict, the fields of `keel solve --certify --json`'s "
          "\"certificate\" (app/records.hpp): termination, status, message (why the solve stopped), problem, "
          "dimension, poses, edges, initial_cost, final_cost, certified, proven (a proof stands behind "
          "lower_bound), lower_bound (rounded down), upper_bound (F, rounded up), relative_gap (rounded up; "
          "set "
          "by the shift chosen from the gap tolerance), dual_gap ((F - tr Lambda) / F, rounded up), "
          "lambda_min_lower_bound (S + eta D >= 0 proven: lambda_min over the rotations >= -eta), shift "
          "(eta), "
          "proof_rank (rank of the point whose multipliers were proven), rounding_margin (mu of the scaled "
          "matrix), residual (the bound on the factor's residual that mu cleared), worst_case_residual "
          "(Higham's bound for the same factor), formation_error, extended_precision (the proof needed a "
          "double-double factor) -- each of these None when nothing was proven --, tolerance_shift (eta* of "
          "the "
          "gap tolerance), trace_lambda, failed_attempts (None, or a dict {proven: False, "
          "largest_failed_shift, attempts}: what failed, not a bound), proof_message (the proof, or what "
          "failed), order (of S), bound_from_staircase and returned_point (when the bound comes from a "
          "staircase point: the returned estimate's own test, {proven, lower_bound, message, "
          "failed_attempts}), final_rank, staircase, iterations, factorizations, cg_steps, tcg_iterations, "
          "ordering, times_s. A number that is not finite is None.")
      .def_property_readonly(
          "termination",
          [](const CertifiedSolveResult& r) { return std::string(pgo::to_string(r.summary.termination)); },
          "'certified', 'rank_limit' or 'not_certified' (pgo::CertifiedTermination).")
      .def_property_readonly(
          "message", [](const CertifiedSolveResult& r) { return r.summary.message; }, "Why it stopped.")
      .def_property_readonly(
          "problem", [](const CertifiedSolveResult& r) { return r.summary.problem; },
          "The problem solved, in words.")
      .def_property_readonly(
          "rank", [](const CertifiedSolveResult& r) { return r.summary.final_rank; },
          "The staircase's last rank before rounding.")
      .def_property_readonly(
          "staircase",
          [](const CertifiedSolveResult& r) { return py::list(record_dict(r.summary)["staircase"]); },
          "One dict per rank of the Riemannian staircase.")
      .def_property_readonly(
          "iterations", [](const CertifiedSolveResult& r) { return r.summary.iterations; },
          "Newton iterations over all ranks.")
      .def_property_readonly(
          "factorizations", [](const CertifiedSolveResult& r) { return r.summary.factorizations; },
          "Numeric factorizations of the Newton systems over all ranks.")
      .def_property_readonly(
          "cg_steps", [](const CertifiedSolveResult& r) { return r.summary.cg_steps; },
          "Newton steps solved by conjugate gradients preconditioned with an earlier factor.")
      .def_property_readonly(
          "tcg_iterations", [](const CertifiedSolveResult& r) { return r.summary.tcg_iterations; },
          "Steihaug-Toint CG iterations of the trust-region steps (an indefinite Hessian; ranks above d).")
      .def_property_readonly(
          "times", [](const CertifiedSolveResult& r) { return py::dict(record_dict(r.summary)["times_s"]); },
          "Seconds per stage.")
      .def_readonly("solve_time_s", &CertifiedSolveResult::solve_time_s, "Wall time of the solve in seconds.")
      .def("__repr__", [](const CertifiedSolveResult& r) {
        return fmt::format(
            "CertifiedSolveResult(termination='{}', cost={:.17g}, lower_bound={:.17g}, rank={})",
            pgo::to_string(r.summary.termination), r.summary.final_cost, r.summary.certificate.bound.lower,
            r.summary.final_rank);
      });

  m.def(
      "solve",
      [](const py::object& g, const py::object& init, const std::string& robust, double robust_param,
         const py::object& seed_obj, const py::object& threads_obj, const py::object& max_iterations_obj,
         bool certify, double gap_tolerance, const py::object& max_rank_obj,
         const std::optional<double>& time_limit_s, double staircase_stationarity,
         double staircase_relative_decrease, const std::string& preconditioner) -> py::object {
        // Integers named in errors (TypeError for a float or a bool, OverflowError beyond the C++ type).
        const std::uint64_t seed = uint_arg(seed_obj, "solve", "seed", UINT64_MAX);
        const auto threads = static_cast<unsigned>(uint_arg(threads_obj, "solve", "threads", UINT_MAX));
        const int max_iterations = int_arg(max_iterations_obj, "solve", "max_iterations");
        const int max_rank = int_arg(max_rank_obj, "solve", "max_rank");
        // An argument of the other mode would be ignored silently (as `keel solve` refuses such an option):
        // one that differs from its default is a ValueError naming it.
        const pgo::Options ml_defaults = app::MaximumLikelihood{}.options;
        const pgo::CertifiedOptions certified_defaults = app::Certified{}.options;
        if (certify) {
          // The defaults by name, from the back end's own defaults.
          const bool init_default = py::isinstance<py::str>(init) &&
                                    init.cast<std::string>() == pgo::to_string(ml_defaults.initial_guess);
          for (const auto& [name, given] :
               {std::pair{"init", !init_default},
                std::pair{"robust", robust != pgo::to_string(ml_defaults.robust_kernel)},
                std::pair{"robust_param", robust_param != ml_defaults.robust_parameter},
                std::pair{"seed", seed != ml_defaults.seed},
                std::pair{"threads", threads != ml_defaults.threads},
                std::pair{"max_iterations", max_iterations != ml_defaults.max_iterations}})
            if (given)
              throw py::value_error(fmt::format(
                  "solve: {} does not apply with certify=True (the certified solve starts from the chordal "
                  "initialization, has no robust kernel and runs on one thread)",
                  name));
        } else {
          for (const auto& [name, given] :
               {std::pair{"gap_tolerance", gap_tolerance != certified_defaults.gap_tolerance},
                std::pair{"max_rank", max_rank != certified_defaults.max_rank},
                std::pair{"time_limit_s", time_limit_s.has_value()},
                std::pair{"staircase_stationarity",
                          staircase_stationarity != certified_defaults.staircase_stationarity},
                std::pair{"staircase_relative_decrease",
                          staircase_relative_decrease != certified_defaults.staircase_relative_decrease},
                std::pair{"preconditioner",
                          preconditioner != pgo::to_string(certified_defaults.preconditioner)}})
            if (given)
              throw py::value_error(fmt::format(
                  "solve: {} applies only with certify=True (the anisotropic solve has no gap, rank or time "
                  "limit)",
                  name));
        }
        if (certify) {
          app::Certified o;
          o.options.gap_tolerance = gap_tolerance;
          o.options.max_rank = max_rank;
          o.options.staircase_stationarity = staircase_stationarity;
          o.options.staircase_relative_decrease = staircase_relative_decrease;
          try {
            o.options.preconditioner = pgo::trust_region_preconditioner_from_string(preconditioner);
          } catch (const std::invalid_argument& e) {
            throw py::value_error(fmt::format("solve: preconditioner: {}", e.what()));
          }
          if (time_limit_s) {
            if (!(*time_limit_s > 0.0) || std::isinf(*time_limit_s))
              throw py::value_error(fmt::format(
                  "solve: time_limit_s must be a finite number of seconds > 0, or None for no limit (got {})",
                  *time_limit_s));
            o.options.time_limit_s = *time_limit_s;
          }
          o.validate();  // ValueError before any work
          if (py::isinstance<PoseGraph2D>(g)) return py::cast(certify_graph(g.cast<const PoseGraph2D&>(), o));
          if (py::isinstance<PoseGraph3D>(g)) return py::cast(certify_graph(g.cast<const PoseGraph3D&>(), o));
          throw py::type_error("solve: graph must be a keel.Graph2D or keel.Graph3D");
        }
        const app::MaximumLikelihood o =
            likelihood_backend(init, robust, robust_param, seed, threads, max_iterations);
        const bool supplied = !py::isinstance<py::str>(init);
        if (py::isinstance<PoseGraph2D>(g)) {
          std::optional<pgo::Estimate2D> est;
          if (supplied) est = pgo::Estimate2D{poses2_from_array(init, "solve (init)"), {}};
          return py::cast(solve_graph(g.cast<const PoseGraph2D&>(), o, est));
        }
        if (py::isinstance<PoseGraph3D>(g)) {
          std::optional<pgo::Estimate3D> est;
          if (supplied) est = pgo::Estimate3D{poses3_from_array(init, "solve (init)")};
          return py::cast(solve_graph(g.cast<const PoseGraph3D&>(), o, est));
        }
        throw py::type_error("solve: graph must be a keel.Graph2D or keel.Graph3D");
      },
      py::arg("graph"), py::arg("init") = "odometry", py::arg("robust") = "none",
      py::arg("robust_param") = 5.0, py::arg("seed") = 0, py::arg("threads") = 1,
      py::arg("max_iterations") = 100, py::arg("certify") = false, py::arg("gap_tolerance") = 1e-6,
      py::arg("max_rank") = 10, py::arg("time_limit_s") = py::none(),
      py::arg("staircase_stationarity") = pgo::CertifiedOptions{}.staircase_stationarity,
      py::arg("staircase_relative_decrease") = pgo::CertifiedOptions{}.staircase_relative_decrease,
      py::arg("preconditioner") = std::string(pgo::to_string(pgo::CertifiedOptions{}.preconditioner)), R"doc(
Batch maximum-likelihood pose-graph solve (keel::pgo::optimize; thesis eq. 2.1): Levenberg-Marquardt with
sparse normal Cholesky (CHOLMOD), the graph's gauge_pose (0 by default) held constant at its given value
(certify=True moves its estimate rigidly so that this pose keeps its value). The options are pgo's defaults
with ONLY these set,
exactly as the CLI `keel solve` does (same inputs give bit-identical results):
  init            initial guess: 'odometry' (chain the odometry edges from the gauge pose), 'as_read' (or
                  'as-read':
                  the graph's poses), 'random' (uniform from `seed`), or an (n, 3) / (n, 7) array of poses
                  (InitialGuess::supplied). Unknown text raises ValueError "unknown pgo::InitialGuess ...".
  robust          kernel on the loop closures: 'none', 'huber', 'cauchy', 'dcs' (pgo::RobustKernel)
  robust_param    Huber/Cauchy a or DCS phi (> 0)
  seed            seed of init='random'
  threads         Ceres threads for residuals/Jacobians (0 = all); results differ in the last bits between
                  thread counts (Ceres reduces per thread), so keep it fixed where results are compared
  max_iterations  trust-region iterations (>= 0)
Returns a SolveResult. Graphs with inconsistent edges raise ValueError naming the edge; a solver failure is
reported in SolveResult.termination / message, not raised, but a solution or cost holding NaN or infinity
(inputs that overflow double precision) raises FloatingPointError (an ArithmeticError).

certify=True solves the isotropic (chordal) model instead, as `keel solve --certify` does
(pgo::solve_certified: chordal initialization, Newton on the Burer-Monteiro lift, the Riemannian staircase up
to `max_rank`, a certificate with a rounding-error margin, certified when the relative gap is within
`gap_tolerance`; `time_limit_s` seconds of wall time, None for no limit: at the limit the point reached and its
rounding are tested and termination is 'time_limit'; `staircase_stationarity`: above rank d each rank is first solved
until |grad|.|X| <= this x max(F, 1) and solved on only where its rounded answer could still be certified, 0 for every
rank to the full tolerance, as `--staircase-stationarity`; `staircase_relative_decrease`: such a loose solve also
stops at a trust-region step that lowers F by less than this x F, 0 for off, as `--staircase-relative-decrease`; `preconditioner`: the trust-region steps' preconditioner above rank d,
'auto', 'joint' or 'reduced', as `--preconditioner`); init, robust, robust_param, seed, threads and max_iterations do
not apply (ValueError when one differs from its default; likewise gap_tolerance, max_rank, time_limit_s,
staircase_stationarity, staircase_relative_decrease and preconditioner without certify=True). Returns a
CertifiedSolveResult. A disconnected graph or an edge whose isotropic weights are not positive raises
ValueError.)doc");

  m.def(
      "robust",
      [](const py::object& graphs, const py::object& candidates, double p, const std::string& composition,
         const std::string& selector, int exact_up_to, double residual_p, const std::string& residual_test,
         int group_window, const std::string& first_solve, const std::string& gnc, double gnc_p,
         const std::string& gnc_inner, const std::optional<double>& time_limit_s,
         unsigned threads) -> py::dict {
        app::RobustOptions o;
        o.p = p;
        o.composition = pcm::composition_from_string(composition);
        o.selector = app::robust_selector_from_string(selector);
        o.exact_up_to = exact_up_to;
        o.residual_p = residual_p;
        o.residual_test = app::robust_residual_test_from_string(residual_test);
        o.group_window = group_window;
        if (first_solve != "staircase" && first_solve != "rank-d")
          throw py::value_error(
              fmt::format("robust: first_solve must be 'staircase' or 'rank-d' (got '{}')", first_solve));
        o.first_solve_rank_d = first_solve == "rank-d";
        o.gnc = app::robust_gnc_from_string(gnc);
        o.gnc_p = gnc_p;
        if (gnc_inner != "certified" && gnc_inner != "local")
          throw py::value_error(
              fmt::format("robust: gnc_inner must be 'certified' or 'local' (got '{}')", gnc_inner));
        o.gnc_certified_inner = gnc_inner == "certified";
        if (time_limit_s) {
          if (!(*time_limit_s > 0.0) || std::isinf(*time_limit_s))
            throw py::value_error(fmt::format(
                "robust: time_limit_s must be a finite number of seconds > 0, or None for no limit (got {})",
                *time_limit_s));
          o.time_limit_s = *time_limit_s;
        }
        o.threads = threads;
        o.validate();  // ValueError before any work
        // One graph or a list of graphs, all 2D or all 3D; candidates None or a keel.Candidates of that
        // dimension.
        const py::list list = py::isinstance<py::list>(graphs) || py::isinstance<py::tuple>(graphs)
                                  ? py::list(graphs)
                                  : py::list(py::make_tuple(graphs));
        if (list.empty()) throw py::value_error("robust: no robot's graph given");
        auto run_on = [&](auto tag) {
          using Graph = decltype(tag);
          using Edge = std::decay_t<decltype(Graph{}.edges[0])>;
          std::vector<Graph> robots;
          for (std::size_t r = 0; r < list.size(); ++r) {
            if (!py::isinstance<Graph>(list[r]))
              throw py::type_error(fmt::format("robust: graphs[{}] is a {}, the first a {}", r,
                                               type_name(list[r]), type_name(list[0])));
            robots.push_back(list[r].cast<const Graph&>());
          }
          std::vector<Edge> inter;
          if (!candidates.is_none()) {
            if (!py::isinstance<Candidates>(candidates))
              throw py::type_error(fmt::format(
                  "robust: candidates must be a keel.Candidates or None (got {})", type_name(candidates)));
            const auto& c = candidates.cast<const Candidates&>();
            const auto* e = std::get_if<std::vector<Edge>>(&c.edges);
            if (e == nullptr)
              throw py::value_error(fmt::format("robust: the candidates are {}D, the graphs {}D", c.dim(),
                                                std::is_same_v<Graph, PoseGraph2D> ? 2 : 3));
            inter = *e;
          }
          std::optional<std::decay_t<decltype(app::robust(robots, inter, o))>> run;
          {
            py::gil_scoped_release release;
            run = app::robust(robots, inter, o);
          }
          py::dict d = record_dict(*run);
          d["solution"] = poses_to_array(run->solved.graph.poses);
          d["graph"] = py::cast(run->solved.graph);
          return d;
        };
        if (py::isinstance<PoseGraph2D>(list[0])) return run_on(PoseGraph2D{});
        if (py::isinstance<PoseGraph3D>(list[0])) return run_on(PoseGraph3D{});
        throw py::type_error("robust: graphs must be a keel.Graph2D or keel.Graph3D, or a list of them");
      },
      py::arg("graphs"), py::arg("candidates") = py::none(), py::arg("p") = 0.11,
      py::arg("composition") = "joint", py::arg("selector") = "auto", py::arg("exact_up_to") = 2000,
      py::arg("residual_p") = 0.01, py::arg("residual_test") = "groups", py::arg("group_window") = 5,
      py::arg("first_solve") = "rank-d", py::arg("gnc") = "off", py::arg("gnc_p") = 0.01,
      py::arg("gnc_inner") = "certified", py::arg("time_limit_s") = py::none(), py::arg("threads") = 1, R"doc(
One or several robots' graphs with wrong loop closures, as `keel robust GRAPH... [--candidates FILE]`
(app::robust; same inputs give the same numbers): each robot's edges between consecutive poses are trusted
odometry, its other edges and the inter-robot `candidates` (a keel.Candidates whose ids are global: robot r's pose
k is k plus the poses of the robots before it) are candidate loop closures. Per group (a robot's own closures, or
a pair of robots') the pairwise consistency in the odometry maps (thesis eq. 2.4 with the joint marginals) and
the largest consistent set (exact maximum clique, or 'heuristic'), then the certified solve of all odometry and the
kept closures.
  graphs        a keel.Graph2D / Graph3D, or a list of them (one per robot, all of one dimension)
  candidates    None or a keel.Candidates (inter-robot), of the graphs' dimension
  p             chi-square tail probability of the threshold gamma, in (0, 1) (thesis PCM-Exact-11 %)
  composition   'joint' or 'independent' (the relative poses' cross-covariances dropped)
  selector      each group's consistent set: 'auto' (exact up to exact_up_to candidates, densest beyond),
                'exact' (maximum clique), 'heuristic' (greedy clique) or 'densest' (densest subgraph)
  exact_up_to   see selector (>= 1)
  residual_p    the residual check after the selection: kept closures (or groups) above their test's quantile
                at 1 - residual_p (residual_test) are removed one at a time, worst first; 0 for none
  residual_test 'groups' (the default: data snooping, r'Q^-1 r with Q the least-squares residual's covariance,
                of each closure and of each closure's group, against the quantile at 1 - residual_p/m, m every
                test of the round: wrong closures that agree with one another), 'snooping' (the single
                closures alone) or 'edge' (each closure's chi-square r'Omega r at the solution)
  group_window  'groups': a closure's group holds the kept closures whose ends both lie within this many poses
                of its own (>= 1)
  first_solve   the residual check's first estimate: 'rank-d' (the default: the certified solver's local
                optimum at rank d, no staircase; the certified solve at the end) or 'staircase' (the
                certified solve)
  gnc           'off', 'after' (graduated non-convexity with truncated least squares over the closures the
                selection kept, instead of the residual check) or 'only' (over every candidate, no PCM)
  gnc_p         GNC's inlier threshold: the chi-square quantile at 1 - gnc_p on each closure's r'Omega r
  gnc_inner     GNC's weighted solves: 'certified' (each with its certificate or gap, in d['gnc']['rounds'])
                or 'local' (Levenberg-Marquardt); the answer is the certified solve either way
  time_limit_s  each group's exact clique search limit in seconds (> 0), None for none
  threads       threads for the consistency matrices (the result does not depend on it)
Returns a dict with the fields of `keel robust --json` but 'files' and 'candidates_file' (robots, poses,
odometry_edges, candidates, kept, p, gamma, dof, composition, selector, exact_up_to, groups, times_s, anisotropic_cost,
gnc, certificate, candidate_list) and, beside them, 'solution' (the (n, 3) or (n, 7) estimate of all robots' poses,
one robot after another) and 'graph' (the solved graph: all odometry and the kept closures). Unlike the command,
nothing is refused when the answer is not certified: read d['certificate']['certified']. An odometry that does
not chain every pose, or robots that no kept closure joins, raise ValueError naming the robot.)doc");

  py::class_<cov::MarginalCovariance>(m, "MarginalCovariance", R"doc(
The factorized information matrix of a graph at given poses (keel::cov::MarginalCovariance), to query joint
marginal covariances repeatedly; keel.marginals is one construction plus one query. Same conventions as
keel.marginals (left perturbation, the graph's gauge_pose fixed). Immutable; queries may run from several Python
threads.)doc")
      .def(py::init([](const py::object& g, const py::object& poses, const std::string& ordering,
                       const std::string& extraction) {
             return make_marginals(g, poses, covariance_options(ordering, extraction));
           }),
           py::arg("graph"), py::arg("poses") = py::none(), py::arg("ordering") = "auto",
           py::arg("extraction") = "auto",
           "Builds H at `poses` (default the graph's) and factorizes it. ordering: 'auto', 'amd', 'metis', "
           "'nesdis', 'natural'; extraction: 'auto', 'forward', 'solve' (cov::CovarianceOptions).")
      .def(
          "pairs",
          [](const cov::MarginalCovariance& mc, const py::object& pairs, const py::object& threads) {
            return pair_query(
                mc, pairs,
                static_cast<unsigned>(uint_arg(threads, "MarginalCovariance.pairs", "threads", UINT_MAX)));
          },
          py::arg("pairs"), py::arg("threads") = 1,
          "Joint covariances of pairs: (m, 6, 6) for 2D, (m, 12, 12) for 3D (see keel.marginals).")
      .def(
          "joint",
          [](const cov::MarginalCovariance& mc, const py::object& ids) {
            return ids_query(mc, variable_ids(ids, "MarginalCovariance.joint"));
          },
          py::arg("ids"), "The joint covariance of the variables `ids` (poses first, then 2D landmarks).")
      .def_property_readonly("num_poses", &cov::MarginalCovariance::num_poses, "Number of poses.")
      .def_property_readonly(
          "summary", [](const cov::MarginalCovariance& mc) { return record_dict(mc.summary()); },
          "What the factorization did (ordering, sizes, nonzeros of L, times in seconds), as a dict.");

  m.def(
      "marginals",
      [](const py::object& g, const py::object& poses, const py::object& pairs, const py::object& ids,
         const py::object& threads_obj) {
        const auto threads = static_cast<unsigned>(uint_arg(threads_obj, "marginals", "threads", UINT_MAX));
        if (pairs.is_none() == ids.is_none())
          throw std::invalid_argument("marginals: give exactly one of pairs and ids");
        std::vector<int> id_list;
        if (!ids.is_none()) id_list = variable_ids(ids, "marginals");
        const auto mc = make_marginals(g, poses, {});
        return pairs.is_none() ? py::array(ids_query(*mc, id_list)) : pair_query(*mc, pairs, threads);
      },
      py::arg("graph"), py::arg("poses") = py::none(), py::arg("pairs") = py::none(),
      py::arg("ids") = py::none(), py::arg("threads") = 1, kMarginalsDoc);
}

}  // namespace keel::python
