#include "app/records.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "core/bound.hpp"

namespace keel::app {

void FieldWriter::number(std::string_view name, double value) {
  if (std::isfinite(value))
    finite_number(name, value);
  else
    null(name);
}

void FieldWriter::number(std::string_view name, const std::optional<double>& value) {
  if (value)
    number(name, *value);
  else
    null(name);
}

std::optional<ProvenFigures> proven_figures(const pgo::Certificate& c) {
  if (!c.proven) return std::nullopt;
  ProvenFigures f{};
  f.lower_bound = c.bound.lower;
  f.relative_gap = c.bound.relative_gap_up();
  f.dual_gap = core::round_up(core::round_up(c.bound.upper - c.trace_lambda) /
                              std::fmax(1.0, std::abs(c.bound.upper)));
  f.shift = c.shift;
  f.proof_rank = c.rank;
  f.rounding_margin = c.rounding_margin;
  f.residual = c.residual;
  f.worst_case_residual = c.worst_case_residual;
  f.formation_error = c.formation_error;
  f.extended_precision = c.extended_precision;
  return f;
}

namespace {

// The attempts of a certificate's proof that failed, as failed (not a bound): null when none did.
void write_failures(std::string_view name, const pgo::Certificate& c, FieldWriter& w) {
  if (!(c.failed_shift > 0.0)) {
    w.null(name);
    return;
  }
  w.record(name, [&](FieldWriter& f) {
    f.boolean("proven", false);
    f.number("largest_failed_shift", c.failed_shift);
    f.integer("attempts", c.attempts);
  });
}

}  // namespace

void write_record(const pgo::Summary& s, FieldWriter& w) {
  w.text("termination", pgo::to_string(s.termination));
  w.text("message", s.message);
  w.number("initial_cost", s.initial_cost);
  w.number("final_cost", s.final_cost);
  w.number("final_chi2", s.final_chi2);
  w.number("normalized_chi2", s.normalized_chi2);  // null without degrees of freedom
  w.integer("residual_dimension", s.residual_dimension);
  w.integer("free_parameter_dimension", s.free_parameter_dimension);
  w.integer("iterations", s.iterations);
  w.integer("successful_steps", s.successful_steps);
  w.number("total_time_s", s.total_time_s);
  w.number("linear_solver_time_s", s.linear_solver_time_s);
  w.number("jacobian_evaluation_time_s", s.jacobian_evaluation_time_s);
}

void write_record(const pgo::RankRecord& r, FieldWriter& w) {
  w.integer("rank", r.rank);
  w.integer("iterations", r.iterations);
  w.integer("factorizations", r.factorizations);
  w.integer("cg_steps", r.cg_steps);
  w.integer("tcg_iterations", r.tcg_iterations);
  w.number("cost", r.cost);
  w.number("gradient_norm", r.gradient_norm);
  w.boolean("certified", r.certified);  // the certificate held at this point (optimal for the relaxation)
  w.number("lambda_min_estimate", r.lambda_min_estimate);
  w.boolean("loose", r.loose);  // stopped at the staircase's loose stationarity
  w.number("time_s", r.time_s);
}

void write_record(const pgo::CertifiedSummary& s, FieldWriter& w) {
  const auto& c = s.certificate;
  const std::optional<ProvenFigures> p = proven_figures(c);
  // A figure of the proof: null unless the proof behind lower_bound succeeded.
  const auto proven = [&](std::string_view name, auto member) {
    if (!p) {
      w.null(name);
      return;
    }
    const auto v = (*p).*member;
    if constexpr (std::is_same_v<decltype(v), const bool>)
      w.boolean(name, v);
    else if constexpr (std::is_same_v<decltype(v), const int>)
      w.integer(name, v);
    else
      w.number(name, v);
  };
  w.text("termination", pgo::to_string(s.termination));
  w.text("status", core::to_string(s.status));
  w.text("message", s.message);
  w.text("problem", s.problem);
  w.integer("dimension", s.dimension);
  w.integer("poses", s.poses);
  w.integer("edges", s.edges);
  w.number("initial_cost", s.initial_cost);
  w.number("final_cost", s.final_cost);
  w.boolean("certified", c.certified);
  w.boolean("proven", c.proven);
  proven("lower_bound", &ProvenFigures::lower_bound);  // rounded down
  w.number("upper_bound", c.bound.upper);              // F at the returned point, rounded up
  proven("relative_gap", &ProvenFigures::relative_gap);
  proven("dual_gap", &ProvenFigures::dual_gap);
  if (p)
    w.number("lambda_min_lower_bound", -p->shift);
  else
    w.null("lambda_min_lower_bound");
  proven("shift", &ProvenFigures::shift);
  w.number("tolerance_shift", c.tolerance_shift);  // η* that the gap tolerance allows: a target, not a proof
  w.number("trace_lambda", c.trace_lambda);
  proven("proof_rank", &ProvenFigures::proof_rank);
  proven("rounding_margin", &ProvenFigures::rounding_margin);
  proven("residual", &ProvenFigures::residual);
  proven("worst_case_residual", &ProvenFigures::worst_case_residual);
  proven("formation_error", &ProvenFigures::formation_error);
  proven("extended_precision", &ProvenFigures::extended_precision);
  write_failures("failed_attempts", c, w);
  w.text("proof_message", c.message);  // the proof, or "no lower bound: " and what failed
  w.integer("order", c.size);          // order of S (translation 0 removed)
  w.boolean("bound_from_staircase", s.bound_from_staircase);
  if (s.bound_from_staircase) {
    w.record("returned_point", [&](FieldWriter& r) {
      r.boolean("proven", s.returned_point.proven);
      if (s.returned_point.proven)
        r.number("lower_bound", s.returned_point.bound.lower);
      else
        r.null("lower_bound");
      r.text("message", s.returned_point.message);
      write_failures("failed_attempts", s.returned_point, r);
    });
  } else {
    w.null("returned_point");
  }
  w.integer("final_rank", s.final_rank);
  w.records("staircase", s.staircase.size(),
            [&](std::size_t k, FieldWriter& r) { write_record(s.staircase[k], r); });
  w.integer("iterations", s.iterations);
  w.integer("factorizations", s.factorizations);
  w.integer("cg_steps", s.cg_steps);
  w.integer("tcg_iterations", s.tcg_iterations);
  w.text("ordering", s.ordering);
  w.record("times_s", [&](FieldWriter& t) {
    t.number("initialization", s.initialization_time_s);
    t.number("local", s.local_time_s);
    t.number("certificate", s.certificate_time_s);
    t.number("rounding", s.rounding_time_s);
    t.number("total", s.total_time_s);
  });
}

void write_record(const cov::FactorSummary& s, FieldWriter& w) {
  w.text("ordering", s.ordering);
  w.boolean("supernodal", s.supernodal);
  w.text("extraction", s.extraction);
  w.integer("size", s.size);
  w.integer("nnz_h", static_cast<std::int64_t>(s.nnz_h));
  w.number("nnz_l", s.nnz_l);
  w.number("factor_flops", s.factor_flops);
  w.integer("num_supernodes", static_cast<std::int64_t>(s.num_supernodes));
  w.number("analyze_time_s", s.analyze_time_s);
  w.number("factorize_time_s", s.factorize_time_s);
}

}  // namespace keel::app

namespace keel::app {

namespace {

template <class G>
void write_robust(const RobustRun<G>& r, FieldWriter& w) {
  const auto& o = r.options;
  std::size_t odometry_edges = 0;
  for (const auto& g : r.odometry) odometry_edges += g.edges.size();
  w.integer("robots", static_cast<std::int64_t>(r.odometry.size()));
  w.integer("poses", static_cast<std::int64_t>(r.selected.poses.size()));
  w.integer("odometry_edges", static_cast<std::int64_t>(odometry_edges));
  w.integer("candidates", static_cast<std::int64_t>(r.candidates.size()));
  w.integer("kept", r.kept);
  w.number("p", o.p);
  w.number("gamma", r.gamma);
  w.integer("dof", G::DoF);
  w.text("composition", pcm::to_string(o.composition));
  w.text("selector", to_string(o.selector));
  w.number("residual_p", o.residual_p);
  w.text("residual_test", to_string(o.residual_test));
  w.integer("group_window", o.group_window);
  w.text("first_solve", o.first_solve_rank_d ? "rank-d" : "staircase");
  w.number("residual_threshold", r.residual_threshold);
  w.integer("residual_rounds", r.residual_rounds);
  w.integer("exact_up_to", o.exact_up_to);
  w.record("gnc", [&](FieldWriter& g) {
    g.text("mode", to_string(o.gnc));
    g.number("p", o.gnc_p);
    g.number("threshold", r.gnc_threshold);
    g.number("mu_factor", o.gnc_mu_factor);
    g.integer("max_rounds", o.gnc_max_rounds);
    g.text("inner", o.gnc_certified_inner ? "certified" : "local");
    g.integer("weighed", r.gnc_weighed);
    g.boolean("converged", r.gnc_converged);
    g.records("rounds", r.gnc_rounds.size(), [&](std::size_t k, FieldWriter& x) {
      const RobustGncRound& round = r.gnc_rounds[k];
      x.number("mu", round.mu);
      x.integer("inliers", round.inliers);
      x.integer("zero", round.zero);
      x.number("weight_sum", round.weight_sum);
      x.number("tls_cost", round.tls_cost);
      x.boolean("certified", round.certified);
      x.number("relative_gap", round.relative_gap);
      x.number("time_s", round.time_s);
    });
  });
  w.records("groups", r.groups.size(), [&](std::size_t k, FieldWriter& g) {
    const RobustGroup& grp = r.groups[k];
    g.integer("robot_a", grp.robot_a);
    g.integer("robot_b", grp.robot_b);
    g.integer("candidates", static_cast<std::int64_t>(grp.members.size()));
    g.integer("kept", static_cast<std::int64_t>(grp.selection.selected.size()));
    g.text("selector", to_string(grp.selector));
    // No search when GNC replaced the selection (every candidate went to GNC): status "not run".
    const auto& search = grp.selection.search;
    g.record("clique", [&](FieldWriter& c) {
      c.text("status", search ? core::to_string(search->status) : std::string_view("not run"));
      c.integer("size", search ? static_cast<std::int64_t>(search->clique.size()) : 0);
      c.integer("upper_bound", search ? search->upper_bound : 0);
      c.integer("nodes_explored", search ? static_cast<std::int64_t>(search->nodes_explored) : 0);
    });
    g.number("consistency_time_s", grp.consistency_time_s);
    g.number("selection_time_s", grp.selection.time_s);
  });
  w.record("times_s", [&](FieldWriter& t) {
    t.number("odometry", r.odometry_time_s);
    t.number("marginals", r.marginals_time_s);
    t.number("consistency", r.consistency_time_s);
    t.number("selection", r.selection_time_s);
    t.number("residual_solves", r.residual_time_s);
    t.number("gnc", r.gnc_time_s);
    t.number("certified_solve", r.solved.summary.total_time_s);
  });
  w.number("anisotropic_cost", r.solved.anisotropic_cost);
  w.record("certificate", [&](FieldWriter& c) { write_record(r.solved.summary, c); });
  w.records("candidate_list", r.candidates.size(), [&](std::size_t k, FieldWriter& c) {
    const auto& cand = r.candidates[k];
    c.integer("candidate", static_cast<std::int64_t>(k));
    c.integer("robot_a", cand.robot_a);
    c.integer("i", cand.pose_a);
    c.integer("robot_b", cand.robot_b);
    c.integer("j", cand.pose_b);
    c.integer("source", cand.source);
    c.integer("edge", cand.edge);
    c.integer("line", cand.line);
    c.integer("group", cand.group);
    c.boolean("kept", cand.kept);
    c.integer("inconsistent_with_kept", cand.inconsistent_with_kept);
    c.integer("removed_in_round", cand.removed_in_round);
    c.number("residual_chi2", cand.residual_chi2);
    c.number("snooping_t", cand.snooping_t);
    c.number("residual_group_t", cand.residual_group_t);
    c.integer("residual_group_dof", cand.residual_group_dof);
    c.integer("residual_group_size", cand.residual_group_size);
    c.number("gnc_weight", cand.gnc_weight);
    c.boolean("joins_robots", cand.joins_robots);
  });
}

}  // namespace

void write_record(const RobustRun2& r, FieldWriter& w) { write_robust(r, w); }
void write_record(const RobustRun3& r, FieldWriter& w) { write_robust(r, w); }

}  // namespace keel::app
