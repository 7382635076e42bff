// keel pcm --a A --b B --candidates C — pairwise consistency maximization of inter-robot loop closures on a
// user's files (app::pcm: thesis §2.6 steps i–iv).
// <variant> before the imports (docs/TOOLCHAIN.md; as in marginals.cpp).
#include <variant>

import keel.core;
import keel.lie;
import keel.graph;
import keel.pgo;
import keel.pcm;
import keel.merge;
import keel.app;

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tool_common.hpp"

namespace keel::cli {

namespace {

struct PcmArgs {
  Common common;
  std::string a, b, candidates, labels, merged, out;
  double p = 0.11;
  std::string composition = "joint", algorithm = "exact";
  double time_limit_s = 0.0;
  unsigned threads = 1;
};

template <class Run>
void report_pcm(const PcmArgs& args, const Run& run, const std::optional<std::vector<bool>>& inlier,
                const Stages& stage, app::Outputs& outputs) {
  const auto& sel = run.selection;
  const auto& search = *sel.search;
  const int n = run.q.n;
  // How many pairs are consistent: the edges of the consistency graph whose maximum clique was searched.
  const long long consistent_pairs = pcm::ConsistencyGraph::from_threshold(n, run.q.q, run.gamma).num_edges();
  const long long all_pairs = static_cast<long long>(n) * (n - 1) / 2;
  json selected = json::array();
  for (int k : sel.selected) {
    const auto& c = run.candidates[static_cast<std::size_t>(k)];
    selected.push_back({{"candidate", k}, {"pose_a", c.pose_a}, {"pose_b", c.pose_b}});
  }
  json j = {{"candidates", n},
            {"dof", run.q.dof},
            {"p", args.p},
            {"gamma", run.gamma},
            {"composition", args.composition},
            {"algorithm", args.algorithm},
            {"selected", selected},
            {"status", std::string(keel::core::to_string(search.status))},
            {"upper_bound", search.upper_bound},
            {"consistent_pairs", consistent_pairs},
            {"pairs", all_pairs},
            {"local_solve_time_s", {run.a.solve_time_s, run.b.solve_time_s}},
            {"marginals_time_s", run.marginals_time_s},
            {"consistency_time_s", run.consistency_time_s},
            {"selection_time_s", sel.time_s}};
  std::optional<app::SelectionScore> score;
  if (inlier) {
    score = app::score_selection(sel.selected, *inlier);
    j["true_positives"] = score->true_positives;
    j["false_positives"] = score->false_positives;
    j["tpr"] = score->tpr;
    j["fpr"] = score->fpr;
  }
  if (run.merged) {
    j["merged"] = {{"file", args.merged}, {"summary", record_json(run.merged->summary)}};
  }
  if (!args.out.empty()) {
    json full = j;
    full["q"] = run.q.q;
    write_json(outputs, args.out, full);
  }
  outputs.commit();
  if (!args.merged.empty()) stage(fmt::format("wrote {}", args.merged));
  if (!args.out.empty()) stage(fmt::format("wrote {}", args.out));
  if (args.common.json) {
    fmt::print("{}\n", j.dump(1));
    return;
  }
  fmt::print("candidates   {} ({}D, {} dof per loop error)\n", n, run.q.dof == 3 ? 2 : 3, run.q.dof);
  fmt::print("threshold    γ = {:.6g} (p = {}, χ²({}) tail), {} composition\n", run.gamma, args.p, run.q.dof,
             args.composition);
  fmt::print("consistent   {} of {} pairs ({:.2f} %)\n", consistent_pairs, all_pairs,
             all_pairs ? 100.0 * consistent_pairs / all_pairs : 0.0);
  fmt::print("selected     {} candidates: {} ({}, bound {})\n", sel.selected.size(),
             fmt::join(sel.selected, " "), keel::core::to_string(search.status), search.upper_bound);
  if (!search.proven_optimal()) {
    fmt::print("             not proven maximum: a larger consistent set may exist (at most {})\n",
               search.upper_bound);
  }
  if (score) {
    fmt::print("labels       TPR {:.4f}, FPR {:.4f} ({} true, {} false positives)\n", score->tpr, score->fpr,
               score->true_positives, score->false_positives);
  }
  fmt::print("time         local solves {:.3f} + {:.3f} s, marginals {:.3f} s, Q {:.3f} s, clique {:.3f} s\n",
             run.a.solve_time_s, run.b.solve_time_s, run.marginals_time_s, run.consistency_time_s,
             sel.time_s);
  if (run.merged) {
    fmt::print("merged       {} ({} poses); normalized χ² {:.6g}\n", args.merged,
               run.merged->poses_a.size() + run.merged->poses_b.size(), run.merged->summary.normalized_chi2);
  }
  if (!args.out.empty()) fmt::print("written      {}\n", args.out);
}

template <class Graph, class Edges>
void pcm_files(const PcmArgs& args, const Graph& a, const Graph& b, const Edges& candidates,
               const Stages& stage, app::Outputs& outputs) {
  // The labels are read and counted before the work.
  std::optional<std::vector<bool>> inlier;
  if (!args.labels.empty()) {
    inlier = app::read_labels(args.labels);
    if (inlier->size() != candidates.size()) {
      throw std::invalid_argument(fmt::format("{}: {} labels for {} candidates in {}", args.labels,
                                              inlier->size(), candidates.size(), args.candidates));
    }
  }
  app::PcmOptions o;
  o.p = args.p;
  o.composition = pcm::composition_from_string(args.composition);
  o.algorithm = pcm::clique_algorithm_from_string(args.algorithm);
  o.time_limit_s = args.time_limit_s;
  o.threads = args.threads;
  o.merge = !args.merged.empty();
  const auto run = app::pcm(a, b, candidates, o, stage.progress());
  if (run.merged) {
    check_solved(run.merged->summary);
    outputs.write(args.merged, [&](const std::filesystem::path& temporary) {
      graph::write_pose_graph(app::merged_graph(run), temporary);
    });
  }
  report_pcm(args, run, inlier, stage, outputs);
}

// The option values, each by the engine's own check (check_option: a refusal is exit 2 naming the option),
// before any file is read. --time-limit, when given, is a number of seconds > 0 (left out: no limit).
void check_pcm_options(const PcmArgs& args, bool time_limit_given) {
  check_option("--p", [&] {
    app::PcmOptions o;
    o.p = args.p;
    o.validate();
  });
  check_option("--composition", [&] { (void)pcm::composition_from_string(args.composition); });
  check_option("--algorithm", [&] { (void)pcm::clique_algorithm_from_string(args.algorithm); });
  check_option("--time-limit", [&] {
    if (time_limit_given && !(args.time_limit_s > 0.0))
      throw std::invalid_argument(fmt::format(
          "{} s: give a time limit > 0 seconds, or leave the option out for no limit", args.time_limit_s));
    app::PcmOptions o;
    o.time_limit_s = args.time_limit_s;
    o.validate();
  });
}

void run_pcm_command(const PcmArgs& args) {
  const auto ext = std::filesystem::path(args.merged).extension();
  if (!args.merged.empty() && ext != ".g2o" && ext != ".txt")
    throw CLI::ValidationError(
        "--merged", fmt::format("{}: give a .g2o (g2o) or .txt (iSAM text) file name", args.merged));
  const Stages stage("pcm", args.common.quiet);
  app::Outputs outputs(
      {{"--a", args.a}, {"--b", args.b}, {"--candidates", args.candidates}, {"--labels", args.labels}});
  if (!args.merged.empty()) outputs.file("--merged", args.merged, app::OutputKind::graph());
  if (!args.out.empty()) outputs.file("--out", args.out, app::OutputKind::json());
  stage(fmt::format("reading {}, {} and {}", args.a, args.b, args.candidates));
  // Robot a's file is read once (a pipe works); its dimension decides how b and the candidates are read.
  const auto graph_a = app::read_graph(args.a);
  if (const auto* a2 = std::get_if<graph::PoseGraph2D>(&graph_a)) {
    pcm_files(args, *a2, graph::read_pose_graph_2d(args.b), graph::read_g2o_edges_2d(args.candidates), stage,
              outputs);
  } else {
    pcm_files(args, std::get<graph::PoseGraph3D>(graph_a), graph::read_pose_graph_3d(args.b),
              graph::read_g2o_edges_3d(args.candidates), stage, outputs);
  }
}

}  // namespace

void add_pcm_command(CLI::App& app) {
  auto a = std::make_shared<PcmArgs>();
  auto* c = app.add_subcommand(
      "pcm", "pairwise consistency maximization of inter-robot loop closures (thesis §2.6) on your files");
  c->group("Your data");
  c->add_option("--a", a->a, "robot a's graph (g2o or iSAM)")->required();
  c->add_option("--b", a->b, "robot b's graph")->required();
  c->add_option("--candidates", a->candidates,
                "candidate loop closures: g2o edges 'EDGE_SE2 i j …' with i a pose of robot a and j a pose "
                "of robot b (EDGE_SE3:QUAT in 3D)")
      ->required();
  c->add_option("--p", a->p, "χ² tail probability of the consistency threshold γ (thesis PCM-Exact-11 %)")
      ->capture_default_str();
  c->add_option("--composition", a->composition, "joint (eq. 2.4 with the joint marginals) or independent")
      ->capture_default_str();
  c->add_option("--algorithm", a->algorithm, "maximum clique: exact or heuristic")->capture_default_str();
  auto* time_limit =
      c->add_option("--time-limit", a->time_limit_s, "stop the exact search after this many seconds (> 0)");
  c->add_option("--labels", a->labels, "labels.txt of keel split: score the selection (TPR, FPR)");
  c->add_option("--merged", a->merged, "solve the merged map with the selected candidates and write it here");
  c->add_option("--out", a->out, "write the result and the consistency matrix Q to this JSON file");
  c->add_option("--threads", a->threads, "threads for Q (the result does not depend on it); 0 = all cores")
      ->capture_default_str();
  add_common(c, a->common);
  c->callback([a, time_limit] {
    check_pcm_options(*a, time_limit->count() > 0);
    run_pcm_command(*a);
  });
}

}  // namespace keel::cli
