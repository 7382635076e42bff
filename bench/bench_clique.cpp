// Google Benchmark for keel.pcm (thesis §2.5, §2.7): exact and heuristic maximum clique on random graphs G(n,
// p) and on consistency graphs of the 1D world of §2.7.1, plus the other selection methods on the same 1D
// matrices Q, a planted-clique family for exact, heuristic and densest-subgraph selection, and the clique
// family (below) that covers PCM's own graphs.
// Run: build/release/bench/bench_clique [--benchmark_filter=1D|Planted|Family]
//      build/release/bench/bench_clique --write-family=DIR   (the family as DIMACS files, for other solvers)
import keel.pcm;
import keel.sim;
import keel.core;
import keel.repro;
import keel.study;

#include <benchmark/benchmark.h>

#include "csv_union.hpp"
#include "study_graphs.hpp"
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pcm = keel::pcm;
namespace sim = keel::sim;

namespace {

// --- random graphs G(n, p): args = vertices, density in percent
// ------------------------------------------------

void BM_Exact(benchmark::State& state) {
  const auto g = sim::random_graph(static_cast<int>(state.range(0)), 0.01 * state.range(1), 2015);
  long long size = 0, nodes = 0;
  for (auto _ : state) {
    const auto r = pcm::maximum_clique(g, pcm::CliqueAlgorithm::exact);
    size = static_cast<long long>(r.clique.size());
    nodes = r.nodes_explored;
    benchmark::DoNotOptimize(size);
  }
  state.counters["clique"] = static_cast<double>(size);
  state.counters["nodes"] = static_cast<double>(nodes);
}

void BM_Heuristic(benchmark::State& state) {
  const auto g = sim::random_graph(static_cast<int>(state.range(0)), 0.01 * state.range(1), 2015);
  long long size = 0;
  for (auto _ : state) {
    const auto r = pcm::maximum_clique(g, pcm::CliqueAlgorithm::heuristic);
    size = static_cast<long long>(r.clique.size());
    benchmark::DoNotOptimize(size);
  }
  state.counters["clique"] = static_cast<double>(size);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int p : {5, 20})
    for (int n : {50, 200, 500, 1000, 2000}) b->Args({n, p});
  for (int n : {50, 100, 200}) b->Args({n, 50});  // dense graphs: the exact search grows fast with density
  b->Unit(benchmark::kMillisecond);
}

// --- 1D worlds (§2.7.1): args = measurements m (half inliers, a quarter aliased, a quarter random)
// ----------------

// Q of world 0 of a fixed seed with m measurements; γ at p = 0.11 (dof 1), as in
// ch2_fig2_2_1d_vs_combinatorial.
pcm::ConsistencyMatrix world_q(int m) {
  const auto o = sim::world1d_options_with_total(sim::World1DOptions{}, m, 0.5, 0.25);
  return sim::world1d_consistency_matrix(sim::generate_world1d(o, 2018, 0));
}
const double kGamma = pcm::consistency_threshold(0.11, 1);

void BM_Exact1D(benchmark::State& state) {
  const auto Q = world_q(static_cast<int>(state.range(0)));
  const auto g = pcm::ConsistencyGraph::from_threshold(Q.n, Q.q, kGamma);
  long long size = 0, nodes = 0;
  for (auto _ : state) {
    const auto r = pcm::maximum_clique(g, pcm::CliqueAlgorithm::exact);
    size = static_cast<long long>(r.clique.size());
    nodes = r.nodes_explored;
    benchmark::DoNotOptimize(size);
  }
  state.counters["clique"] = static_cast<double>(size);
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["density"] =
      2.0 * static_cast<double>(g.num_edges()) / (static_cast<double>(Q.n) * (Q.n - 1));
}

void BM_Heuristic1D(benchmark::State& state) {
  const auto Q = world_q(static_cast<int>(state.range(0)));
  const auto g = pcm::ConsistencyGraph::from_threshold(Q.n, Q.q, kGamma);
  long long size = 0;
  for (auto _ : state) {
    const auto r = pcm::maximum_clique(g, pcm::CliqueAlgorithm::heuristic);
    size = static_cast<long long>(r.clique.size());
    benchmark::DoNotOptimize(size);
  }
  state.counters["clique"] = static_cast<double>(size);
}

// Whole selections from Q (thresholding included for PCM), as timed in Fig. 2.3.
void BM_SelectPcmExact1D(benchmark::State& state) {
  const auto Q = world_q(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(pcm::select_pcm(Q, kGamma, pcm::CliqueAlgorithm::exact));
}

void BM_Scgp1D(benchmark::State& state) {
  const auto Q = world_q(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(pcm::select_scgp(Q));
}

void BM_Ransac1D(benchmark::State& state) {
  const auto Q = world_q(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(pcm::select_ransac(Q, kGamma));
}

void BM_CombinatorialPruned1D(benchmark::State& state) {
  const auto Q = world_q(static_cast<int>(state.range(0)));
  for (auto _ : state)
    benchmark::DoNotOptimize(
        pcm::max_consistent_set_combinatorial(Q, kGamma, pcm::CombinatorialMethod::pruned));
}

void BM_CombinatorialExhaustive1D(benchmark::State& state) {
  const auto Q = world_q(static_cast<int>(state.range(0)));
  for (auto _ : state)
    benchmark::DoNotOptimize(
        pcm::max_consistent_set_combinatorial(Q, kGamma, pcm::CombinatorialMethod::exhaustive));
}

void world_sizes(benchmark::internal::Benchmark* b) {
  for (int m : {50, 100, 200, 500, 1000, 2000}) b->Arg(m);
  b->Unit(benchmark::kMicrosecond);
}

// --- planted cliques: args = vertices n, planted size k in percent of n, density p in percent
// ------------------------
// k mutually consistent inliers among n candidates whose other pairs are consistent with probability p
// (sim::planted_clique_graph). Counters: the size found, precision and recall against the planted set, and
// for the exact search its proven bound and whether it proved optimality within its 10 s limit; for the
// densest subgraph the inconsistent pairs of its raw rounding. Run:
//   build/release/bench/bench_clique --benchmark_filter=Planted

sim::PlantedClique planted(const benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int k = std::max(1, static_cast<int>(std::lround(0.01 * state.range(1) * n)));
  return sim::planted_clique_graph(n, k, 0.01 * state.range(2), 2026);
}

void report(benchmark::State& state, const std::vector<int>& found, const std::vector<int>& truth) {
  std::size_t hit = 0;
  for (int v : found) hit += std::binary_search(truth.begin(), truth.end(), v) ? 1 : 0;
  state.counters["found"] = static_cast<double>(found.size());
  state.counters["planted"] = static_cast<double>(truth.size());
  state.counters["precision"] =
      found.empty() ? 0.0 : static_cast<double>(hit) / static_cast<double>(found.size());
  state.counters["recall"] =
      truth.empty() ? 1.0 : static_cast<double>(hit) / static_cast<double>(truth.size());
}

// The exact search on a planted graph, with its proven bound, status and node count as counters.
void run_exact(benchmark::State& state, const sim::PlantedClique& p, const pcm::CliqueOptions& o) {
  pcm::CliqueResult r;
  for (auto _ : state) {
    r = pcm::maximum_clique(p.graph, pcm::CliqueAlgorithm::exact, o);
    benchmark::DoNotOptimize(r.clique.data());
  }
  report(state, r.clique, p.planted);
  state.counters["bound"] = r.upper_bound;
  state.counters["optimal"] = r.proven_optimal() ? 1.0 : 0.0;
  state.counters["nodes"] = static_cast<double>(r.nodes_explored);
}

// Exact search with its bounds switched on one by one, each at every candidate (args: n, k %, p %, bounds): 0
// greedy colouring only, 1 + insertion and Re-NUMBER, 2 + MaxSAT unit propagation, 3 MaxSAT without
// Re-NUMBER, 4 the default (both, each while it pays for itself).
void BM_PlantedExact(benchmark::State& state) {
  const auto p = planted(state);
  pcm::CliqueOptions o;
  o.time_limit_s = 10.0;
  const auto bounds = state.range(3);
  o.recolour = bounds == 1 || bounds == 2 || bounds == 4;
  o.maxsat_bound = bounds >= 2;
  o.adaptive_bounds = bounds == 4;
  run_exact(state, p, o);
}

// Refutation only: the exact search started from the planted clique (CliqueOptions::initial_clique), so the
// time is the proof that nothing larger exists (args: n, k %, p %).
void BM_PlantedRefute(benchmark::State& state) {
  const auto p = planted(state);
  pcm::CliqueOptions o;
  o.time_limit_s = 10.0;
  o.initial_clique = p.planted;
  run_exact(state, p, o);
}

void BM_PlantedHeuristic(benchmark::State& state) {
  const auto p = planted(state);
  pcm::CliqueResult r;
  for (auto _ : state) {
    r = pcm::maximum_clique(p.graph, pcm::CliqueAlgorithm::heuristic);
    benchmark::DoNotOptimize(r.clique.data());
  }
  report(state, r.clique, p.planted);
  state.counters["bound"] = r.upper_bound;
}

void BM_PlantedDensest(benchmark::State& state) {
  const auto p = planted(state);
  pcm::DensestResult r;
  for (auto _ : state) {
    r = pcm::densest_subgraph(p.graph);
    benchmark::DoNotOptimize(r.selection.data());
  }
  report(state, r.selection, p.planted);
  state.counters["raw"] = static_cast<double>(r.raw.size());
  state.counters["violations"] = static_cast<double>(r.violations);
  state.counters["converged"] = r.converged ? 1.0 : 0.0;
  state.counters["outer"] = r.outer_iterations;
  state.counters["inner"] = static_cast<double>(r.inner_iterations);
  state.counters["products"] = static_cast<double>(r.products);
}

void planted_family(benchmark::internal::Benchmark* b) {
  for (int n : {100, 300, 1000, 2000})
    for (int k : {1, 2, 10, 30})
      for (int p : {5, 20, 50, 70}) b->Args({n, k, p});
  b->Unit(benchmark::kMillisecond)->Iterations(1);
}

// --- the clique family: the graphs the maximum-clique search and the densest selector must be fast on
// ---------- Four groups, each graph named for the side-by-side script (bench/side_by_side/clique.sh):
//   planted_n<n>_k<k>_p<p%>   planted cliques of k = 2 % and 10 % of n in G(n, p), n = 100 … 2000, p =
//   5/20/50 %
//                             (sim::planted_clique_graph, seed 2026);
//   world1d_m<m>_w<w>         consistency graphs of the Fig. 2.3 generator (ch2_fig2_3_timing's world: half
//                             inliers, a quarter aliased, the rest random; γ at p = 0.11, dof 1), m = 100 …
//                             2000, worlds w = 0 … 4 of seed 20180522;
//   city10000_d<i>            the 81 data sets of ch2_table2_1_city (its config, full profile, its seed):
//                             Q of eq. 2.4 with the joint composition thresholded at γ(11 %);
//   sphere2500_d<i>           the 10 data sets of ch2_table2_2_3d_substitute, alike.
// The two data-set groups need the data sets (scripts/fetch-datasets) and take a few seconds to build (one
// local solve per robot); each group is built once, on first use.

using FamilyGraph = keel::bench::NamedGraph;

struct FamilyGroup {
  std::vector<std::string> names;
  std::function<std::vector<FamilyGraph>()> build;
  std::vector<FamilyGraph> graphs;
  bool built = false;
  std::string error;  // why the group could not be built
  const std::vector<FamilyGraph>& get() {
    if (!built) {
      built = true;
      try {
        graphs = build();
      } catch (const std::exception& e) {
        error = e.what();
      }
    }
    return graphs;
  }
};

constexpr int kPlantedN[] = {100, 300, 1000, 2000};
constexpr int kPlantedK[] = {2, 10};  // percent of n
constexpr int kPlantedP[] = {5, 20, 50};
constexpr int kDenseN[] = {100, 200, 300};  // and G(n, 0.7) with a planted 2 %: where the bounds prune most
constexpr int kWorldM[] = {100, 200, 500, 1000, 2000};
constexpr int kWorlds = 5;
constexpr std::uint64_t kWorldSeed = 20180522;  // ch2_fig2_3_timing's seed

std::string source_path(const std::string& relative) { return std::string(KEEL_SOURCE_DIR) + "/" + relative; }

// The data sets of a two-robot experiment (its full profile and seed), thresholded at γ(11 %).
template <class Table, bool three_d>
std::vector<FamilyGraph> study_graphs(const std::string& id, const std::string& prefix) {
  return keel::bench::study_graphs<Table, three_d>(source_path("experiments/" + id + "/experiment.toml"), id,
                                                   prefix);
}

std::vector<FamilyGroup>& family() {
  static std::vector<FamilyGroup> groups = [] {
    std::vector<FamilyGroup> g(4);
    for (int n : kPlantedN)
      for (int k : kPlantedK)
        for (int p : kPlantedP) g[0].names.push_back(fmt::format("planted_n{}_k{}_p{}", n, k * n / 100, p));
    for (int n : kDenseN) g[0].names.push_back(fmt::format("planted_n{}_k{}_p70", n, 2 * n / 100));
    g[0].build = [] {
      std::vector<FamilyGraph> out;
      for (int n : kPlantedN)
        for (int k : kPlantedK)
          for (int p : kPlantedP) {
            auto pc = sim::planted_clique_graph(n, k * n / 100, 0.01 * p, 2026);
            out.push_back(
                {fmt::format("planted_n{}_k{}_p{}", n, k * n / 100, p),
                 fmt::format("sim::planted_clique_graph({}, {}, {}, 2026)", n, k * n / 100, 0.01 * p),
                 std::move(pc.graph)});
          }
      for (int n : kDenseN) {
        auto pc = sim::planted_clique_graph(n, 2 * n / 100, 0.7, 2026);
        out.push_back({fmt::format("planted_n{}_k{}_p70", n, 2 * n / 100),
                       fmt::format("sim::planted_clique_graph({}, {}, 0.7, 2026)", n, 2 * n / 100),
                       std::move(pc.graph)});
      }
      return out;
    };
    for (int m : kWorldM)
      for (int w = 0; w < kWorlds; ++w) g[1].names.push_back(fmt::format("world1d_m{}_w{}", m, w));
    g[1].build = [] {
      std::vector<FamilyGraph> out;
      for (int m : kWorldM)
        for (int w = 0; w < kWorlds; ++w) {
          const auto o = sim::world1d_options_with_total(sim::World1DOptions{}, m, 0.5, 0.25);
          const auto Q = sim::world1d_consistency_matrix(sim::generate_world1d(o, kWorldSeed, w));
          out.push_back(
              {fmt::format("world1d_m{}_w{}", m, w),
               fmt::format("1D world {} of seed {} with m = {} (Fig. 2.3 generator), gamma(0.11, 1)", w,
                           kWorldSeed, m),
               pcm::ConsistencyGraph::from_threshold(Q.n, Q.q, kGamma)});
        }
      return out;
    };
    for (int i = 0; i < 81; ++i) g[2].names.push_back(fmt::format("city10000_d{:02}", i));
    g[2].build = [] {
      return study_graphs<keel::study::ch2::CityTable, false>("ch2_table2_1_city", "city10000");
    };
    for (int i = 0; i < 10; ++i) g[3].names.push_back(fmt::format("sphere2500_d{:02}", i));
    g[3].build = [] {
      return study_graphs<keel::study::ch2::Substitute3D, true>("ch2_table2_2_3d_substitute", "sphere2500");
    };
    return g;
  }();
  return groups;
}

// The graph of group `group` at `index`, or nullptr after marking the state skipped (data set missing).
const FamilyGraph* family_graph(benchmark::State& state, std::size_t group, std::size_t index) {
  auto& gr = family()[group];
  const auto& graphs = gr.get();
  if (!gr.error.empty() || index >= graphs.size()) {
    if (gr.error.empty()) gr.error = "the group built fewer graphs than it names";
    state.SkipWithError(gr.error.c_str());  // the group outlives the benchmark run
    return nullptr;
  }
  if (graphs[index].name != gr.names[index]) {
    state.SkipWithError("family names out of step");
    return nullptr;
  }
  return &graphs[index];
}

// The exact search's bound variants: colouring only, each bound alone at every candidate, both at every
// candidate, and the default (both, each while it pays for itself: CliqueOptions::adaptive_bounds).
struct ExactVariant {
  const char* name;
  bool recolour, maxsat, adaptive;
};
constexpr ExactVariant kExactVariants[] = {{"colouring", false, false, false},
                                           {"recolour", true, false, false},
                                           {"maxsat", false, true, false},
                                           {"both", true, true, false},
                                           {"default", true, true, true}};

void run_family_exact(benchmark::State& state, std::size_t group, std::size_t index, ExactVariant v) {
  const auto* f = family_graph(state, group, index);
  if (!f) return;
  pcm::CliqueOptions o;
  o.recolour = v.recolour;
  o.maxsat_bound = v.maxsat;
  o.adaptive_bounds = v.adaptive;
  pcm::CliqueResult r;
  for (auto _ : state) {
    r = pcm::maximum_clique(f->graph, pcm::CliqueAlgorithm::exact, o);
    benchmark::DoNotOptimize(r.clique.data());
  }
  state.counters["clique"] = static_cast<double>(r.clique.size());
  state.counters["nodes"] = static_cast<double>(r.nodes_explored);
}

void run_family_densest(benchmark::State& state, std::size_t group, std::size_t index) {
  const auto* f = family_graph(state, group, index);
  if (!f) return;
  pcm::DensestResult r;
  for (auto _ : state) {
    r = pcm::densest_subgraph(f->graph);
    benchmark::DoNotOptimize(r.selection.data());
  }
  state.counters["selection"] = static_cast<double>(r.selection.size());
  state.counters["inner"] = static_cast<double>(r.inner_iterations);
  state.counters["products"] = static_cast<double>(r.products);
}

// One run per repetition, three repetitions, their median (graphs take from microseconds to seconds).
void family_timing(benchmark::internal::Benchmark* b) {
  b->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(true);
}

void register_family() {
  auto& groups = family();
  for (std::size_t gi = 0; gi < groups.size(); ++gi)
    for (std::size_t i = 0; i < groups[gi].names.size(); ++i) {
      const std::string& name = groups[gi].names[i];
      for (const auto& v : kExactVariants)
        family_timing(benchmark::RegisterBenchmark(fmt::format("Family/{}/exact_{}", name, v.name).c_str(),
                                                   run_family_exact, gi, i, v));
      family_timing(benchmark::RegisterBenchmark(fmt::format("Family/{}/densest", name).c_str(),
                                                 run_family_densest, gi, i));
    }
}

// Writes every graph of the family (whose group builds) as DIMACS "p edge" files DIR/<name>.clq (1-based
// vertices), the input of the side-by-side script's solvers. Returns the number written.
int write_family(const std::filesystem::path& dir) {
  int written = 0;
  for (auto& group : family()) {
    const auto& graphs = group.get();
    if (!group.error.empty()) {
      std::fprintf(stderr, "bench_clique: a family group was not written: %s\n", group.error.c_str());
      continue;
    }
    for (const auto& f : graphs) {
      keel::bench::write_dimacs(dir, f.name, "bench_clique family graph: " + f.origin, f.graph);
      ++written;
    }
  }
  return written;
}

}  // namespace

BENCHMARK(BM_Exact)->Apply(sizes);
BENCHMARK(BM_Heuristic)->Apply(sizes);
BENCHMARK(BM_Exact1D)->Apply(world_sizes);
BENCHMARK(BM_Heuristic1D)->Apply(world_sizes);
BENCHMARK(BM_SelectPcmExact1D)->Apply(world_sizes);
BENCHMARK(BM_Scgp1D)->Arg(50)->Arg(100)->Arg(200)->Arg(500)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Ransac1D)->Apply(world_sizes);
BENCHMARK(BM_CombinatorialPruned1D)->Arg(16)->Arg(32)->Arg(48)->Arg(64)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CombinatorialExhaustive1D)->Arg(12)->Arg(16)->Arg(20)->Arg(24)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PlantedExact)->Apply([](benchmark::internal::Benchmark* b) {
  for (int n : {100, 300, 1000, 2000})
    for (int k : {1, 2, 10, 30})
      for (int p : {5, 20, 50, 70})
        for (int bounds : {0, 1, 2, 3, 4}) b->Args({n, k, p, bounds});
  b->Unit(benchmark::kMillisecond)->Iterations(1);
});
BENCHMARK(BM_PlantedRefute)->Apply(planted_family);
BENCHMARK(BM_PlantedHeuristic)->Apply(planted_family);
BENCHMARK(BM_PlantedDensest)->Apply(planted_family);

int main(int argc, char** argv) {
  constexpr const char* kWrite = "--write-family=";
  for (int a = 1; a < argc; ++a)
    if (std::strncmp(argv[a], kWrite, std::strlen(kWrite)) == 0) {
      try {
        const int n = write_family(argv[a] + std::strlen(kWrite));
        std::printf("bench_clique: wrote %d graphs to %s\n", n, argv[a] + std::strlen(kWrite));
        return 0;
      } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
      }
    }
  register_family();
  return keel::bench::run_benchmarks(argc, argv);
}
