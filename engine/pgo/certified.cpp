// Certified pose-graph optimization (certified.hpp): the staircase over the parts of certified_internal.hpp
// (problem, local solves, certificate, lift and rounding) and the public functions.
#include "pgo/certified.hpp"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/blas.hpp"
#include "core/names.hpp"
#include "core/timing.hpp"
#include "linalg/double_double.hpp"
#include "linalg/psd_proof.hpp"
#include "linalg/sparse_cholesky.hpp"
#include "pgo/certified_internal.hpp"

namespace keel::pgo {

namespace {

using namespace certified;

template <class Pose>
Point point_from_poses(const Problem& P, const std::vector<Pose>& poses) {
  if (static_cast<int>(poses.size()) < P.n)
    fail(fmt::format("certify: {} poses given for a graph of {}", poses.size(), P.n));
  Point X;
  X.r = P.d;
  X.Q.resize(static_cast<std::size_t>(P.n));
  X.T.resize(P.d, P.n);
  for (int v = 0; v < P.n; ++v) {
    X.Q[static_cast<std::size_t>(v)] = poses[static_cast<std::size_t>(v)].rotation();
    X.T.col(v) = poses[static_cast<std::size_t>(v)].translation();
  }
  // Translations relative to pose 0 (the gauge of the certificate matrix), in pose 0's frame so that R_0 = I
  // is not required: F is invariant under a common rigid motion.
  const Small R0t = X.Q[0].transpose();
  const Eigen::VectorXd t0 = X.T.col(0);
  for (int v = 0; v < P.n; ++v) {
    X.Q[static_cast<std::size_t>(v)] = R0t * X.Q[static_cast<std::size_t>(v)];
    X.T.col(v) = R0t * (X.T.col(v) - t0);
  }
  return X;
}

lie::SE2 to_pose(const Small& R, const Eigen::VectorXd& t, const lie::SE2*) {
  return lie::SE2(t(0), t(1), std::atan2(R(1, 0), R(0, 0)));
}
lie::SE3 to_pose(const Small& R, const Eigen::VectorXd& t, const lie::SE3*) {
  return lie::SE3(lie::SO3::from_matrix_unchecked(lie::Mat3(R)), lie::Vec3(t));
}

template <class Pose, class Graph>
void solve_impl(const Graph& graph, const CertifiedOptions& o, CertifiedSummary& S,
                std::vector<Pose>& poses) {
  o.validate();
  // CHOLMOD's supernodal factorizations call the BLAS: one BLAS thread keeps the result independent of the
  // machine's core count (core/blas.hpp), and is what the side-by-side measurements use.
  const core::SingleThreadedBlas one_blas_thread;
  const core::SerialOpenMp serial_openmp;  // CHOLMOD's supernodal teams of four (core/blas.hpp)
  const auto t_total = core::Clock::now();
  const Deadline deadline{t_total, o.time_limit_s};
  const int d = std::is_same_v<Pose, lie::SE2> ? 2 : 3;
  if (o.max_rank < d) fail(fmt::format("CertifiedOptions: max_rank must be >= {} (got {})", d, o.max_rank));
  const Problem P = make_problem(graph, d);
  std::unique_ptr<DataPreconditioner> pre;  // made by the first local solve above rank d
  S.poses = P.n;
  S.edges = static_cast<int>(P.edges.size());
  S.dimension = d;
  S.problem = fmt::format(
      "isotropic (chordal) SE({}) synchronization: Σ κ‖R_j − R_i R̃‖²_F + τ‖t_j − t_i − R_i t̃‖² with "
      "SE-Sync's κ, τ "
      "from each edge's information",
      d);
  auto t0 = core::Clock::now();
  Point X;
  if (o.chordal_initialization) {
    X = chordal_initialization(P);
  } else {
    if (static_cast<int>(graph.poses.size()) < P.n)
      fail("solve_certified: chordal_initialization = false needs an estimate for every pose in the graph");
    X = point_from_poses(P, graph.poses);
  }
  S.initial_cost = cost(P, X);
  S.initialization_time_s = core::seconds_since(t0);

  // The proven certificate with the highest lower bound over every point tested (any proven Λ bounds the
  // minimum, whichever point it came from), and whether it is the last one tested.
  Certificate best;
  int tested = 0, best_index = -1;
  auto keep = [&](const Certificate& C) {
    if (C.proven && (!best.proven || C.bound.lower > best.bound.lower)) {
      best = C;
      best_index = tested;
    }
    ++tested;
  };
  bool rank_limited = false, timed_out = false;
  // Above rank d each rank is first solved loosely (CertifiedOptions::staircase_stationarity). `polished`
  // receives the rank-d answer when a loose point shows that no bound can certify it (below).
  const bool staged = o.staircase_stationarity > 0.0;
  CertifiedOptions loose = o, full = o;
  if (staged) loose.stationarity_tolerance = o.staircase_stationarity / o.gap_tolerance;
  full.staircase_relative_decrease = 0.0;  // the relative-decrease stop belongs to the loose solves only
  std::optional<Point> polished;
  std::string uncertifiable;  // why the staircase stopped early (empty: it did not)
  // A lifted point back to SO(d)ⁿ and its optimal translations, then the local solve at rank d.
  const auto round_and_polish = [&](Point& Y) {
    t0 = core::Clock::now();
    Y = round_to_rotations(P, Y);
    S.rounding_time_s += core::seconds_since(t0);
    t0 = core::Clock::now();
    const LocalOutcome polish = local_solve(P, Y, full, pre, deadline);
    S.local_time_s += core::seconds_since(t0);
    polish.add_to(S);
    return polish;
  };
  for (;;) {
    const auto t_rank = core::Clock::now();
    RankRecord rec;
    rec.rank = X.r;
    LocalOutcome local;
    auto solve_at_rank = [&](const CertifiedOptions& with) {
      t0 = core::Clock::now();
      local = local_solve(P, X, with, pre, deadline);
      S.local_time_s += core::seconds_since(t0);
      local.add_to(S);
      if (S.ordering.empty()) S.ordering = local.ordering;
      rec.iterations += local.iterations;
      rec.factorizations += local.factorizations;
      rec.cg_steps += local.cg_steps;
      rec.tcg_iterations += local.tcg_iterations;
      rec.cost = local.cost;
      rec.gradient_norm = local.gradient_norm;
    };
    EscapeDirection esc;
    auto test = [&] {
      esc = EscapeDirection{};
      t0 = core::Clock::now();
      Certificate c = certificate_at(P, X, o.gap_tolerance, X.r < o.max_rank ? &esc : nullptr);
      S.certificate_time_s += core::seconds_since(t0);
      keep(c);
      return c;
    };
    const bool loose_first = staged && X.r > d;
    solve_at_rank(loose_first ? loose : full);
    Certificate C = test();
    rec.loose = loose_first;
    if (loose_first && !C.certified && !local.timed_out && !deadline.passed()) {
      // At the loose point: S's curvature below −(η* + ‖grad‖) is taken as the saddle's own (the multipliers
      // of a point that far from stationarity are off by about ‖grad‖), and the staircase climbs at once.
      const bool descend =
          esc.found && esc.rayleigh < -(std::max(C.tolerance_shift, 0.0) + local.gradient_norm);
      if (!descend) {
        // Otherwise the point is near a minimizer of this rank. F there bounds the relaxation's optimum from
        // above, and so every lower bound that any point can prove: when the rank-d answer rounded from it
        // and polished costs more than that by kUncertifiable × the gap tolerance, no tighter solve of this
        // rank could certify it, and the answer and the bound proven so far are returned.
        Point R = X;
        const LocalOutcome polish = round_and_polish(R);
        if (polish.timed_out ||
            polish.cost - local.cost > kUncertifiable * o.gap_tolerance * std::max(polish.cost, 1.0)) {
          timed_out = polish.timed_out;
          if (!timed_out)
            uncertifiable = fmt::format(
                "; the staircase stopped at rank {}: the answer rounded from its loose point costs {:.10g}, "
                "above "
                "F = {:.10g} there, which bounds every lower bound from above",
                X.r, polish.cost, local.cost);
          polished = std::move(R);
        } else {
          rec.loose = false;
          solve_at_rank(full);
          C = test();
        }
      }
    }
    rec.certified = C.certified;
    rec.lambda_min_estimate = esc.found ? esc.rayleigh : 0.0;
    rec.time_s = core::seconds_since(t_rank);
    S.staircase.push_back(rec);
    S.final_rank = X.r;
    S.certificate = C;
    if (C.certified || polished) break;
    if (local.timed_out || deadline.passed()) {
      timed_out = true;
      break;
    }
    if (X.r >= o.max_rank || !esc.found || !lift(P, X, esc)) {
      rank_limited = X.r >= o.max_rank;
      if (!esc.found && X.r < o.max_rank)
        S.message = fmt::format(
            "the certificate failed at rank {} but S has no curvature below −η* = {:.3g} (estimate {:.3g}): "
            "the "
            "test is at the limit of double precision for this gap tolerance",
            X.r, S.certificate.tolerance_shift, esc.rayleigh);
      break;
    }
  }
  // Back to SO(d)ⁿ, polish at rank d, certify the returned point.
  t0 = core::Clock::now();
  if (polished || X.r > d) {
    if (polished)  // rounded and polished already
      X = std::move(*polished);
    else
      timed_out = round_and_polish(X).timed_out || timed_out;
    t0 = core::Clock::now();
    Certificate C = certificate_at(P, X, o.gap_tolerance, nullptr);
    S.certificate_time_s += core::seconds_since(t0);
    keep(C);
    S.certificate = C;
  } else {
    // Already SO(d)ⁿ (to rounding): re-project and re-solve the translations so the returned rotations are
    // orthonormal; F changes in the last bits only.
    Point R = round_to_rotations(P, X);
    if (cost(P, R) <= S.certificate.bound.upper * (1.0 + 1e-12)) X = std::move(R);
    S.rounding_time_s += core::seconds_since(t0);
  }
  S.final_cost = cost(P, X);
  // The reported certificate is the proof behind the best lower bound, every field its own; the upper end is
  // F at the returned point, rounded up. Nothing proven: the last test's failure, lower −∞.
  const double upper = cost_upper(P, X);
  if (best.proven) {
    if (best_index != tested - 1) {
      // The bound comes from a staircase point: the returned point's own test is reported beside it.
      S.bound_from_staircase = true;
      S.returned_point = S.certificate;
      S.returned_point.bound.upper = upper;
    }
    S.certificate = best;
  } else {
    S.certificate.bound.lower = -std::numeric_limits<double>::infinity();
  }
  S.certificate.bound.upper = upper;
  const double gap = S.certificate.bound.relative_gap_up();
  S.certificate.certified = S.certificate.proven && gap <= o.gap_tolerance;
  if (S.certificate.certified) {
    S.termination = CertifiedTermination::certified;
    S.status = core::SearchStatus::optimal;
    S.message = fmt::format("numerically certified at rank {}: relative gap {} ≤ {:.3g}", S.final_rank,
                            core::format_upper(gap, 3), o.gap_tolerance);
  } else {
    S.termination = timed_out      ? CertifiedTermination::time_limit
                    : rank_limited ? CertifiedTermination::rank_limit
                                   : CertifiedTermination::not_certified;
    S.status = core::SearchStatus::unproven;
    if (timed_out)
      S.message =
          fmt::format("stopped at the time limit of {} s at rank {}; {}", o.time_limit_s, S.final_rank,
                      S.certificate.proven ? "the lower bound of the points reached holds"
                                           : "no lower bound holds at the points reached");
    if (S.message.empty())
      S.message = rank_limited
                      ? fmt::format("the staircase reached max_rank = {} without a certificate", o.max_rank)
                  : !S.certificate.proven
                      ? fmt::format("not certified: {}", S.certificate.message)
                      : fmt::format(
                            "not certified: the best lower bound (multipliers of the rank-{} point) leaves a "
                            "relative gap of {} > {:.3g}{}",
                            S.certificate.rank, core::format_lower(gap, 3), o.gap_tolerance,
                            S.bound_from_staircase ? "; the returned point's own test failed" : "") +
                            uncertifiable;
  }
  poses.resize(static_cast<std::size_t>(P.n));
  for (int v = 0; v < P.n; ++v)
    poses[static_cast<std::size_t>(v)] = to_pose(
        X.Q[static_cast<std::size_t>(v)], Eigen::VectorXd(X.T.col(v)), static_cast<const Pose*>(nullptr));
  // The solution holds pose 0 at the identity (the gauge of the certificate matrix). A graph whose gauge is
  // another pose k (g2o's FIX k) gets the rigid motion that puts pose k at its as-read value; F, Λ and the
  // bound are invariant under it (F to rounding at the moved poses).
  if (const auto k = static_cast<std::size_t>(graph.gauge_pose);
      k != 0 && k < graph.poses.size() && k < poses.size()) {
    const Pose move = graph.poses[k] * poses[k].inverse();
    for (auto& T : poses) T = move * T;
    poses[k] = graph.poses[k];
  }
  S.total_time_s = core::seconds_since(t_total);
}

template <class Pose, class Graph>
Certificate certify_impl(const Graph& graph, const std::vector<Pose>& poses, double gap_tolerance) {
  if (!(gap_tolerance > 0.0)) fail(fmt::format("certify: gap_tolerance must be > 0 (got {})", gap_tolerance));
  const int d = std::is_same_v<Pose, lie::SE2> ? 2 : 3;
  const Problem P = make_problem(graph, d);
  const Point X = point_from_poses(P, poses);
  const core::SingleThreadedBlas one_blas_thread;  // as in solve_impl
  const core::SerialOpenMp serial_openmp;
  return certificate_at(P, X, gap_tolerance, nullptr);
}

template <class Pose, class Graph>
double cost_impl(const Graph& graph, const std::vector<Pose>& poses) {
  const int d = std::is_same_v<Pose, lie::SE2> ? 2 : 3;
  const Problem P = make_problem(graph, d);
  return cost(P, point_from_poses(P, poses));
}

}  // namespace

IsotropicWeights isotropic_weights(const graph::Edge2& e) {
  const lie::Mat2 tt = e.information.topLeftCorner<2, 2>();
  IsotropicWeights w;
  w.tau = 2.0 / tt.inverse().trace();
  w.kappa = e.information(2, 2);
  return w;
}

IsotropicWeights isotropic_weights(const graph::Edge3& e) {
  const lie::Mat3 tt = e.information.topLeftCorner<3, 3>();
  const lie::Mat3 qq = 4.0 * e.information.bottomRightCorner<3, 3>();
  IsotropicWeights w;
  w.tau = 3.0 / tt.inverse().trace();
  w.kappa = 3.0 / (2.0 * qq.inverse().trace());
  return w;
}

void CertifiedOptions::validate() const {
  if (!(gap_tolerance > 0.0 && gap_tolerance < 1.0))
    fail(fmt::format("CertifiedOptions: gap_tolerance must be in (0, 1) (got {})", gap_tolerance));
  if (!(staircase_stationarity >= 0.0 && staircase_stationarity < 1.0))
    fail(fmt::format("CertifiedOptions: staircase_stationarity must be in [0, 1) (0: off; got {})",
                     staircase_stationarity));
  if (!(staircase_relative_decrease >= 0.0 && staircase_relative_decrease < 1.0))
    fail(fmt::format("CertifiedOptions: staircase_relative_decrease must be in [0, 1) (0: off; got {})",
                     staircase_relative_decrease));
  if (max_rank > kMaxRank)
    fail(fmt::format("CertifiedOptions: max_rank must be <= {} (got {})", kMaxRank, max_rank));
  if (max_iterations < 1)
    fail(fmt::format("CertifiedOptions: max_iterations must be >= 1 (got {})", max_iterations));
  if (!(stationarity_tolerance > 0.0 && stationarity_tolerance <= 1.0))
    fail(fmt::format("CertifiedOptions: stationarity_tolerance must be in (0, 1] (got {})",
                     stationarity_tolerance));
  if (!(time_limit_s >= 0.0) || std::isinf(time_limit_s))
    fail(fmt::format(
        "CertifiedOptions: time_limit_s must be a finite number of seconds >= 0 (0: none; got {})",
        time_limit_s));
}

namespace {
constexpr core::NameTable<TrustRegionPreconditioner, 3> kTrustRegionPreconditioner{
    "pgo::TrustRegionPreconditioner",
    {{{TrustRegionPreconditioner::automatic, "auto"},
      {TrustRegionPreconditioner::joint, "joint"},
      {TrustRegionPreconditioner::reduced, "reduced"}}}};
}  // namespace

std::string_view to_string(TrustRegionPreconditioner p) { return kTrustRegionPreconditioner.name(p); }
TrustRegionPreconditioner trust_region_preconditioner_from_string(std::string_view s) {
  return kTrustRegionPreconditioner.parse(s);
}

std::string_view to_string(CertifiedTermination t) {
  switch (t) {
    case CertifiedTermination::certified:
      return "certified";
    case CertifiedTermination::rank_limit:
      return "rank_limit";
    case CertifiedTermination::not_certified:
      return "not_certified";
    case CertifiedTermination::time_limit:
      return "time_limit";
  }
  return "unknown";
}

double isotropic_cost(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& poses) {
  return cost_impl(graph, poses);
}
double isotropic_cost(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& poses) {
  return cost_impl(graph, poses);
}

CertifiedResult2D solve_certified(const graph::PoseGraph2D& graph, const CertifiedOptions& options) {
  if (!graph.landmark_measurements.empty())
    fail(
        "solve_certified: graphs with landmarks are not supported (the isotropic model covers pose-pose "
        "edges)");
  CertifiedResult2D r;
  solve_impl(graph, options, r.summary, r.poses);
  return r;
}

CertifiedResult3D solve_certified(const graph::PoseGraph3D& graph, const CertifiedOptions& options) {
  CertifiedResult3D r;
  solve_impl(graph, options, r.summary, r.poses);
  return r;
}

namespace {

template <class Graph>
CertifiedSolution<Graph> solution_impl(const Graph& g, const CertifiedOptions& options) {
  const auto t0 = core::Clock::now();
  auto r = solve_certified(g, options);
  CertifiedSolution<Graph> out;
  out.solve_time_s = core::seconds_since(t0);
  out.graph = g;
  out.graph.poses = std::move(r.poses);
  out.graph.has_initial_poses = true;
  out.summary = std::move(r.summary);
  if (g.indefinite_information > 0) {
    out.anisotropic_cost = std::numeric_limits<double>::quiet_NaN();  // undefined with indefinite information
  } else {
    std::conditional_t<std::is_same_v<Graph, graph::PoseGraph2D>, Estimate2D, Estimate3D> at;
    at.poses = out.graph.poses;
    out.anisotropic_cost = evaluate(g, at).cost;
  }
  return out;
}

}  // namespace

CertifiedSolution<graph::PoseGraph2D> certified_solution(const graph::PoseGraph2D& graph,
                                                         const CertifiedOptions& options) {
  return solution_impl(graph, options);
}
CertifiedSolution<graph::PoseGraph3D> certified_solution(const graph::PoseGraph3D& graph,
                                                         const CertifiedOptions& options) {
  return solution_impl(graph, options);
}

Certificate certify(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& poses,
                    double gap_tolerance) {
  return certify_impl(graph, poses, gap_tolerance);
}
Certificate certify(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& poses,
                    double gap_tolerance) {
  return certify_impl(graph, poses, gap_tolerance);
}

}  // namespace keel::pgo
