// keel robust GRAPH — one robot's graph with wrong loop closures (app::robust): the odometry trusted, the other
// edges candidates, the largest pairwise-consistent set of them (thesis eqs. 2.4–2.5, the relative poses from
// the odometry map's joint marginals), then the certified solve of the odometry and the kept closures.
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

#include <filesystem>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "tool_common.hpp"

namespace keel::cli {

namespace {

struct RobustArgs {
  Common common;
  std::string file, out, report;
  double p = 0.11;
  std::string composition = "joint", algorithm = "exact";
  double time_limit_s = 0.0;
  unsigned threads = 1;
};

// Every candidate with its poses, whether it was kept, and why: a closure left out is inconsistent (q above γ
// either way) with at least one kept closure, counted here.
template <class Run>
json robust_candidates_json(const Run& run) {
  std::vector<char> kept(run.candidates.size(), 0);
  for (const int k : run.selection.selected) kept[static_cast<std::size_t>(k)] = 1;
  json list = json::array();
  for (std::size_t k = 0; k < run.candidates.size(); ++k) {
    int against = 0;
    for (const int s : run.selection.selected)
      if (run.q.at(static_cast<int>(k), s) > run.gamma || run.q.at(s, static_cast<int>(k)) > run.gamma) ++against;
    list.push_back({{"candidate", k},
                    {"edge", run.candidate_edges[k]},
                    {"i", run.candidates[k].pose_a},
                    {"j", run.candidates[k].pose_b},
                    {"kept", kept[k] != 0},
                    {"inconsistent_with_kept", against},
                    {"reason", kept[k] ? "in the largest pairwise-consistent set"
                                       : fmt::format("inconsistent with {} kept closure{}", against,
                                                     against == 1 ? "" : "s")}});
  }
  return list;
}

template <class Graph>
void robust_file(const RobustArgs& args, const Graph& g, const Stages& stage, app::Outputs& outputs,
                 graph::GraphFormat format) {
  app::RobustOptions o;
  o.p = args.p;
  o.composition = pcm::composition_from_string(args.composition);
  o.algorithm = pcm::clique_algorithm_from_string(args.algorithm);
  o.time_limit_s = args.time_limit_s;
  o.threads = args.threads;
  const auto run = app::robust(g, o, stage.progress());
  const auto& s = run.solved.summary;
  const bool certified = s.certificate.certified;
  const auto& search = run.selection.search;
  json j = {{"file", args.file},
            {"poses", g.poses.size()},
            {"odometry_edges", run.odometry.edges.size()},
            {"candidates", run.candidates.size()},
            {"kept", run.selection.selected.size()},
            {"p", args.p},
            {"gamma", run.gamma},
            {"composition", args.composition},
            {"algorithm", args.algorithm},
            {"clique_status", search ? std::string(core::to_string(search->status)) : "none (no candidates)"},
            {"clique_upper_bound", search ? json(search->upper_bound) : json(0)},
            {"times_s",
             {{"odometry", run.odometry_time_s},
              {"marginals", run.marginals_time_s},
              {"consistency", run.consistency_time_s},
              {"selection", run.selection.time_s},
              {"certified_solve", s.total_time_s}}},
            {"anisotropic_cost", std::isfinite(run.solved.anisotropic_cost) ? json(run.solved.anisotropic_cost) : json(nullptr)},
            {"certificate", record_json(s)}};
  const json candidates = robust_candidates_json(run);
  // Outputs are written only on exit 0 (a certified answer), all or nothing (app::Outputs).
  if (certified) {
    if (!args.out.empty()) {
      const auto& solved = run.solved.graph;
      outputs.write(args.out, [&](const std::filesystem::path& temporary) {
        if (format == graph::GraphFormat::g2o)
          graph::write_g2o(solved, temporary);
        else
          graph::write_isam(solved, temporary);
      });
    }
    if (!args.report.empty()) {
      json full = j;
      full["candidate_list"] = candidates;
      write_json(outputs, args.report, full);
    }
    outputs.commit();
  }
  if (args.common.json) {
    json full = j;
    full["candidate_list"] = candidates;
    fmt::print("{}\n", full.dump(1));
  } else {
    fmt::print("graph        {} ({} poses, {} odometry edges, {} candidate loop closures)\n", args.file,
               g.poses.size(), run.odometry.edges.size(), run.candidates.size());
    if (search) {
      fmt::print("threshold    γ = {:.6g} (p = {}, χ²({}) tail), {} composition in the odometry map\n", run.gamma,
                 args.p, run.q.dof, args.composition);
      fmt::print("kept         {} of {} loop closures ({}, bound {}){}\n", run.selection.selected.size(),
                 run.candidates.size(), core::to_string(search->status), search->upper_bound,
                 search->proven_optimal() ? "" : ": not proven the largest consistent set");
    }
    print_certified_summary(args.file, s, run.solved.anisotropic_cost);
    fmt::print("times        odometry {:.3f} s, marginals {:.3f} s, Q {:.3f} s, clique {:.3f} s, certified solve "
               "{:.3f} s\n",
               run.odometry_time_s, run.marginals_time_s, run.consistency_time_s, run.selection.time_s,
               s.total_time_s);
    if (!args.out.empty() && certified) fmt::print("written      {}\n", args.out);
    if (!args.report.empty() && certified) fmt::print("written      {}\n", args.report);
  }
  if (!certified)
    throw CommandFailed(fmt::format("not certified: {}{}", s.message,
                                    args.out.empty() && args.report.empty() ? "" : " (no output written)"));
}

void run_robust(const RobustArgs& args) {
  check_option("--p", [&] {
    app::RobustOptions o;
    o.p = args.p;
    o.validate();
  });
  check_option("--composition", [&] { (void)pcm::composition_from_string(args.composition); });
  check_option("--algorithm", [&] { (void)pcm::clique_algorithm_from_string(args.algorithm); });
  check_option("--time-limit", [&] {
    app::RobustOptions o;
    o.time_limit_s = args.time_limit_s;
    o.validate();
  });
  const Stages stage("robust", args.common.quiet);
  app::Outputs outputs({{"file", args.file}});
  if (!args.out.empty()) outputs.file("--out", args.out, app::OutputKind::graph());
  if (!args.report.empty()) outputs.file("--report", args.report, app::OutputKind::json());
  stage(fmt::format("reading {}", args.file));
  const app::GraphInput input = app::read_graph_input(args.file);
  const auto ext = std::filesystem::path(args.out).extension();
  const auto format = ext == ".txt" ? graph::GraphFormat::isam : graph::GraphFormat::g2o;
  std::visit([&](const auto& g) { robust_file(args, g, stage, outputs, format); }, input.graph);
}

}  // namespace

void add_robust_command(CLI::App& app) {
  auto a = std::make_shared<RobustArgs>();
  auto* c = app.add_subcommand(
      "robust",
      "one robot's graph with wrong loop closures: keep the largest pairwise-consistent set (PCM, thesis ch. 2) "
      "and solve with a global-optimality certificate");
  c->group("Your data");
  c->add_option("file", a->file,
                "the graph (g2o or iSAM, 2D or 3D): edges i → i + 1 are the trusted odometry, every other edge "
                "a candidate loop closure")
      ->required();
  c->add_option("--p", a->p, "χ² tail probability of the consistency threshold γ (thesis PCM-Exact-11 %)")
      ->capture_default_str();
  c->add_option("--composition", a->composition, "joint (with the joint marginals) or independent")
      ->capture_default_str();
  c->add_option("--algorithm", a->algorithm, "maximum clique: exact or heuristic")->capture_default_str();
  c->add_option("--time-limit", a->time_limit_s, "stop the exact clique search after this many seconds (0: none)")
      ->capture_default_str();
  c->add_option("--out", a->out, "write the solved graph (odometry and kept closures) here, if certified (.g2o or .txt)");
  c->add_option("--report", a->report, "write the JSON report (every candidate: kept or not, and why) here");
  c->add_option("--threads", a->threads, "threads for Q (the result does not depend on it); 0 = all cores")
      ->capture_default_str();
  add_common(c, a->common);
  c->callback([a] { run_robust(*a); });
}

}  // namespace keel::cli
