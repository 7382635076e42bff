// Google Benchmark for keel.pgo: batch solve (Levenberg–Marquardt, sparse normal Cholesky / CHOLMOD) of the
// iSAM benchmark graphs from the odometry initial guess, on 1 and 2 threads; and the certified solve of the
// isotropic model (pgo::solve_certified) on every SE-Sync benchmark graph (BM_Certified/<name>; counters:
// cost, relative gap of the proven bound (-1 when nothing was proven), certified, rank, Newton iterations,
// seconds per stage). bench/side_by_side/certified.sh runs the same graphs beside SE-Sync. Wall-clock time
// per solve; the counters give the solver's iterations and costs (Ceres' convention: cost = ½ Σ χ²). Run from
// the repository root (datasets are found through datasets/manifest.toml, or $KEEL_DATASETS):
//   build/release/bench/bench_pgo
// Note: Debian's libbenchmark prints "Library was built as DEBUG"; that concerns the library's own timing
// loop only.
import keel.datasets;
import keel.graph;
import keel.pgo;

#include <benchmark/benchmark.h>

#include "csv_union.hpp"

#include <cmath>
#include <map>
#include <string>
#include <type_traits>

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

// The certified solve of one data set file.
template <class Graph>
void certified(benchmark::State& state, const Graph& g) {
  pgo::CertifiedSummary last;
  for (auto _ : state) {
    auto r = pgo::solve_certified(g);
    last = r.summary;
    benchmark::DoNotOptimize(r.poses.data());
  }
  const double gap = last.certificate.bound.relative_gap();
  state.counters["cost"] = last.final_cost;
  state.counters["gap"] = std::isfinite(gap) ? gap : -1.0;
  state.counters["certified"] = last.certificate.certified ? 1.0 : 0.0;
  state.counters["rank"] = last.final_rank;
  state.counters["iterations"] = last.iterations;
  state.counters["init_s"] = last.initialization_time_s;
  state.counters["local_s"] = last.local_time_s;
  state.counters["certificate_s"] = last.certificate_time_s;
  state.SetLabel(std::string(pgo::to_string(last.termination)));
}

struct CertifiedFile {
  const char* name;     // benchmark name
  const char* dataset;  // datasets/manifest.toml
  const char* path;
  int dimension;
};
constexpr CertifiedFile kCertifiedFiles[] = {
    {"manhattan", "manhattan3500", "se-sync/manhattan.g2o", 2},
    {"city10000", "city10000", "se-sync/city10000.g2o", 2},
    {"intel", "intel", "se-sync/intel.g2o", 2},
    {"CSAIL", "se-sync-benchmarks", "CSAIL.g2o", 2},
    {"MIT", "se-sync-benchmarks", "MIT.g2o", 2},
    {"ais2klinik", "se-sync-benchmarks", "ais2klinik.g2o", 2},
    {"kitti_00", "se-sync-benchmarks", "kitti_00.g2o", 2},
    {"kitti_02", "se-sync-benchmarks", "kitti_02.g2o", 2},
    {"kitti_05", "se-sync-benchmarks", "kitti_05.g2o", 2},
    {"sphere2500", "sphere2500", "se-sync/sphere2500.g2o", 3},
    {"torus3D", "se-sync-benchmarks", "torus3D.g2o", 3},
    {"cubicle", "se-sync-benchmarks", "cubicle.g2o", 3},
    {"parking-garage", "parking-garage", "se-sync/parking-garage.g2o", 3},
    {"sphere_bignoise_vertex3", "se-sync-benchmarks", "sphere_bignoise_vertex3.g2o", 3},
    {"smallGrid3D", "se-sync-benchmarks", "smallGrid3D.g2o", 3},
    {"tinyGrid3D", "se-sync-benchmarks", "tinyGrid3D.g2o", 3},
};

// The graph of one file, read once per process (the isotropic model reads only the diagonal blocks).
template <class Graph>
const Graph& certified_graph(const CertifiedFile& f) {
  static std::map<std::string, Graph> cache;
  auto it = cache.find(f.name);
  if (it == cache.end()) {
    const auto file = datasets::resolve_dataset_file(f.dataset, f.path);
    constexpr auto check = graph::InformationCheck::diagonal_blocks;
    if constexpr (std::is_same_v<Graph, graph::PoseGraph2D>) {
      it = cache.emplace(f.name, graph::read_pose_graph_2d(file, check)).first;
    } else {
      it = cache.emplace(f.name, graph::read_pose_graph_3d(file, check)).first;
    }
  }
  return it->second;
}

const bool kCertifiedRegistered = [] {
  for (const auto& f : kCertifiedFiles) {
    benchmark::RegisterBenchmark((std::string("BM_Certified/") + f.name).c_str(),
                                 [f](benchmark::State& state) {
                                   if (f.dimension == 2) {
                                     certified(state, certified_graph<graph::PoseGraph2D>(f));
                                   } else {
                                     certified(state, certified_graph<graph::PoseGraph3D>(f));
                                   }
                                 })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  return true;
}();

}  // namespace

BENCHMARK(BM_Manhattan3500)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_City10000)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Sphere2500)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

KEEL_BENCHMARK_MAIN()
