// Beyond the thesis: PCM's exact maximum clique, its heuristic and the densest-subgraph relaxation (CLIPPER)
// on planted-clique graphs, 1D worlds (§2.7.1) and the Table 2.1 candidate sets (§2.7.2) — thin driver over
// keel::eval's clique-scale studies (eval/clique_scale.hpp). Sizes, precision/recall, violations and the
// exact search's status and bound are metrics; wall times are timings (never diffed).
import keel.core;
import keel.pcm;
import keel.sim;
import keel.eval;

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace core = keel::core;
namespace pcm = keel::pcm;
namespace sim = keel::sim;
namespace eval = keel::eval;

namespace {

// Aggregates over every graph of every family, for the checks.
struct Tally {
  std::size_t graphs = 0, exact_below_heuristic = 0, not_cliques = 0, above_bound = 0, optimal = 0,
              optimal_inconsistent = 0, below_planted = 0, densest_raw_violating = 0, reference_checked = 0,
              reference_mismatch = 0;
};

// Records one group of graphs (a planted cell, the 1D worlds, the City data sets) under `prefix` and adds its
// graphs to the tally of the checks; `planted_k` > 0 is the planted clique's size.
void record_group(core::Results& r, const std::string& prefix,
                  const std::vector<eval::CliqueGraphOutcome>& all, std::size_t first, std::size_t last,
                  int planted_k, Tally& tally) {
  for (auto m : eval::kAllCliqueScaleMethods) {
    const auto s = eval::summarize_clique_method(all, first, last, m);
    const std::string n = fmt::format("{}.{}", prefix, eval::to_string(m));
    r.metric(n + ".size", s.size_mean);
    r.metric(n + ".size_min", s.size_min);
    r.metric(n + ".precision", s.precision);
    r.metric(n + ".recall", s.recall);
    r.metric(n + ".violations", static_cast<double>(s.violations_total));  // in the outputs (0: cliques)
    if (m == eval::CliqueScaleMethod::densest) {
      r.metric(n + ".raw_size", s.raw_size_mean);
      r.metric(n + ".raw_violations", s.raw_violations_mean);
      r.metric(n + ".raw_violating_graphs", static_cast<double>(s.raw_violating_graphs));
    }
    if (m == eval::CliqueScaleMethod::exact) {
      r.metric(n + ".optimal", static_cast<double>(s.optimal_graphs) / static_cast<double>(s.graphs));
      r.metric(n + ".upper_bound", s.upper_bound_mean);
      r.metric(n + ".gap", s.gap_mean);
      r.metric(n + ".gap_max", s.gap_max);
      r.metric(n + ".nodes", s.nodes_mean);
    }
    r.timing(n + ".time_s", s.time_mean_s);
    r.timing(n + ".time_s.max", s.time_max_s);
  }
  for (std::size_t i = first; i < last; ++i) {
    const auto& g = all[i];
    const auto& ex = g.of(eval::CliqueScaleMethod::exact);
    ++tally.graphs;
    tally.exact_below_heuristic += ex.size < g.of(eval::CliqueScaleMethod::heuristic).size;
    if (g.reference_size >= 0) {
      ++tally.reference_checked;
      tally.reference_mismatch += ex.status != pcm::SearchStatus::optimal || ex.size != g.reference_size;
    }
    tally.densest_raw_violating += g.of(eval::CliqueScaleMethod::densest).raw_violations > 0;
    for (const auto& o : g.methods) {
      tally.not_cliques += o.violations > 0;
      tally.above_bound += o.size > ex.upper_bound;
    }
    if (ex.status == pcm::SearchStatus::optimal) {
      ++tally.optimal;
      tally.optimal_inconsistent += ex.size != ex.upper_bound;
      tally.below_planted += planted_k > 0 && ex.size < planted_k;
    }
  }
}

eval::CliqueScaleOptions read_methods(const core::ConfigTable& p) {
  eval::CliqueScaleOptions o;
  o.exact_node_limit = static_cast<long long>(p.count("exact_node_limit"));
  o.reference_max_vertices = static_cast<int>(p.integer("reference_max_vertices"));
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  return core::experiment_main(argc, argv, [](core::Experiment& ex) {
    const auto& p = ex.params();
    eval::PlantedCliqueStudyOptions po;
    po.methods = read_methods(p);
    for (double n : p.numbers("sizes")) po.sizes.push_back(static_cast<int>(n));
    po.clique_fractions = p.numbers("clique_fractions");
    po.clique_min = static_cast<int>(p.integer("clique_min"));
    po.densities = p.numbers("densities");
    po.seeds = p.count("seeds");
    // 1D worlds of §2.7.1 with exactly `world1d_measurements` measurements (the fractions of Fig. 2.3).
    eval::World1DCliqueOptions wo;
    wo.methods = po.methods;
    const auto w1 = p.table("world1d");
    const auto world_base = eval::read_world1d_options(w1, false);
    const int m = static_cast<int>(w1.count("measurements"));
    const double inlier_fraction = w1.number("inlier_fraction"),
                 aliased_fraction = w1.number("aliased_fraction");
    const double w1_p = w1.number("pcm_p");
    wo.worlds = p.count("world1d_worlds");
    // The Table 2.1 data sets (ch2_table2_1_city's scenario and candidate seed).
    const auto city = p.table("city");
    const std::size_t city_datasets = p.count("city_datasets");
    const double city_p = city.number("pcm_p");
    const auto city_seed = static_cast<std::uint64_t>(city.integer("seed"));
    const auto copt = eval::read_candidate_options(city);
    const auto scenario = eval::load_scenario_2d(city);
    const double f_fig = p.number("figure_clique_fraction");
    ex.params_done();
    try {
      wo.world = sim::world1d_options_with_total(world_base, m, inlier_fraction, aliased_fraction);
      wo.gamma = pcm::consistency_threshold(w1_p, 1);
      po.validate();
      wo.validate();
    } catch (const std::invalid_argument& e) {
      throw core::ConfigError(fmt::format("{}: {}", p.file(), e.what()));
    }
    po.seed = ex.seed();
    po.threads = ex.threads();
    wo.seed = ex.seed();
    wo.stream_base = std::uint64_t{1} << 48;  // apart from the planted graphs' streams
    wo.threads = ex.threads();
    auto& r = ex.results();
    Tally tally;

    // Planted cliques.
    const auto cells = po.cells();
    core::Progress progress(ex.id(), cells.size() * po.seeds + wo.worlds + city_datasets);
    auto t0 = core::Clock::now();
    const auto planted = eval::run_planted_clique_study(po, &progress);
    r.timing("planted", core::seconds_since(t0));
    std::vector<std::string> cell_names;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const auto& cell = cells[c];
      const std::string name = fmt::format("planted.n{:04d}.k{:04d}.p{:02d}", cell.n, cell.k,
                                           static_cast<int>(std::lround(100 * cell.p)));
      cell_names.push_back(name);
      r.metric(name + ".k", cell.k);
      r.metric(name + ".omega0", cell.omega0);
      r.metric(name + ".planted_is_maximum", cell.planted_is_maximum() ? 1.0 : 0.0);
      record_group(r, name, planted.outcomes, c * po.seeds, (c + 1) * po.seeds, cell.k, tally);
    }
    r.metric("planted.cells", static_cast<double>(cells.size()));
    r.metric("planted.seeds", static_cast<double>(po.seeds));

    // 1D worlds.
    t0 = core::Clock::now();
    const auto worlds = eval::run_world1d_clique_study(wo, &progress);
    r.timing("world1d", core::seconds_since(t0));
    r.metric("world1d.worlds", static_cast<double>(wo.worlds));
    r.metric("world1d.gamma", wo.gamma);
    double edges = 0;
    for (const auto& w : worlds) edges += static_cast<double>(w.edges);
    r.metric("world1d.density", edges / static_cast<double>(worlds.size()) / (0.5 * m * (m - 1.0)));
    record_group(r, "world1d", worlds, 0, worlds.size(), 0, tally);

    // The Table 2.1 candidate sets.
    t0 = core::Clock::now();
    const auto local = eval::solve_local_pair(scenario);
    const auto sets =
        eval::run_two_robot_clique_study(scenario, local, copt, city_p, pcm::Composition::joint, po.methods,
                                         city_seed, city_datasets, ex.threads(), &progress);
    r.timing("city", core::seconds_since(t0));
    progress.finish();
    r.metric("city.datasets", static_cast<double>(city_datasets));
    r.metric("city.candidates", static_cast<double>(sets.front().vertices));
    edges = 0;
    for (const auto& s : sets)
      edges += static_cast<double>(s.edges) / (0.5 * s.vertices * (s.vertices - 1.0));
    r.metric("city.density", edges / static_cast<double>(sets.size()));
    record_group(r, "city", sets, 0, sets.size(), 0, tally);

    // Over every graph of the three families.
    r.metric("all.graphs", static_cast<double>(tally.graphs));
    r.metric("all.exact.optimal_graphs", static_cast<double>(tally.optimal));
    r.metric("all.densest.raw_violating_graphs", static_cast<double>(tally.densest_raw_violating));
    r.metric("all.reference_graphs", static_cast<double>(tally.reference_checked));
    r.check("the exact search never returns a smaller clique than the heuristic",
            tally.exact_below_heuristic == 0,
            fmt::format("{} of {} graphs", tally.exact_below_heuristic, tally.graphs));
    r.check("every method's output is a clique (the densest subgraph after its repair)",
            tally.not_cliques == 0,
            fmt::format("{} outputs with a non-adjacent pair, of {}", tally.not_cliques,
                        eval::kCliqueScaleMethods * tally.graphs));
    r.check(fmt::format("on graphs of at most {} vertices the exact search proves optimal the size that the "
                        "colouring-only exact search finds",
                        po.methods.reference_max_vertices),
            tally.reference_checked > 0 && tally.reference_mismatch == 0,
            fmt::format("{} graphs compared, {} differ or are not proven", tally.reference_checked,
                        tally.reference_mismatch));
    r.check("no method returns a clique larger than the exact search's proven upper bound",
            tally.above_bound == 0, fmt::format("{} outputs above the bound", tally.above_bound));
    r.check(
        "where the exact search proves optimality, its clique has the bound's size and at least the planted "
        "k",
        tally.optimal_inconsistent == 0 && tally.below_planted == 0,
        fmt::format("{} proven optimal of {} graphs; {} with size != bound, {} below the planted k",
                    tally.optimal, tally.graphs, tally.optimal_inconsistent, tally.below_planted));

    // Figure: per density, mean wall time and recall of each method against n at one clique fraction.
    core::Figure fig;
    fig.file = ex.id() + ".png";
    fig.title = fmt::format(
        "Planted clique of {:g} % of n: mean wall time per graph (machine-dependent) and recall of the "
        "planted set",
        100 * f_fig);
    fig.cols = static_cast<int>(po.densities.size());
    fig.rows = 2;
    fig.width = 5.0 * fig.cols;
    fig.height = 9.0;
    const char* colors[] = {"tab:blue", "tab:green", "tab:orange"};
    const char* markers[] = {"o", "s", "^"};
    std::vector<core::Panel> time_panels, recall_panels;
    for (double dens : po.densities) {
      core::Panel tp, rp;
      tp.title = rp.title = fmt::format("p = {:g}", dens);
      tp.xlabel = rp.xlabel = "candidates n";
      tp.ylabel = "mean wall time (s)";
      rp.ylabel = "recall of the planted clique";
      tp.xscale = tp.yscale = rp.xscale = "log";
      rp.ylim = std::pair{0.0, 1.05};
      tp.legend = "upper left";
      rp.legend = "none";
      for (std::size_t k = 0; k < eval::kCliqueScaleMethods; ++k) {
        const auto meth = eval::kAllCliqueScaleMethods[k];
        std::vector<double> xs, rec;
        std::vector<std::string> tn;
        for (std::size_t c = 0; c < cells.size(); ++c) {
          const auto& cell = cells[c];
          const int kk = std::max(po.clique_min, static_cast<int>(std::lround(f_fig * cell.n)));
          if (cell.p != dens || cell.k != std::min(cell.n, kk)) continue;
          xs.push_back(cell.n);
          tn.push_back(fmt::format("{}.{}.time_s", cell_names[c], eval::to_string(meth)));
          rec.push_back(
              eval::summarize_clique_method(planted.outcomes, c * po.seeds, (c + 1) * po.seeds, meth).recall);
        }
        auto l = core::line_layer(xs, {}, std::string(eval::to_string(meth)), colors[k], markers[k]);
        l.y_timings = tn;
        tp.layers.push_back(l);
        rp.layers.push_back(
            core::line_layer(xs, rec, std::string(eval::to_string(meth)), colors[k], markers[k]));
      }
      time_panels.push_back(tp);
      recall_panels.push_back(rp);
    }
    for (auto& pnl : time_panels) fig.panels.push_back(pnl);
    for (auto& pnl : recall_panels) fig.panels.push_back(pnl);
    r.figure(fig);
  });
}
