// keel robust GRAPH... [--candidates FILE] — one or several robots' graphs with wrong loop closures
// (app::robust): each robot's odometry trusted, its other edges and the inter-robot list candidates, each
// group's largest pairwise-consistent set (thesis eqs. 2.4–2.5, the relative poses from the odometry maps'
// joint marginals), the residual check or GNC (--gnc), then the certified solve of all odometry and the kept
// closures.
// <variant> before the imports (docs/TOOLCHAIN.md; as in marginals.cpp).
#include <variant>

import keel.core;
import keel.lie;
import keel.graph;
import keel.pgo;
import keel.pcm;
import keel.app;

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "tool_common.hpp"
#include "write_solution.hpp"

namespace keel::cli {

namespace {

struct RobustArgs {
  Common common;
  std::vector<std::string> files;
  std::string candidates, out, report;
  double p = 0.11;
  std::string composition = "joint", selector = "auto";
  int exact_up_to = 2000;
  double residual_p = 0.01;
  std::string gnc = "off", gnc_inner = "certified", residual_test = "groups", first_solve = "rank-d";
  int group_window = 5;
  double gnc_p = 0.01;
  double time_limit_s = 0.0;
  unsigned threads = 1;
};

template <class Graph, class Edge>
void robust_files(const RobustArgs& args, const std::vector<Graph>& robots, const std::vector<Edge>& inter,
                  const Stages& stage, app::Outputs& outputs, graph::GraphFormat format) {
  app::RobustOptions o;
  o.p = args.p;
  o.composition = pcm::composition_from_string(args.composition);
  o.selector = app::robust_selector_from_string(args.selector);
  o.exact_up_to = args.exact_up_to;
  o.residual_p = args.residual_p;
  o.residual_test = app::robust_residual_test_from_string(args.residual_test);
  o.group_window = args.group_window;
  o.first_solve_rank_d = args.first_solve == "rank-d";
  o.gnc = app::robust_gnc_from_string(args.gnc);
  o.gnc_p = args.gnc_p;
  o.gnc_certified_inner = args.gnc_inner == "certified";
  o.time_limit_s = args.time_limit_s;
  o.threads = args.threads;
  const auto run = app::robust(robots, inter, o, stage.progress());
  const auto& s = run.solved.summary;
  const bool certified = s.certificate.certified;
  // The report is app's record of the run (the Python module's keel.robust gives the same fields).
  json j = record_json(run);
  j["files"] = args.files;
  j["candidates_file"] = args.candidates.empty() ? json(nullptr) : json(args.candidates);
  // Outputs are written only on exit 0 (a certified answer), all or nothing (app::Outputs).
  if (certified) {
    if (!args.out.empty()) {
      outputs.write(args.out, [&](const std::filesystem::path& temporary) {
        write_solution(run.solved.graph, temporary, format);
      });
    }
    if (!args.report.empty()) write_json(outputs, args.report, j);
    outputs.commit();
  }
  if (args.common.json) {
    fmt::print("{}\n", j.dump(1));
  } else {
    for (std::size_t r = 0; r < robots.size(); ++r)
      fmt::print("robot {:<6} {} ({} poses, {} odometry edges)\n", r, args.files[r], robots[r].poses.size(),
                 run.odometry[r].edges.size());
    fmt::print("threshold    γ = {:.6g} (p = {}, χ²({}) tail), {} composition in the odometry maps\n",
               run.gamma, args.p, s.dimension == 2 ? 3 : 6, args.composition);
    for (const auto& grp : run.groups) {
      if (!grp.selection.search) {
        fmt::print("candidates   {} {} (no consistency check: every candidate goes to GNC)\n",
                   grp.members.size(),
                   grp.robot_a == grp.robot_b
                       ? fmt::format("loop closures of robot {}", grp.robot_a)
                       : fmt::format("closures between robots {} and {}", grp.robot_a, grp.robot_b));
        continue;
      }
      const auto& search = *grp.selection.search;
      fmt::print("kept         {} of {} {} ({}: {}, bound {}){}\n", grp.selection.selected.size(),
                 grp.members.size(),
                 grp.robot_a == grp.robot_b
                     ? fmt::format("loop closures of robot {}", grp.robot_a)
                     : fmt::format("closures between robots {} and {}", grp.robot_a, grp.robot_b),
                 app::to_string(grp.selector), core::to_string(search.status), search.upper_bound,
                 search.proven_optimal() ? "" : ": not proven the largest consistent set");
    }
    if (run.groups.empty()) fmt::print("kept         no candidate loop closure was given\n");
    if (run.residual_threshold > 0.0) {
      std::vector<std::string> removed;
      for (const auto& c : run.candidates)
        if (c.removed_in_round > 0)
          removed.push_back(!std::isnan(c.residual_group_t)
                                ? fmt::format("{}:{} → {}:{} (its group of {}: T {:.3g}, {} dof)", c.robot_a,
                                              c.pose_a, c.robot_b, c.pose_b, c.residual_group_size,
                                              c.residual_group_t, c.residual_group_dof)
                            : std::isnan(c.snooping_t)
                                ? fmt::format("{}:{} → {}:{} (χ² {:.3g})", c.robot_a, c.pose_a, c.robot_b,
                                              c.pose_b, c.residual_chi2)
                                : fmt::format("{}:{} → {}:{} (T {:.3g}, χ² {:.3g})", c.robot_a, c.pose_a,
                                              c.robot_b, c.pose_b, c.snooping_t, c.residual_chi2));
      fmt::print(
          "residual     {} removed ({} above {:.4g}, p = {}){}{}{}; {} loop closures kept\n", removed.size(),
          run.options.residual_test == app::RobustResidualTest::snooping
              ? "data snooping's T, Bonferroni over the closures tested; first round's threshold"
          : run.options.residual_test == app::RobustResidualTest::groups
              ? "data snooping's T of closures and of groups, Bonferroni over the tests; first round's "
                "threshold of one closure"
              : "χ² at the solution",
          run.residual_threshold, run.options.residual_p, removed.empty() ? "" : ": ",
          fmt::join(removed.begin(), removed.begin() + std::min<std::ptrdiff_t>(10, std::ssize(removed)),
                    ", "),
          removed.size() > 10 ? ", …" : "", run.kept);
    }
    if (run.options.gnc != app::RobustGnc::off) {
      int rejected = 0, joins = 0;
      for (const auto& c : run.candidates) {
        rejected += !c.kept && !std::isnan(c.gnc_weight);
        joins += c.joins_robots;
      }
      int certified_rounds = 0;
      double worst_gap = 0.0;
      for (const auto& r : run.gnc_rounds) {
        certified_rounds += r.certified;
        worst_gap = std::max(worst_gap, r.relative_gap);
      }
      fmt::print(
          "gnc          TLS over {} closures, c̄² = {:.4g} (p = {}): {} round{}{}, {} rejected{}; {} loop "
          "closures kept\n",
          run.gnc_weighed, run.gnc_threshold, run.options.gnc_p, run.gnc_rounds.size(),
          run.gnc_rounds.size() == 1 ? "" : "s",
          run.gnc_converged ? " (converged)" : " (round limit: weights not settled)", rejected,
          joins > 0 ? fmt::format(", {} kept only to join robots", joins) : "", run.kept);
      if (run.options.gnc_certified_inner && !run.gnc_rounds.empty())
        fmt::print("gnc solves   {} of {} weighted solves certified{}\n", certified_rounds,
                   run.gnc_rounds.size(),
                   certified_rounds == std::ssize(run.gnc_rounds)
                       ? ""
                       : fmt::format(" (largest proven relative gap {:.3g})", worst_gap));
    }
    print_certified_summary(args.files.size() == 1 ? args.files[0] : "the robots' graphs together", s,
                            run.solved.anisotropic_cost);
    fmt::print(
        "times        odometry {:.3f} s, marginals {:.3f} s, Q {:.3f} s, cliques {:.3f} s, residual check "
        "{:.3f} s, GNC {:.3f} s, certified solve {:.3f} s\n",
        run.odometry_time_s, run.marginals_time_s, run.consistency_time_s, run.selection_time_s,
        run.residual_time_s, run.gnc_time_s, s.total_time_s);
    if (!args.out.empty() && certified) fmt::print("written      {}\n", args.out);
    if (!args.report.empty() && certified) fmt::print("written      {}\n", args.report);
  }
  if (!certified)
    throw CommandFailed(
        fmt::format("{}{}{}", s.message.starts_with("not certified") ? "" : "not certified: ", s.message,
                    args.out.empty() && args.report.empty() ? "" : " (no output written)"));
}

void run_robust(const RobustArgs& args) {
  check_option("--p", [&] {
    app::RobustOptions o;
    o.p = args.p;
    o.validate();
  });
  check_option("--composition", [&] { (void)pcm::composition_from_string(args.composition); });
  check_option("--selector", [&] { (void)app::robust_selector_from_string(args.selector); });
  check_option("--residual-p", [&] {
    app::RobustOptions o;
    o.residual_p = args.residual_p;
    o.validate();
  });
  check_option("--residual-test", [&] { (void)app::robust_residual_test_from_string(args.residual_test); });
  check_option("--group-window", [&] {
    app::RobustOptions o;
    o.group_window = args.group_window;
    o.validate();
  });
  check_option("--gnc", [&] { (void)app::robust_gnc_from_string(args.gnc); });
  check_option("--gnc-p", [&] {
    app::RobustOptions o;
    o.gnc_p = args.gnc_p;
    o.validate();
  });
  check_option("--first-solve", [&] {
    if (args.first_solve != "staircase" && args.first_solve != "rank-d")
      throw std::invalid_argument(
          fmt::format("--first-solve must be staircase or rank-d (got '{}')", args.first_solve));
  });
  check_option("--gnc-inner", [&] {
    if (args.gnc_inner != "certified" && args.gnc_inner != "local")
      throw std::invalid_argument(
          fmt::format("--gnc-inner must be certified or local (got '{}')", args.gnc_inner));
  });
  check_option("--exact-up-to", [&] {
    app::RobustOptions o;
    o.exact_up_to = args.exact_up_to;
    o.validate();
  });
  check_option("--time-limit", [&] {
    app::RobustOptions o;
    o.time_limit_s = args.time_limit_s;
    o.validate();
  });
  const Stages stage("robust", args.common.quiet);
  std::vector<std::pair<std::string, std::filesystem::path>> inputs;
  for (const auto& f : args.files) inputs.emplace_back("GRAPH", f);
  if (!args.candidates.empty()) inputs.emplace_back("--candidates", args.candidates);
  app::Outputs outputs(inputs);
  if (!args.out.empty()) outputs.file("--out", args.out, app::OutputKind::graph());
  if (!args.report.empty()) outputs.file("--report", args.report, app::OutputKind::json());
  stage(fmt::format("reading {}{}", fmt::join(args.files, ", "),
                    args.candidates.empty() ? "" : " and " + args.candidates));
  const auto ext = std::filesystem::path(args.out).extension();
  const auto format = ext == ".txt" ? graph::GraphFormat::isam : graph::GraphFormat::g2o;
  // The first graph decides the dimension; the others and the candidates are read as that.
  const app::GraphInput first = app::read_graph_input(args.files[0]);
  if (const auto* g2 = std::get_if<graph::PoseGraph2D>(&first.graph)) {
    std::vector<graph::PoseGraph2D> robots{*g2};
    for (std::size_t r = 1; r < args.files.size(); ++r)
      robots.push_back(graph::read_pose_graph_2d(args.files[r]));
    robust_files(
        args, robots,
        args.candidates.empty() ? std::vector<graph::Edge2>{} : graph::read_g2o_edges_2d(args.candidates),
        stage, outputs, format);
  } else {
    std::vector<graph::PoseGraph3D> robots{std::get<graph::PoseGraph3D>(first.graph)};
    for (std::size_t r = 1; r < args.files.size(); ++r)
      robots.push_back(graph::read_pose_graph_3d(args.files[r]));
    robust_files(
        args, robots,
        args.candidates.empty() ? std::vector<graph::Edge3>{} : graph::read_g2o_edges_3d(args.candidates),
        stage, outputs, format);
  }
}

}  // namespace

void add_robust_command(CLI::App& app) {
  auto a = std::make_shared<RobustArgs>();
  auto* c =
      app.add_subcommand("robust",
                         "one or several robots' graphs with wrong loop closures: keep the largest "
                         "pairwise-consistent set (PCM, thesis ch. 2) and solve with a global-optimality "
                         "certificate");
  c->group("Your data");
  c->add_option(
       "graphs", a->files,
       "one graph per robot (g2o or iSAM, 2D or 3D): edges i → i + 1 are the robot's trusted odometry, "
       "every other edge a candidate loop closure")
      ->required();
  c->add_option(
      "--candidates", a->candidates,
      "inter-robot candidate loop closures: g2o edges whose ids are global (robot r's pose k is k plus "
      "the poses of the robots before it, in the order given)");
  c->add_option("--p", a->p, "χ² tail probability of the consistency threshold γ (thesis PCM-Exact-11 %)")
      ->capture_default_str();
  c->add_option("--composition", a->composition, "joint (with the joint marginals) or independent")
      ->capture_default_str();
  c->add_option(
       "--selector", a->selector,
       "each group's consistent set: auto (exact up to --exact-up-to candidates, densest beyond), exact "
       "(maximum clique), heuristic (greedy clique) or densest (densest subgraph)")
      ->capture_default_str();
  c->add_option(
       "--residual-p", a->residual_p,
       "the residual check after the selection: kept closures (or groups) above their test's quantile at "
       "1 − this are removed one at a time, worst first (0: no check)")
      ->capture_default_str();
  c->add_option(
       "--residual-test", a->residual_test,
       "the residual check's statistic: groups (data snooping, rᵀQ⁻¹r with Q the least-squares residual's "
       "covariance, of each closure and of each closure's group, Bonferroni over every test: wrong closures "
       "that agree with one another), snooping (the single closures alone) or edge (χ² = rᵀΩr at the "
       "solution)")
      ->capture_default_str();
  c->add_option(
       "--group-window", a->group_window,
       "--residual-test groups: a closure's group holds the kept closures whose ends both lie within "
       "this many poses of its own")
      ->capture_default_str();
  c->add_option(
       "--gnc", a->gnc,
       "graduated non-convexity with truncated least squares, instead of the residual check: off, after "
       "(over the closures the consistency selection kept) or only (over every candidate, no PCM)")
      ->capture_default_str();
  c->add_option("--gnc-p", a->gnc_p,
                "GNC's inlier threshold: the χ² quantile at 1 − this on each closure's rᵀΩr")
      ->capture_default_str();
  c->add_option(
       "--first-solve", a->first_solve,
       "the residual check's first estimate: staircase (the certified solve) or rank-d (the certified "
       "solver's local optimum at rank d; the certified solve at the end)")
      ->capture_default_str();
  c->add_option("--gnc-inner", a->gnc_inner,
                "GNC's weighted solves: certified (each with its certificate or gap) or local "
                "(Levenberg–Marquardt; the answer is certified either way)")
      ->capture_default_str();
  c->add_option("--exact-up-to", a->exact_up_to,
                "auto: the exact clique for groups of at most this many candidates")
      ->capture_default_str();
  c->add_option("--time-limit", a->time_limit_s,
                "stop the exact clique search after this many seconds (0: none)")
      ->capture_default_str();
  c->add_option("--out", a->out,
                "write the solved graph (odometry and kept closures) here, if certified (.g2o or .txt)");
  c->add_option("--report", a->report, "write the JSON report (every candidate: kept or not, and why) here");
  c->add_option("--threads", a->threads, "threads for Q (the result does not depend on it); 0 = all cores")
      ->capture_default_str();
  add_common(c, a->common);
  c->callback([a] { run_robust(*a); });
}

}  // namespace keel::cli
