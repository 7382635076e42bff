// Google Benchmark for keel.pcm (thesis §2.5): exact and heuristic maximum clique on random consistency
// graphs of sparse density. Run: build/release/bench/bench_clique
import keel.pcm;
import keel.core;

#include <benchmark/benchmark.h>

namespace pcm = keel::pcm;

namespace {

// Args: vertices, density in percent.
void BM_Exact(benchmark::State& state) {
  const auto g = pcm::random_graph(static_cast<int>(state.range(0)), 0.01 * state.range(1), 2015);
  long long size = 0, nodes = 0;
  for (auto _ : state) {
    const auto r = pcm::maximum_clique_exact(g);
    size = static_cast<long long>(r.clique.size());
    nodes = r.nodes_explored;
    benchmark::DoNotOptimize(size);
  }
  state.counters["clique"] = static_cast<double>(size);
  state.counters["nodes"] = static_cast<double>(nodes);
}

void BM_Heuristic(benchmark::State& state) {
  const auto g = pcm::random_graph(static_cast<int>(state.range(0)), 0.01 * state.range(1), 2015);
  long long size = 0;
  for (auto _ : state) {
    const auto r = pcm::maximum_clique_heuristic(g);
    size = static_cast<long long>(r.clique.size());
    benchmark::DoNotOptimize(size);
  }
  state.counters["clique"] = static_cast<double>(size);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int p : {5, 20})
    for (int n : {50, 200, 500, 1000, 2000}) b->Args({n, p});
  b->Unit(benchmark::kMillisecond);
}

}  // namespace

BENCHMARK(BM_Exact)->Apply(sizes);
BENCHMARK(BM_Heuristic)->Apply(sizes);
BENCHMARK_MAIN();
