// Google Benchmark for keel.pgo: batch solve (Levenberg–Marquardt, sparse normal Cholesky / CHOLMOD) of the
// iSAM benchmark graphs from the odometry initial guess, on 1 and 2 threads. Wall-clock time per solve; the
// counters give the solver's iterations and costs (Ceres' convention: cost = ½ Σ χ²). Run from the repository
// root (datasets are found through datasets/manifest.toml, or $KEEL_DATASETS):
//   build/release/bench/bench_pgo
// Note: Debian's libbenchmark prints "Library was built as DEBUG"; that concerns the library's own timing
// loop only.
import keel.datasets;
import keel.graph;
import keel.pgo;

#include <benchmark/benchmark.h>

#include <string>

namespace datasets = keel::datasets;
namespace graph = keel::graph;
namespace pgo = keel::pgo;

namespace {

const graph::PoseGraph2D& manhattan() {
  static const auto g =
      graph::read_isam_2d(datasets::resolve_dataset_file("manhattan3500", "isam/manhattanOlson3500.txt"));
  return g;
}

const graph::PoseGraph2D& city() {
  static const auto g =
      graph::read_isam_2d(datasets::resolve_dataset_file("city10000", "isam/city10000.txt"));
  return g;
}

const graph::PoseGraph3D& sphere() {
  static const auto g =
      graph::read_isam_3d(datasets::resolve_dataset_file("sphere2500", "isam/sphere2500.txt"));
  return g;
}

template <class Graph>
void solve(benchmark::State& state, const Graph& g) {
  pgo::Options o;
  o.initial_guess = pgo::InitialGuess::odometry;
  o.threads = static_cast<unsigned>(state.range(0));
  pgo::Summary last;
  for (auto _ : state) {
    auto r = pgo::optimize(g, o);
    last = r.summary;
    benchmark::DoNotOptimize(r.estimate.poses.data());
  }
  state.counters["iterations"] = last.iterations;
  state.counters["initial_cost"] = last.initial_cost;
  state.counters["final_cost"] = last.final_cost;
  state.counters["normalized_chi2"] = last.normalized_chi2;
  state.counters["linear_solver_s"] = last.linear_solver_time_s;
  state.counters["jacobian_eval_s"] = last.jacobian_evaluation_time_s;
  state.SetLabel(std::string(pgo::to_string(last.termination)));
}

void BM_Manhattan3500(benchmark::State& state) { solve(state, manhattan()); }
void BM_City10000(benchmark::State& state) { solve(state, city()); }
void BM_Sphere2500(benchmark::State& state) { solve(state, sphere()); }

}  // namespace

BENCHMARK(BM_Manhattan3500)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_City10000)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Sphere2500)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
