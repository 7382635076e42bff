// Google Benchmark for keel.pcm (thesis §2.5, §2.7): exact and heuristic maximum clique on random graphs G(n,
// p) and on consistency graphs of the 1D world of §2.7.1, plus the other selection methods on the same 1D
// matrices Q, and a planted-clique family for exact, heuristic and densest-subgraph selection.
// Run: build/release/bench/bench_clique [--benchmark_filter=1D|Planted]
import keel.pcm;
import keel.sim;
import keel.core;

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
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

// Exact search with its bounds switched on one by one (args: n, k %, p %, bounds): 0 greedy colouring only,
// 1 + insertion and Re-NUMBER, 2 + MaxSAT unit propagation (the default), 3 MaxSAT without Re-NUMBER.
void BM_PlantedExact(benchmark::State& state) {
  const auto p = planted(state);
  pcm::CliqueOptions o;
  o.time_limit_s = 10.0;
  const auto bounds = state.range(3);
  o.recolour = bounds == 1 || bounds == 2;
  o.maxsat_bound = bounds >= 2;
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
}

void planted_family(benchmark::internal::Benchmark* b) {
  for (int n : {100, 300, 1000, 2000})
    for (int k : {1, 2, 10, 30})
      for (int p : {5, 20, 50, 70}) b->Args({n, k, p});
  b->Unit(benchmark::kMillisecond)->Iterations(1);
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
        for (int bounds : {0, 1, 2, 3}) b->Args({n, k, p, bounds});
  b->Unit(benchmark::kMillisecond)->Iterations(1);
});
BENCHMARK(BM_PlantedRefute)->Apply(planted_family);
BENCHMARK(BM_PlantedHeuristic)->Apply(planted_family);
BENCHMARK(BM_PlantedDensest)->Apply(planted_family);
BENCHMARK_MAIN();
