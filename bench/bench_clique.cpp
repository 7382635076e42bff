// Google Benchmark for keel.pcm (thesis §2.5, §2.7): exact and heuristic maximum clique on random graphs G(n,
// p) and on consistency graphs of the 1D world of §2.7.1, plus the other selection methods on the same 1D
// matrices Q. Run: build/release/bench/bench_clique [--benchmark_filter=1D]
import keel.pcm;
import keel.sim;
import keel.eval;
import keel.core;

#include <benchmark/benchmark.h>

namespace pcm = keel::pcm;
namespace sim = keel::sim;
namespace eval = keel::eval;

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
        eval::max_consistent_set_combinatorial(Q, kGamma, eval::CombinatorialMethod::pruned));
}

void BM_CombinatorialExhaustive1D(benchmark::State& state) {
  const auto Q = world_q(static_cast<int>(state.range(0)));
  for (auto _ : state)
    benchmark::DoNotOptimize(
        eval::max_consistent_set_combinatorial(Q, kGamma, eval::CombinatorialMethod::exhaustive));
}

void world_sizes(benchmark::internal::Benchmark* b) {
  for (int m : {50, 100, 200, 500, 1000, 2000}) b->Arg(m);
  b->Unit(benchmark::kMicrosecond);
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
BENCHMARK_MAIN();
