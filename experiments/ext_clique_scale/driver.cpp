// Beyond the thesis: PCM's exact maximum clique, its heuristic and the densest-subgraph relaxation (CLIPPER)
// on planted-clique graphs, 1D worlds (§2.7.1) and the Table 2.1 candidate sets (§2.7.2) — thin driver over
// keel::eval's clique-scale studies (eval/clique_scale.hpp). Sizes, precision/recall, violations and the
// exact search's status and bound are metrics; wall times are timings (never diffed).
import keel.core;
import keel.repro;
import keel.pcm;
import keel.sim;
import keel.eval;

#include <fmt/format.h>

#include <cstdint>
#include <stdexcept>

namespace core = keel::core;
namespace repro = keel::repro;
namespace pcm = keel::pcm;
namespace sim = keel::sim;
namespace eval = keel::eval;

namespace {

eval::CliqueScaleOptions read_methods(const core::ConfigTable& p) {
  eval::CliqueScaleOptions o;
  o.exact_node_limit = static_cast<long long>(p.count("exact_node_limit"));
  o.reference_max_vertices = static_cast<int>(p.integer("reference_max_vertices"));
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
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
    eval::CliqueScaleTally tally;

    // Planted cliques.
    core::Progress progress(ex.id(), po.cells().size() * po.seeds + wo.worlds + city_datasets);
    auto t0 = core::Clock::now();
    const auto planted = eval::run_planted_clique_study(po, &progress);
    r.timing("planted", core::seconds_since(t0));
    eval::record_planted_clique_study(r, planted, tally);

    // 1D worlds.
    t0 = core::Clock::now();
    const auto worlds = eval::run_world1d_clique_study(wo, &progress);
    r.timing("world1d", core::seconds_since(t0));
    r.metric("world1d.worlds", static_cast<double>(wo.worlds));
    r.metric("world1d.gamma", wo.gamma);
    double edges = 0;
    for (const auto& w : worlds) edges += static_cast<double>(w.edges);
    r.metric("world1d.density", edges / static_cast<double>(worlds.size()) / (0.5 * m * (m - 1.0)));
    eval::record_clique_group(r, "world1d", worlds, 0, worlds.size(), 0, tally);

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
    eval::record_clique_group(r, "city", sets, 0, sets.size(), 0, tally);

    // Over every graph of the three families, and the figure.
    tally.record(r, po.methods.reference_max_vertices);
    r.figure(eval::planted_clique_figure(planted, po, f_fig, ex.id() + ".png"));
  });
}
