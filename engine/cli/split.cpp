// keel split GRAPH --ground-truth T — a two-robot split with generated outliers (the Table 2.1 set-up);
// keel split GRAPH --robots N — N robots of consecutive poses with wrong loop closures added, for keel
// robust. <variant> before the imports (docs/TOOLCHAIN.md; as in marginals.cpp).
#include <variant>

import keel.core;
import keel.graph;
import keel.pgo;
import keel.sim;
import keel.app;

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <type_traits>

#include "tool_common.hpp"

namespace keel::cli {

namespace {

struct SplitArgs {
  Common common;
  std::string graph, ground_truth, out_dir;
  app::SplitFilesOptions options;
  // --robots mode
  int robots = 0;  // 0: the two-robot Table 2.1 split (--ground-truth)
  double wrong_rate = 0.0;
  std::string wrong_kind = "random";
  int group_size = 5;
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

// keel split GRAPH --robots N: app::robot_files.
void run_robots(const SplitArgs& a) {
  app::RobotFilesOptions o;
  o.robots = a.robots;
  o.wrong.rate = a.wrong_rate;
  o.wrong.group_size = a.group_size;
  o.seed = a.options.seed;
  check_option("--robots", [&] {
    if (a.robots < 1) throw std::invalid_argument(fmt::format("--robots must be >= 1 (got {})", a.robots));
  });
  check_option("--wrong-kind", [&] { o.wrong.kind = sim::wrong_closure_kind_from_string(a.wrong_kind); });
  check_option("--wrong-rate/--group-size", [&] { o.wrong.validate(); });
  const Stages stage("split", a.common.quiet);
  app::Outputs outputs({{"graph", a.graph}});
  // Robot files of an earlier split into more robots would stay beside the new ones: refused.
  for (int r = a.robots;; ++r) {
    const auto stale = std::filesystem::path(a.out_dir) / fmt::format("robot{}.g2o", r);
    if (!std::filesystem::exists(stale)) break;
    throw app::OutputError(fmt::format(
        "--out-dir: {} holds {} from an earlier split into more robots; it would be left beside the {} new "
        "robot files (remove it, or choose another folder)",
        a.out_dir, stale.filename().string(), a.robots));
  }
  const auto staging = outputs.folder("--out-dir", a.out_dir, app::robot_folder_files(a.robots));
  stage(fmt::format("reading {}", a.graph));
  const auto any = app::read_graph(a.graph);
  int wrong = 0;
  std::size_t poses = 0;
  std::visit(
      [&](const auto& g) {
        if constexpr (std::is_same_v<std::decay_t<decltype(g)>, graph::PoseGraph2D> ||
                      std::is_same_v<std::decay_t<decltype(g)>, graph::PoseGraph3D>) {
          poses = g.poses.size();
          wrong = app::robot_files(g, o, staging);
        }
      },
      any);
  outputs.commit();
  if (a.common.json) {
    fmt::print("{}\n", json{{"out_dir", a.out_dir},
                            {"robots", a.robots},
                            {"poses", poses},
                            {"wrong_closures", wrong},
                            {"wrong_kind", a.wrong_kind},
                            {"seed", a.options.seed}}
                           .dump(1));
    return;
  }
  fmt::print("robots       {} of consecutive poses ({} poses)\n", a.robots, poses);
  fmt::print("wrong        {} {} loop closures added ({} % of all loop closures; seed {})\n", wrong,
             a.wrong_kind, 100.0 * a.wrong_rate, a.options.seed);
  fmt::print("written      {}/{{robot0.g2o{}{}, closures.txt}}\n", a.out_dir,
             a.robots > 1 ? fmt::format(" … robot{}.g2o", a.robots - 1) : "",
             a.robots > 1 ? ", candidates.g2o" : "");
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
      "with outliers (the set-up of thesis Table 2.1), or with --robots N any graph into N robots with wrong "
      "loop closures added (keel robust's inputs)");
  c->group("Your data");
  c->add_option("graph", a->graph, "the single-robot graph")->required();
  c->add_option("--ground-truth", a->ground_truth,
                "ground-truth poses, lines 'id x y theta' (required without --robots)");
  c->add_option(
       "--out-dir", a->out_dir,
       "folder for a.g2o, b.g2o, candidates.g2o, labels.txt, truth.txt, or with --robots N robot0.g2o … "
       "robot<N-1>.g2o, candidates.g2o and closures.txt (created; files of these names are replaced only "
       "as the whole set an earlier keel split wrote)")
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
  c->add_option(
      "--robots", a->robots,
      "instead of the two-robot split: this many robots of consecutive poses (2D or 3D, any graph), "
      "each robot's own loop closures in its file and the closures between robots in "
      "candidates.g2o, for keel robust");
  c->add_option(
       "--wrong-rate", a->wrong_rate,
       "--robots: wrong loop closures added before the cut, as a share of all loop closures, in [0, 1)")
      ->capture_default_str();
  c->add_option("--wrong-kind", a->wrong_kind,
                "--robots: random (uniform pose pairs and measurements) or aliased (groups of mutually "
                "consistent wrong closures, thesis §2.7.2)")
      ->capture_default_str();
  c->add_option("--group-size", a->group_size, "--robots: members of an aliased group")
      ->capture_default_str();
  add_common(c, a->common);
  c->callback([a, c] {
    // The options of the other mode would be ignored silently: given, they are a bad command line (exit 2).
    const bool robots = c->get_option("--robots")->count() > 0;
    constexpr const char* kTwoRobot[] = {"--ground-truth", "--first",          "--split",
                                         "--last",         "--inliers",        "--aliased-groups",
                                         "--aliased-size", "--random-outliers"};
    constexpr const char* kRobots[] = {"--wrong-rate", "--wrong-kind", "--group-size"};
    for (const char* name :
         robots ? std::span<const char* const>(kTwoRobot) : std::span<const char* const>(kRobots))
      if (c->get_option(name)->count() > 0)
        throw CLI::ValidationError(name, robots ? "belongs to the two-robot split (without --robots)"
                                                : "applies only with --robots");
    if (robots) return run_robots(*a);
    if (a->ground_truth.empty())
      throw CLI::ValidationError("--ground-truth",
                                 "is required (or --robots N: robots of consecutive poses for keel robust)");
    check_split_options(*a);
    run_split(*a);
  });
}

}  // namespace keel::cli
