#include "sos/certify.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/names.hpp"
#include "core/timing.hpp"
#include "pgo/optimize.hpp"

namespace keel::sos {

namespace {
// A lower bound above the solution's cost by more than the tolerance is not a bound (a numerical failure): it
// must not read as a zero gap.
bool bound_is_valid(double ub, double lb, double tol) {
  return std::isfinite(ub) && std::isfinite(lb) && lb <= ub + tol * std::max(std::abs(ub), 1.0);
}
}  // namespace

void CertifyOptions::validate() const {
  relaxation.validate();
  polish.validate();
  if (!(gap_tolerance > 0))
    throw std::invalid_argument(
        fmt::format("sos::CertifyOptions: gap_tolerance must be > 0 (got {})", gap_tolerance));
  if (escalation_max_moments < 1)
    throw std::invalid_argument(fmt::format(
        "sos::CertifyOptions: escalation_max_moments must be >= 1 (got {})", escalation_max_moments));
}

CertifiedSolution solve_certified(const graph::PoseGraph2D& graph, const CertifyOptions& o) {
  o.validate();
  return solve_certified(graph, planar_problem(graph), o);
}

CertifiedSolution solve_certified(const graph::PoseGraph2D& graph, const PlanarProblem& p,
                                  const CertifyOptions& o) {
  o.validate();
  const auto t0 = core::Clock::now();
  CertifiedSolution out;
  out.first = relax(p, o.relaxation);
  out.relax_time_s = out.first.time_s;

  // Round: rotations to the circle, then the translations and landmarks that are optimal for them.
  const auto tp = core::Clock::now();
  Eigen::VectorXd z = out.first.z;
  project_rotations(p, z);
  solve_translations(p, z);
  out.rounded_cost = polynomial_cost(p, z);
  // Polish with keel.pgo (pose 0 held at the identity), then on the thesis's own cost.
  const PlanarEstimate rounded = estimate_of(p, z);
  pgo::Options lm = o.polish;
  lm.initial_guess = pgo::InitialGuess::supplied;
  lm.constant_poses = {0};
  const pgo::Estimate2D start{rounded.poses, rounded.landmarks};
  graph::PoseGraph2D g = graph;
  g.poses.resize(static_cast<std::size_t>(p.poses), lie::SE2::identity());
  const pgo::Result2D polished = pgo::optimize(g, lm, &start);
  Eigen::VectorXd zp = unknowns_of(p, polished.estimate.poses, polished.estimate.landmarks);
  (void)refine(p, zp);
  (void)refine(p, z);
  out.z = polynomial_cost(p, zp) <= polynomial_cost(p, z) ? zp : z;
  out.bound.upper = polynomial_cost(p, out.z);
  out.estimate = estimate_of(p, out.z);
  out.polish_time_s = core::seconds_since(tp);

  // The cost is a χ² (units of the measurement noise), so below 1 the gap is absolute (core::Bound): a gap of
  // 1e-6 at a zero-residual solution means 1e-6 σ², not an undefined ratio.
  out.bound.lower = out.first.lower_bound;
  const bool first_valid = bound_is_valid(out.bound.upper, out.bound.lower, o.gap_tolerance);
  if (!first_valid)
    out.note =
        fmt::format("order-{} bound {} is not finite or exceeds the solution's cost {}: not a valid bound",
                    out.first.order, out.bound.lower, out.bound.upper);
  if (first_valid && out.relative_gap() <= o.gap_tolerance) {
    out.status = core::SearchStatus::optimal;
    out.certified_order = out.first.order;
  } else if (o.escalate && out.first.order == 1) {
    const auto te = core::Clock::now();
    RelaxationOptions second = o.relaxation;
    second.order = 2;  // same structure: dense = rotations only, translations minimised out; cliques = full
    second.max_moments = o.escalation_max_moments;
    try {
      out.second = relax(p, second);
      out.escalated = true;
      if (!first_valid) out.bound.lower = -std::numeric_limits<double>::infinity();
      if (std::isfinite(out.second.lower_bound))
        out.bound.lower = std::max(out.bound.lower, out.second.lower_bound);
      // The order-2 estimate may round to a better solution than the order-1 one.
      Eigen::VectorXd z2 = out.second.z;
      project_rotations(p, z2);
      solve_translations(p, z2);
      (void)refine(p, z2);
      if (polynomial_cost(p, z2) < out.bound.upper) {
        out.z = z2;
        out.bound.upper = polynomial_cost(p, z2);
        out.estimate = estimate_of(p, z2);
      }
      if (bound_is_valid(out.bound.upper, out.bound.lower, o.gap_tolerance) &&
          out.relative_gap() <= o.gap_tolerance) {
        out.status = core::SearchStatus::optimal;
        out.certified_order = 2;
        out.note.clear();
      } else {
        out.note += fmt::format("{}order 2 did not close the gap ({:.3g})", out.note.empty() ? "" : "; ",
                                out.relative_gap());
      }
    } catch (const std::length_error& e) {
      out.note += fmt::format("{}order 2 skipped: {}", out.note.empty() ? "" : "; ", e.what());
    } catch (const std::exception& e) {  // a solver failure at order 2 keeps the order-1 result
      out.note += fmt::format("{}order 2 failed: {}", out.note.empty() ? "" : "; ", e.what());
    }
    out.escalation_time_s = core::seconds_since(te);
  }
  // The cliques structure's lower bound corrects its equality residuals with a box on the translation moments
  // that is not proven (relaxation.hpp): its gap is reported, never certified.
  if (o.relaxation.structure == Structure::cliques && out.status == core::SearchStatus::optimal) {
    out.status = core::SearchStatus::unproven;
    out.note = fmt::format(
        "{}the cliques structure's bound (gap {:.3g}) rests on an unproven translation box: not "
        "certified (use structure dense)",
        out.note.empty() ? "" : out.note + "; ", out.relative_gap());
    out.certified_order = 0;
  }
  out.time_s = core::seconds_since(t0);
  return out;
}

graph::PoseGraph2D exactness_counterexample() {
  const double theta[6] = {0.23, 0.43, 1.13, -1.81, 1.36, -1.35};
  const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  graph::PoseGraph2D g;
  g.poses.assign(4, lie::SE2::identity());
  for (int k = 0; k < 6; ++k) {
    graph::Edge2 e;
    e.i = pairs[k][0], e.j = pairs[k][1];
    e.measurement = lie::SE2(0, 0, theta[k]);
    e.information = lie::Mat3(Eigen::Vector3d(1, 1, 2).asDiagonal());  // ω_R = ω_x = ω_y = 1 (problem.hpp)
    g.edges.push_back(e);
  }
  g.source = "exactness counterexample";
  return g;
}

}  // namespace keel::sos
