#include "study/ch4/robust_backend.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/statistics.hpp"
#include "core/timing.hpp"
#include "datasets/manifest.hpp"
#include "graph/io.hpp"
#include "graph/trajectory_error.hpp"
#include "pgo/certified.hpp"
#include "study/ch4/certified_pgo.hpp"

namespace keel::study::ch4 {

using repro::Figure;
using repro::Layer;
using repro::Panel;
using repro::Results;
using repro::RunContext;

RobustBackend::Options RobustBackend::Options::read(const core::ConfigTable& p) {
  Options o;
  o.robust.p = p.number("p");
  o.robust.residual_p = p.number("residual_p");
  o.robust.exact_up_to = static_cast<int>(p.integer("exact_up_to"));
  o.robust.time_limit_s = p.number("clique_time_limit_s");
  // The residual check's statistic; absent: the edge χ² test this experiment was registered with, whatever
  // keel robust's own default is.
  o.robust.residual_test =
      p.parse_or("residual_test", merge::robust_residual_test_from_string, merge::RobustResidualTest::edge);
  o.robust.group_window = static_cast<int>(p.integer_or("group_window", o.robust.group_window));
  // The residual check's first estimate; absent: the certified solve, as registered.
  const std::string first = p.string_or("first_solve", "staircase");
  if (first != "staircase" && first != "rank-d")
    throw core::ConfigError(
        fmt::format("{}: first_solve must be staircase or rank-d, not '{}'", p.where("first_solve"), first));
  o.robust.first_solve_rank_d = first == "rank-d";  // not keel robust's default: absent, as registered
  o.robust.solve = read_certified_solve(p);
  o.robust.solve.time_limit_s = p.number("solve_time_limit_s");
  o.robust.threads = 1;  // the trials run in parallel, each on one thread
  p.validate(o.robust);
  for (const double r : p.numbers("rates")) {
    if (!(r >= 0 && r < 1))
      throw core::ConfigError(fmt::format("{}: every rate must be in [0, 1), not {}", p.where("rates"), r));
    o.rates.push_back(r);
  }
  for (const std::string& k : p.strings("kinds")) {
    try {
      o.kinds.push_back(sim::wrong_closure_kind_from_string(k));
    } catch (const std::invalid_argument& e) {
      throw core::ConfigError(fmt::format("{}: {}", p.where("kinds"), e.what()));
    }
  }
  for (const double r : p.numbers("robots")) {
    if (!(r >= 1 && r == std::floor(r)))
      throw core::ConfigError(
          fmt::format("{}: robot counts are integers >= 1, not {}", p.where("robots"), r));
    o.robots.push_back(static_cast<int>(r));
  }
  o.group_size = static_cast<int>(p.integer("aliased_group_size"));
  sim::WrongClosures w;
  w.group_size = o.group_size;
  p.validate(w);
  o.trials = static_cast<int>(p.count("trials"));
  for (const GraphPrefix& g : read_graph_prefixes(p))
    o.graphs.push_back({g.file.name, g.file.dataset, g.file.file, g.file.dimension, g.poses});
  return o;
}

std::vector<RobustBackendCell> RobustBackend::make_cells(const Options& o) {
  std::vector<RobustBackendCell> cells;
  for (std::size_t g = 0; g < o.graphs.size(); ++g)
    for (const int robots : o.robots) {
      const repro::KeyPath base = repro::path(o.graphs[g].name).under(fmt::format("r{}", robots));
      for (const double rate : o.rates) {
        if (rate == 0) {
          cells.push_back({g, robots, sim::WrongClosureKind::random, 0.0, base.under("clean")});
          continue;
        }
        for (const auto kind : o.kinds)
          cells.push_back(
              {g, robots, kind, rate,
               base.under(sim::to_string(kind)).under(fmt::format("out{}", std::llround(100 * rate)))});
      }
    }
  return cells;
}

namespace {

// Consecutive poses of one robot: the pairs of RPE.
std::vector<std::pair<int, int>> backend_rpe_pairs(int n, int robots) {
  std::vector<std::pair<int, int>> out;
  for (int k = 0; k + 1 < n; ++k)
    if (sim::robot_of_pose(k, n, robots) == sim::robot_of_pose(k + 1, n, robots)) out.emplace_back(k, k + 1);
  return out;
}

template <class Graph>
RobustBackendReference backend_reference(const Graph& clean, std::size_t g, int robots,
                                         const pgo::CertifiedOptions& solve) {
  // Every robot's odometry and every true loop closure: the graph without the odometry edges that join
  // two robots (which sim::split_into_robots drops).
  Graph h = clean;
  const int n = static_cast<int>(h.poses.size());
  std::erase_if(h.edges, [&](const auto& e) {
    return std::abs(e.i - e.j) == 1 &&
           sim::robot_of_pose(e.i, n, robots) != sim::robot_of_pose(e.j, n, robots);
  });
  RobustBackendReference ref;
  ref.graph = g;
  ref.robots = robots;
  auto r = pgo::solve_certified(h, solve);
  ref.certified = r.summary.certificate.certified;
  ref.cost = r.summary.final_cost;
  ref.relative_gap = r.summary.certificate.proven ? r.summary.certificate.bound.relative_gap_up() : 1.0;
  ref.time_s = r.summary.total_time_s;
  if constexpr (std::is_same_v<Graph, graph::PoseGraph2D>)
    ref.poses2 = std::move(r.poses);
  else
    ref.poses3 = std::move(r.poses);
  return ref;
}

template <class Graph, class Pose>
void backend_trial(const Graph& clean, const RobustBackendCell& cell, const RobustBackend::Options& o,
                   const core::Streams& streams, const std::vector<Pose>& reference, RobustBackendTrial& t) {
  const auto corrupted = RobustBackend::trial_graph(clean, o, cell, t.trial, streams);
  const int n_clean = static_cast<int>(clean.edges.size());
  t.true_closures = static_cast<int>(corrupted.loop_closures.size() - corrupted.outliers.size());
  t.wrong_closures = static_cast<int>(corrupted.outliers.size());
  const auto split = sim::split_into_robots(corrupted.graph, cell.robots);
  const auto t0 = core::Clock::now();
  try {
    const auto run = merge::robust(split.robots, split.inter, o.robust);
    t.time_s = core::seconds_since(t0);
    t.cliques_proven = std::all_of(run.groups.begin(), run.groups.end(), [](const merge::RobustGroup& g) {
      return g.selection.search && g.selection.search->status == core::SearchStatus::optimal;
    });
    for (const auto& c : run.candidates) {
      const int e =
          c.source >= 0
              ? split.robot_edge[static_cast<std::size_t>(c.source)][static_cast<std::size_t>(c.edge)]
              : split.inter_edge[static_cast<std::size_t>(c.edge)];
      const bool wrong = e >= n_clean;
      if (c.kept) ++(wrong ? t.kept_wrong : t.kept_true);
      if (c.removed_in_round > 0) ++(wrong ? t.removed_wrong : t.removed_true);
    }
    const auto& s = run.solved.summary;
    t.certified = s.certificate.certified;
    t.proven = s.certificate.proven;
    t.relative_gap = s.certificate.proven ? s.certificate.bound.relative_gap_up() : 1.0;
    t.cost = s.final_cost;
    t.residual_rounds = run.residual_rounds;
    t.consistency_time_s = run.marginals_time_s + run.consistency_time_s;
    t.selection_time_s = run.selection_time_s;
    t.residual_time_s = run.residual_time_s;
    t.solve_time_s = s.total_time_s;
    const auto& poses = run.solved.graph.poses;
    t.ate = graph::absolute_trajectory_error(reference, poses);
    t.rpe = graph::relative_pose_error(reference, poses,
                                       backend_rpe_pairs(static_cast<int>(poses.size()), cell.robots));
  } catch (const std::exception& e) {  // a refusal is a result of the trial, reported with its reason
    t.time_s = core::seconds_since(t0);
    t.refused = true;
    t.error = e.what();
  }
}

template <class Graph>
auto backend_trial_graph(const Graph& clean, const RobustBackend::Options& o, const RobustBackendCell& cell,
                         int trial, const core::Streams& streams) {
  sim::WrongClosures w;
  w.rate = cell.rate;
  w.kind = cell.kind;
  w.group_size = o.group_size;
  // The stream of (graph, trial) in the kind's family: every robot count and rate of a trial sees the same
  // draws (a higher rate adds to a lower one's wrong closures).
  return sim::add_wrong_loop_closures(
      clean, w, streams.child("wrong_closures").child(std::string(sim::to_string(cell.kind))),
      cell.graph * static_cast<std::uint64_t>(o.trials) + static_cast<std::uint64_t>(trial));
}

}  // namespace

RobustBackend::CleanGraph RobustBackend::clean_graph(const Options& o, std::size_t g) {
  const RobustBackendGraph& f = o.graphs[g];
  const auto path = datasets::resolve_dataset_file(f.dataset, f.file);
  sim::WrongClosures subset;  // rate 0: the first poses and the edges among them, as read
  subset.first_poses = f.poses;
  CleanGraph out;
  if (f.dimension == 2)
    out.g2 = sim::add_wrong_loop_closures(graph::read_pose_graph_2d(path), subset, core::Streams(0), 0).graph;
  else
    out.g3 = sim::add_wrong_loop_closures(graph::read_pose_graph_3d(path), subset, core::Streams(0), 0).graph;
  return out;
}

RobustBackendReference RobustBackend::reference(const CleanGraph& clean, const Options& options,
                                                std::size_t g, int robots) {
  return options.graphs[g].dimension == 2 ? backend_reference(clean.g2, g, robots, options.robust.solve)
                                          : backend_reference(clean.g3, g, robots, options.robust.solve);
}

sim::CorruptedGraph2 RobustBackend::trial_graph(const graph::PoseGraph2D& clean, const Options& o,
                                                const RobustBackendCell& cell, int trial,
                                                const core::Streams& streams) {
  return backend_trial_graph(clean, o, cell, trial, streams);
}
sim::CorruptedGraph3 RobustBackend::trial_graph(const graph::PoseGraph3D& clean, const Options& o,
                                                const RobustBackendCell& cell, int trial,
                                                const core::Streams& streams) {
  return backend_trial_graph(clean, o, cell, trial, streams);
}

RobustBackend::Outcome RobustBackend::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  out.cells = make_cells(o);
  // Set-up (every shard): the subsets, and the reference of each graph and robot count.
  std::vector<CleanGraph> clean;
  for (std::size_t g = 0; g < o.graphs.size(); ++g) {
    clean.push_back(clean_graph(o, g));
    for (const int robots : o.robots) out.references.push_back(reference(clean[g], o, g, robots));
  }
  const auto reference = [&](const RobustBackendCell& c) -> const RobustBackendReference& {
    for (const auto& r : out.references)
      if (r.graph == c.graph && r.robots == c.robots) return r;
    throw std::logic_error("RobustBackend: no reference for a cell");
  };
  const std::size_t per_cell = static_cast<std::size_t>(o.trials);
  out.trials.resize(out.cells.size() * per_cell);
  core::Progress progress = context.progress(out.trials.size());
  const core::Streams& streams = context.streams();
  context.trials(
      out.trials.size(),
      [&](std::size_t i) {
        RobustBackendTrial& t = out.trials[i];
        t.cell = static_cast<int>(i / per_cell);
        t.trial = static_cast<int>(i % per_cell);
        const RobustBackendCell& cell = out.cells[static_cast<std::size_t>(t.cell)];
        const RobustBackendReference& ref = reference(cell);
        if (o.graphs[cell.graph].dimension == 2)
          backend_trial(clean[cell.graph].g2, cell, o, streams, ref.poses2, t);
        else
          backend_trial(clean[cell.graph].g3, cell, o, streams, ref.poses3, t);
      },
      &progress, out.trials);
  progress.finish();
  return out;
}

void RobustBackend::record(Results& r, const Outcome& out) {
  const Options& o = out.options;
  const std::size_t per_cell = static_cast<std::size_t>(o.trials);
  // The references.
  for (const RobustBackendReference& ref : out.references) {
    const auto m =
        r.at(repro::path(o.graphs[ref.graph].name).under(fmt::format("r{}", ref.robots)).under("reference"));
    m.metric("certified", ref.certified ? 1 : 0);
    m.metric("cost", ref.cost);
    m.metric("relative_gap", ref.relative_gap);
    m.timing("time_s", ref.time_s);
  }
  int sound_trials = 0, unsound = 0, wrong_kept_low = 0, low_trials = 0, clean_trials = 0,
      clean_certified = 0;
  std::string unsound_keys, wrong_kept_keys, clean_keys;
  struct Tally {
    int trials = 0, refused = 0, certified = 0, exact_selection = 0, kept_wrong = 0;
    std::vector<double> precision, recall, ate, rpe, gap, time, ratio;
  };
  Tally all;
  for (std::size_t c = 0; c < out.cells.size(); ++c) {
    const RobustBackendCell& cell = out.cells[c];
    const RobustBackendReference* ref = nullptr;
    for (const auto& x : out.references)
      if (x.graph == cell.graph && x.robots == cell.robots) ref = &x;
    Tally t;
    std::string refusals;
    for (std::size_t k = c * per_cell; k < (c + 1) * per_cell; ++k) {
      const RobustBackendTrial& x = out.trials[k];
      ++t.trials;
      if (x.refused) {
        ++t.refused;
        if (refusals.empty()) refusals = x.error;
        continue;
      }
      const int kept = x.kept_true + x.kept_wrong;
      t.precision.push_back(kept > 0 ? static_cast<double>(x.kept_true) / kept : 1.0);
      t.recall.push_back(x.true_closures > 0 ? static_cast<double>(x.kept_true) / x.true_closures : 1.0);
      t.ate.push_back(x.ate);
      t.rpe.push_back(x.rpe);
      t.gap.push_back(x.relative_gap);
      t.time.push_back(x.time_s);
      if (ref->time_s > 0) t.ratio.push_back(x.time_s / ref->time_s);
      t.certified += x.certified ? 1 : 0;
      t.kept_wrong += x.kept_wrong;
      const bool exact = x.kept_wrong == 0 && x.kept_true == x.true_closures;
      t.exact_selection += exact ? 1 : 0;
      // Soundness: where the kept set is exactly the true closures, the answer is the reference's problem;
      // two certified solves of it agree in F within the tolerance, and their trajectories nearly coincide.
      if (exact && x.certified && ref->certified) {
        ++sound_trials;
        const double tol = 2 * o.robust.solve.gap_tolerance * std::max(ref->cost, 1.0);
        if (std::abs(x.cost - ref->cost) > tol) {
          ++unsound;
          unsound_keys += " " + cell.key.name();
        }
      }
      if (cell.rate > 0 && cell.rate <= 0.4 && cell.kind == sim::WrongClosureKind::random) {
        ++low_trials;
        if (x.kept_wrong > 0) {
          ++wrong_kept_low;
          if (wrong_kept_keys.size() < 400)
            wrong_kept_keys += fmt::format(" {}#{}", cell.key.name(), x.trial);
        }
      }
      if (cell.rate == 0) {
        ++clean_trials;
        clean_certified += x.certified ? 1 : 0;
        if (!x.certified && clean_keys.size() < 400)
          clean_keys += fmt::format(" {}#{}", cell.key.name(), x.trial);
      }
    }
    const auto m = r.at(cell.key);
    m.metric("trials", t.trials);
    m.metric("refused", t.refused);
    m.metric("certified", t.certified);
    m.metric("exact_selection", t.exact_selection);
    m.metric("kept_wrong", t.kept_wrong);
    m.metric("rate", cell.rate);
    if (!t.precision.empty()) {
      m.metric("precision_mean", core::mean_std(t.precision).mean);
      m.metric("precision_min", *std::min_element(t.precision.begin(), t.precision.end()));
      m.metric("recall_mean", core::mean_std(t.recall).mean);
      m.metric("recall_min", *std::min_element(t.recall.begin(), t.recall.end()));
      m.metric("ate_median", core::median(t.ate));
      m.metric("ate_max", *std::max_element(t.ate.begin(), t.ate.end()));
      m.metric("rpe_median", core::median(t.rpe));
      m.metric("relative_gap_median", core::median(t.gap));
      m.timing("time_s.median", core::median(t.time));
      m.timing("time_s.max", *std::max_element(t.time.begin(), t.time.end()));
      if (!t.ratio.empty()) m.timing("time_ratio_to_clean.median", core::median(t.ratio));
    }
    if (!refusals.empty()) m.note("first_refusal", refusals);
    all.trials += t.trials;
    all.refused += t.refused;
    all.certified += t.certified;
    all.kept_wrong += t.kept_wrong;
    all.exact_selection += t.exact_selection;
  }
  r.metric("all.trials", all.trials);
  r.metric("all.refused", all.refused);
  r.metric("all.certified", all.certified);
  r.metric("all.exact_selection", all.exact_selection);
  r.metric("all.kept_wrong", all.kept_wrong);
  r.metric("all.sound_trials", sound_trials);
  r.metric("all.low_random_trials", low_trials);
  r.metric("all.low_random_wrong_kept", wrong_kept_low);
  r.metric("all.clean_trials", clean_trials);
  r.metric("all.clean_certified", clean_certified);
  r.check(
      "Soundness: where the kept closures are exactly the true ones and both solves are certified, the "
      "answer's F equals the outlier-free reference's within twice the gap tolerance",
      unsound == 0,
      unsound == 0 ? fmt::format("{} such trials, all agree", sound_trials)
                   : fmt::format("{} of {} disagree:{}", unsound, sound_trials, unsound_keys));
  r.check(
      "With random wrong closures at rates up to 40 %, no answer keeps a wrong closure (pairwise "
      "consistency, then the residual check)",
      wrong_kept_low == 0,
      wrong_kept_low == 0
          ? fmt::format("{} trials, none kept a wrong closure", low_trials)
          : fmt::format("{} of {} trials kept one or more:{}", wrong_kept_low, low_trials, wrong_kept_keys));
  r.check("Without wrong closures, every answer is certified", clean_certified == clean_trials,
          clean_certified == clean_trials
              ? fmt::format("{} trials, all certified", clean_trials)
              : fmt::format("{} of {} certified; not:{}", clean_certified, clean_trials, clean_keys));
}

std::vector<Figure> RobustBackend::figures(const Outcome& out) {
  const Options& o = out.options;
  const std::size_t per_cell = static_cast<std::size_t>(o.trials);
  const char* colors[] = {"C0", "C1", "C2", "C3", "C4", "C5", "C6", "C7", "C8", "C9"};
  // One panel per kind and measure; one line per graph (the mean over trials and robot counts).
  const auto panel = [&](sim::WrongClosureKind kind, int measure) {
    Panel p;
    p.xlabel = "wrong closures (% of loop closures)";
    p.ylabel = measure == 0 ? "precision (mean)" : measure == 1 ? "recall (mean)" : "certified (share)";
    p.title = fmt::format("{} wrong closures", sim::to_string(kind));
    for (std::size_t g = 0; g < o.graphs.size(); ++g) {
      std::vector<double> x, y;
      for (const double rate : o.rates) {
        double sum = 0;
        int count = 0;
        for (std::size_t c = 0; c < out.cells.size(); ++c) {
          const RobustBackendCell& cell = out.cells[c];
          if (cell.graph != g || cell.rate != rate || (rate > 0 && cell.kind != kind)) continue;
          for (std::size_t k = c * per_cell; k < (c + 1) * per_cell; ++k) {
            const RobustBackendTrial& t = out.trials[k];
            if (t.refused) continue;
            const int kept = t.kept_true + t.kept_wrong;
            sum += measure == 0 ? (kept > 0 ? static_cast<double>(t.kept_true) / kept : 1.0)
                   : measure == 1
                       ? (t.true_closures > 0 ? static_cast<double>(t.kept_true) / t.true_closures : 1.0)
                       : (t.certified ? 1.0 : 0.0);
            ++count;
          }
        }
        if (count == 0) continue;
        x.push_back(100 * rate);
        y.push_back(sum / count);
      }
      p.layers.push_back(repro::line_layer(x, y, o.graphs[g].name, colors[g % 10]));
    }
    p.legend = "best";
    return p;
  };
  Figure f;
  f.file = ".png";
  f.title = "Robust back end: kept closures and certificates against the share of wrong closures";
  f.rows = 3, f.cols = static_cast<int>(o.kinds.size());
  for (int measure = 0; measure < 3; ++measure)
    for (const auto kind : o.kinds) f.panels.push_back(panel(kind, measure));
  f.width = 5.5 * static_cast<double>(o.kinds.size());
  f.height = 11.0;
  return {f};
}

}  // namespace keel::study::ch4
