// keel split GRAPH --ground-truth T — a two-robot split with generated outliers (the Table 2.1 set-up).
// <variant> before the imports (docs/TOOLCHAIN.md; as in marginals.cpp).
#include <variant>

import keel.core;
import keel.graph;
import keel.pgo;
import keel.sim;
import keel.app;

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <limits>
#include <memory>
#include <string>

#include "tool_common.hpp"

namespace keel::cli {

namespace {

struct SplitArgs {
  Common common;
  std::string graph, ground_truth, out_dir;
  app::SplitFilesOptions options;
};

// The option values, each by the engine's own check (check_option: a refusal is exit 2 naming the option),
// before any file is read: the counts (CandidateOptions::validate) and the split's order (SplitOptions::
// validate with any pose count; `--last` against the graph's pose count is checked once it is read).
void check_split_options(const SplitArgs& a) {
  const auto& c = a.options.candidates;
  const auto check = [](const char* option, auto set) {
    sim::CandidateOptions o;
    set(o);
    check_option(option, [&] { o.validate(); });
  };
  check("--inliers", [&](sim::CandidateOptions& o) { o.num_inliers = c.num_inliers; });
  check("--aliased-groups/--aliased-size", [&](sim::CandidateOptions& o) {
    o.aliased_groups = c.aliased_groups;
    o.aliased_group_size = c.aliased_group_size;
  });
  check("--random-outliers", [&](sim::CandidateOptions& o) { o.random_outliers = c.random_outliers; });
  check_option("--first/--split/--last", [&] { a.options.split.validate(std::numeric_limits<int>::max()); });
}

void run_split(const SplitArgs& a) {
  const Stages stage("split", a.common.quiet);
  app::Outputs outputs({{"graph", a.graph}, {"--ground-truth", a.ground_truth}});
  const auto staging = outputs.folder("--out-dir", a.out_dir, app::split_folder_files());
  stage(fmt::format("reading {} and {}", a.graph, a.ground_truth));
  const auto any = app::read_graph(a.graph);  // read once: a pipe works
  if (!std::holds_alternative<graph::PoseGraph2D>(any)) {
    throw std::invalid_argument(fmt::format("{}: keel split supports 2D graphs", a.graph));
  }
  const auto& g = std::get<graph::PoseGraph2D>(any);
  const auto truth = graph::read_poses_2d(a.ground_truth);
  const auto set = app::split_files(g, truth, a.options, staging);
  outputs.commit();
  const int inliers = static_cast<int>(set.inliers().size());
  const auto& s = a.options.split;
  if (a.common.json) {
    fmt::print("{}\n", json{{"out_dir", a.out_dir},
                            {"robot_a", {s.first, s.split}},
                            {"robot_b", {s.split, s.last}},
                            {"candidates", set.candidates.size()},
                            {"inliers", inliers}}
                           .dump(1));
    return;
  }
  fmt::print("robots       a = poses [{}, {}), b = [{}, {})\n", s.first, s.split, s.split, s.last);
  fmt::print("candidates   {} ({} inliers, {} aliased, {} random outliers; seed {})\n", set.candidates.size(),
             inliers, a.options.candidates.aliased_groups * a.options.candidates.aliased_group_size,
             a.options.candidates.random_outliers, a.options.seed);
  fmt::print("written      {}/{{a.g2o, b.g2o, candidates.g2o, labels.txt, truth.txt}}\n", a.out_dir);
}

}  // namespace

void add_split_command(CLI::App& app) {
  auto a = std::make_shared<SplitArgs>();
  auto& o = a->options;
  o.split.first = 0;
  o.split.split = 750;
  o.split.last = 1500;
  auto* c = app.add_subcommand(
      "split",
      "split a single-robot 2D graph with ground truth into two robots and candidate loop closures "
      "with outliers (the set-up of thesis Table 2.1)");
  c->group("Your data");
  c->add_option("graph", a->graph, "the single-robot graph")->required();
  c->add_option("--ground-truth", a->ground_truth, "ground-truth poses, lines 'id x y theta'")->required();
  c->add_option(
       "--out-dir", a->out_dir,
       "folder for a.g2o, b.g2o, candidates.g2o, labels.txt, truth.txt (created; files of these names "
       "are replaced only as the whole set an earlier keel split wrote)")
      ->required();
  c->add_option("--first", o.split.first, "first pose of robot a")->capture_default_str();
  c->add_option("--split", o.split.split, "first pose of robot b")->capture_default_str();
  c->add_option("--last", o.split.last, "one past the last pose of robot b")->capture_default_str();
  c->add_option("--inliers", o.candidates.num_inliers, "true loop closures drawn")->capture_default_str();
  c->add_option("--aliased-groups", o.candidates.aliased_groups, "groups of mutually consistent outliers")
      ->capture_default_str();
  c->add_option("--aliased-size", o.candidates.aliased_group_size, "outliers per group")
      ->capture_default_str();
  c->add_option("--random-outliers", o.candidates.random_outliers, "random outliers")->capture_default_str();
  c->add_option("--seed", o.seed, "seed of the draw")->capture_default_str();
  add_common(c, a->common);
  c->callback([a] {
    check_split_options(*a);
    run_split(*a);
  });
}

}  // namespace keel::cli
