#include "study/ch4/certified_noise.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/bound.hpp"
#include "core/statistics.hpp"
#include "datasets/manifest.hpp"
#include "graph/io.hpp"
#include "sim/loop_closures.hpp"
#include "study/ch4/certified_pgo.hpp"

namespace keel::study::ch4 {

using repro::Figure;
using repro::Layer;
using repro::Panel;
using repro::Results;
using repro::RunContext;

namespace {

// "0.3" -> "0p3": a level's value inside a results key (dots separate a key's parts).
std::string key_number(double v) {
  std::string s = fmt::format("{:g}", v);
  std::replace(s.begin(), s.end(), '.', 'p');
  return s;
}

}  // namespace

CertifiedNoiseSweep::Options CertifiedNoiseSweep::Options::read(const core::ConfigTable& p) {
  Options o;
  o.solve = read_certified_solve(p);
  o.solve.time_limit_s = p.number("time_limit_s");
  o.solve.chordal_initialization = true;
  p.validate(o.solve);
  o.alternative_time_limit_s = p.number("alternative_time_limit_s");
  if (!(o.alternative_time_limit_s > 0))
    throw core::ConfigError(fmt::format("{}: must be > 0 (seconds), not {}",
                                        p.where("alternative_time_limit_s"), o.alternative_time_limit_s));
  o.draws = static_cast<int>(p.integer("draws"));
  if (o.draws < 1)
    throw core::ConfigError(fmt::format("{}: must be >= 1, not {}", p.where("draws"), o.draws));
  for (const double s : p.numbers("rotation_noise")) {
    sim::LoopClosureCorruption c;
    c.rotation_noise = s;
    p.validate(c);
    o.levels.push_back({"rot" + key_number(s), s, 0.0});
  }
  for (const double f : p.numbers("outlier_fraction")) {
    sim::LoopClosureCorruption c;
    c.outlier_fraction = f;
    p.validate(c);
    o.levels.push_back({"out" + key_number(100 * f), 0.0, f});
  }
  if (o.levels.empty())
    throw core::ConfigError(fmt::format("{}: no level (rotation_noise and outlier_fraction are both empty)",
                                        p.where("rotation_noise")));
  for (const GraphPrefix& g : read_graph_prefixes(p))
    o.subsets.push_back({g.file.name, g.file.dataset, g.file.file, g.file.dimension, g.poses});
  return o;
}

std::vector<NoiseSweepGraph> CertifiedNoiseSweep::make_graphs(const Options& o,
                                                              const core::Streams& streams) {
  constexpr auto check = graph::InformationCheck::diagonal_blocks;  // the isotropic model needs κ and τ only
  const core::Streams graph_streams = streams.child("graphs");
  std::vector<NoiseSweepGraph> out;
  for (std::size_t k = 0; k < o.subsets.size(); ++k) {
    const NoiseSweepSubset& s = o.subsets[k];
    const auto path = datasets::resolve_dataset_file(s.dataset, s.file);
    graph::PoseGraph2D g2;
    graph::PoseGraph3D g3;
    if (s.dimension == 2)
      g2 = graph::read_pose_graph_2d(path, check);
    else
      g3 = graph::read_pose_graph_3d(path, check);
    for (std::size_t l = 0; l < o.levels.size(); ++l)
      for (int m = 0; m < o.draws; ++m) {
        sim::LoopClosureCorruption c;
        c.first_poses = s.poses;
        c.rotation_noise = o.levels[l].rotation_noise;
        c.outlier_fraction = o.levels[l].outlier_fraction;
        const std::uint64_t index = k * static_cast<std::uint64_t>(o.draws) + static_cast<std::uint64_t>(m);
        NoiseSweepGraph g;
        g.subset = k, g.level = l, g.draw = m;
        g.key = repro::path(s.name).under(o.levels[l].name).under(fmt::format("d{}", m));
        const auto fill = [&](auto corrupted) {
          g.loop_closures = static_cast<int>(corrupted.loop_closures.size());
          g.outliers = static_cast<int>(corrupted.outliers.size());
          corrupted.graph.source = fmt::format("{} ({})", g.key.name(), s.file);
          return std::move(corrupted.graph);
        };
        if (s.dimension == 2)
          g.g2 = fill(sim::corrupt_loop_closures(g2, c, graph_streams, index));
        else
          g.g3 = fill(sim::corrupt_loop_closures(g3, c, graph_streams, index));
        out.push_back(std::move(g));
      }
  }
  return out;
}

CertifiedNoiseSweep::Outcome CertifiedNoiseSweep::run(const Options& o, const RunContext& context) {
  // Every graph is made first (a missing data set fails before any solve).
  std::vector<NoiseSweepGraph> graphs = make_graphs(o, context.streams());
  core::Progress progress = context.progress(graphs.size());
  pgo::CertifiedOptions alt = o.solve;
  alt.chordal_initialization = false;
  alt.time_limit_s = o.alternative_time_limit_s;
  Outcome out;
  out.options = o;
  // One graph after another on one thread: the recorded times are those of a single-threaded run, comparable
  // with SE-Sync's (bench/side_by_side/certified.sh).
  for (NoiseSweepGraph& g : graphs) {
    NoiseSweepOutcome r;
    r.key = g.key, r.subset = g.subset, r.level = g.level, r.draw = g.draw;
    r.loop_closures = g.loop_closures, r.outliers = g.outliers;
    const int d = o.subsets[g.subset].dimension;
    alt.max_rank = d;
    if (d == 2) {
      r.summary = pgo::solve_certified(g.g2, o.solve).summary;
      r.alternative = pgo::solve_certified(g.g2, alt).summary;
    } else {
      r.summary = pgo::solve_certified(g.g3, o.solve).summary;
      r.alternative = pgo::solve_certified(g.g3, alt).summary;
    }
    out.graphs.push_back(std::move(r));
    progress.advance(1);
  }
  progress.finish();
  return out;
}

namespace {

// The lowest cost found on a graph: the certified solve's answer or the second solve's.
double lowest_cost(const NoiseSweepOutcome& g) {
  return std::min(g.summary.final_cost, g.alternative.final_cost);
}

// A certificate is contradicted when a feasible point costs less than its certified F by more than the gap
// tolerance allows: F − F* ≤ gap · max(F, 1) and F* ≤ F_alt.
bool certificate_contradicted(const NoiseSweepOutcome& g, double tol) {
  return g.summary.certificate.certified &&
         g.alternative.final_cost < g.summary.final_cost - tol * std::max(g.summary.final_cost, 1.0);
}

}  // namespace

void CertifiedNoiseSweep::record(Results& r, const Outcome& out) {
  const Options& o = out.options;
  const double tol = o.solve.gap_tolerance;
  struct Tally {
    int graphs = 0, certified = 0, proven = 0, time_limit = 0, alt_time_limit = 0, rank_limit = 0;
    std::vector<double> gap, rank, iterations, tcg, outliers, loop_closures;
  };
  std::vector<Tally> level(o.levels.size());
  Tally all;
  int contradicted = 0, bound_above = 0;
  std::string contradicted_keys, bound_keys, stalled_keys;
  for (const NoiseSweepOutcome& g : out.graphs) {
    const pgo::CertifiedSummary& s = g.summary;
    const pgo::Certificate& c = s.certificate;
    const std::string n = g.key.name();
    const auto m = r.at(g.key);
    m.metric("poses", s.poses);
    m.metric("edges", s.edges);
    m.metric("loop_closures", g.loop_closures);
    m.metric("outliers", g.outliers);
    m.metric("initial_cost", s.initial_cost);
    m.metric("cost", s.final_cost);
    m.metric("certified", c.certified ? 1 : 0);
    m.metric("proven", c.proven ? 1 : 0);
    if (c.proven) {  // only from the proof behind the bound
      m.metric("lower_bound", c.bound.lower);
      m.metric("relative_gap", c.bound.relative_gap_up());
    }
    m.metric("final_rank", s.final_rank);
    m.metric("iterations", s.iterations);
    m.metric("tcg_iterations", s.tcg_iterations);
    m.metric("alternative_cost", g.alternative.final_cost);
    m.note("termination", std::string(pgo::to_string(s.termination)));
    m.note("alternative_termination", std::string(pgo::to_string(g.alternative.termination)));
    m.timing("time_s", s.total_time_s);
    m.timing("alternative_time_s", g.alternative.total_time_s);
    for (Tally* t : {&level[g.level], &all}) {
      ++t->graphs;
      t->certified += c.certified ? 1 : 0;
      t->proven += c.proven ? 1 : 0;
      t->time_limit += s.termination == pgo::CertifiedTermination::time_limit ? 1 : 0;
      t->alt_time_limit += g.alternative.termination == pgo::CertifiedTermination::time_limit ? 1 : 0;
      t->rank_limit += s.termination == pgo::CertifiedTermination::rank_limit ? 1 : 0;
      t->gap.push_back(c.proven ? c.bound.relative_gap_up() : 1.0);  // nothing proven: a gap of 100 %
      t->rank.push_back(s.final_rank);
      t->iterations.push_back(s.iterations);
      t->tcg.push_back(s.tcg_iterations);
      t->outliers.push_back(g.outliers);
      t->loop_closures.push_back(g.loop_closures);
    }
    if (certificate_contradicted(g, tol)) ++contradicted, contradicted_keys += " " + n;
    // The proven bound holds for every feasible point: below both costs found (both rounded to nearest, the
    // bound rounded down; a relative 1e-12 covers the costs' own rounding).
    if (c.proven && c.bound.lower > lowest_cost(g) + 1e-12 * std::max(lowest_cost(g), 1.0))
      ++bound_above, bound_keys += " " + n;
    if (s.termination == pgo::CertifiedTermination::time_limit) stalled_keys += " " + n;
  }
  const auto put = [&](const std::string& p, const Tally& t) {
    r.under(p).metric("graphs", t.graphs);
    r.under(p).metric("certified", t.certified);
    r.under(p).metric("certified_rate", t.graphs > 0 ? 100.0 * t.certified / t.graphs : 0.0);
    r.under(p).metric("proven", t.proven);
    r.under(p).metric("time_limit", t.time_limit);
    r.under(p).metric("alternative_time_limit", t.alt_time_limit);
    r.under(p).metric("rank_limit", t.rank_limit);
    if (!t.gap.empty()) {  // over every graph, nothing proven counted as 1
      r.under(p).metric("relative_gap_median", core::median(t.gap));
      r.under(p).metric("relative_gap_max", *std::max_element(t.gap.begin(), t.gap.end()));
    }
    r.under(p).metric("final_rank_median", core::median(t.rank));
    r.under(p).metric("iterations_median", core::median(t.iterations));
    r.under(p).metric("tcg_iterations_median", core::median(t.tcg));
    r.under(p).metric("outliers_median", core::median(t.outliers));
    r.under(p).metric("loop_closures_median", core::median(t.loop_closures));
  };
  for (std::size_t l = 0; l < o.levels.size(); ++l) {
    put(o.levels[l].name, level[l]);
    r.under(o.levels[l].name).metric("rotation_noise", o.levels[l].rotation_noise);
    r.under(o.levels[l].name).metric("outlier_fraction", o.levels[l].outlier_fraction);
    std::vector<double> times;
    for (const NoiseSweepOutcome& g : out.graphs)
      if (g.level == l) times.push_back(g.summary.total_time_s);
    if (!times.empty()) {
      r.under(o.levels[l].name).timing("time_s.median", core::median(times));
      r.under(o.levels[l].name).timing("time_s.max", *std::max_element(times.begin(), times.end()));
    }
  }
  put("all", all);
  r.metric("all.contradicted", contradicted);
  r.metric("all.bound_above_cost", bound_above);
  r.check(
      "No certificate is contradicted: no local solve from the file's own estimates finds a cost more than "
      "the "
      "gap tolerance below a certified F",
      contradicted == 0,
      contradicted == 0
          ? fmt::format("{} certified of {} graphs, none contradicted", all.certified, all.graphs)
          : fmt::format("contradicted:{}", contradicted_keys));
  r.check(
      "Every proven lower bound lies below every cost found on its graph (the certified solve's and the "
      "second solve's)",
      bound_above == 0,
      bound_above == 0
          ? fmt::format("{} proven bounds of {} graphs, all below both costs", all.proven, all.graphs)
          : fmt::format("bound above a cost:{}", bound_keys));
  r.check(fmt::format(
              "The certified solve finishes within its time limit ({:g} s) on every graph: no local solve "
              "stalls",
              o.solve.time_limit_s),
          all.time_limit == 0,
          all.time_limit == 0
              ? fmt::format("{} graphs, none stopped at the limit", all.graphs)
              : fmt::format("{} of {} stopped at the limit:{}", all.time_limit, all.graphs, stalled_keys));
}

std::vector<Figure> CertifiedNoiseSweep::figures(const Outcome& out) {
  const Options& o = out.options;
  const char* colors[] = {"C0", "C1", "C2", "C3", "C4", "C5", "C6", "C7", "C8", "C9"};
  // Two x axes: the rotation noise (rad) of the noise levels, the outlier fraction (%) of the outlier levels.
  const auto panel = [&](bool noise, bool time) {
    Panel p;
    p.xlabel = noise ? "rotation noise on loop closures (rad)" : "outlier closures (% of loop closures)";
    p.ylabel = time ? "seconds (one thread)" : "relative gap of the proven bound (1 = nothing proven)";
    p.title = time ? "certified solve, time per graph"
                   : "proven gap (certified: ≈ tolerance/33, set by the shift rule)";
    p.yscale = "log";
    for (std::size_t k = 0; k < o.subsets.size(); ++k) {
      std::vector<double> x, y;
      std::vector<std::string> names;
      for (const NoiseSweepOutcome& g : out.graphs) {
        const NoiseSweepLevel& l = o.levels[g.level];
        if (g.subset != k || (l.rotation_noise > 0) != noise) continue;
        x.push_back(noise ? l.rotation_noise : 100 * l.outlier_fraction);
        const auto& c = g.summary.certificate;
        y.push_back(c.proven ? std::max(c.bound.relative_gap_up(), 1e-16) : 1.0);
        names.push_back(g.key.key("time_s"));
      }
      if (x.empty()) continue;
      Layer layer = repro::scatter_layer(x, time ? std::vector<double>{} : y,
                                         fmt::format("{} ({} poses)", o.subsets[k].name, o.subsets[k].poses),
                                         colors[k % 10], 30.0, 0.8, "o");
      if (time) layer.y_timings = names;
      p.layers.push_back(std::move(layer));
    }
    if (!time) p.layers.push_back(repro::hline_layer(o.solve.gap_tolerance, "gap tolerance", "k"));
    p.legend = "best";
    return p;
  };
  Figure f;
  f.file = ".png";
  f.title = "Certified solve on corrupted subsets of SE-Sync's benchmark graphs";
  f.rows = 2, f.cols = 2;
  f.panels = {panel(true, true), panel(false, true), panel(true, false), panel(false, false)};
  f.width = 11.0;
  f.height = 9.0;
  return {f};
}

}  // namespace keel::study::ch4
