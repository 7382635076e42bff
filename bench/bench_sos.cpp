// Google Benchmark for keel.sos: SBSOS-SLAM with its certificate (relax, round, polish, refine, certify) per
// 100-pose segment of Manhattan3500 (pose graph) and CityTrees10000 (landmarks), the §4.6 protocol whose
// medians the thesis reports as 20.55 s and 161.8 s (MATLAB + MOSEK). One benchmark iteration solves every
// segment once; the counters give the median and maximum time per segment and the share certified. Variants:
// the dense block by DSDP (what the experiments use) and by SDPA, and the Sparse-BSOS clique structure by
// DSDP on the first `cliques_segments` segments only (it is slower by orders of magnitude; its certified
// share is 0 by design: that structure's bound rests on an unproven translation box, sos/certify.hpp). Run
// from the repository root:
//   build/release/bench/bench_sos
import keel.core;
import keel.datasets;
import keel.graph;
import keel.convex;
import keel.sos;

#include <benchmark/benchmark.h>

#include "csv_union.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace core = keel::core;
namespace datasets = keel::datasets;
namespace graph = keel::graph;
namespace convex = keel::convex;
namespace sos = keel::sos;

namespace {

const graph::PoseGraph2D& manhattan() {
  static const auto g = graph::read_pose_graph_2d(
      datasets::resolve_dataset_file("manhattan3500", "isam/manhattanOlson3500.txt"));
  return g;
}

const graph::PoseGraph2D& city_trees() {
  static const auto g =
      graph::read_pose_graph_2d(datasets::resolve_dataset_file("cityTrees10000", "isam/cityTrees10000.txt"));
  return g;
}

void segments(benchmark::State& state, const graph::PoseGraph2D& g, sos::Structure structure,
              convex::SdpSolver solver, int max_segments) {
  std::vector<sos::Segment> segs;
  const int n = static_cast<int>(g.poses.size());
  for (int first = 0; first + 100 <= n && (max_segments == 0 || static_cast<int>(segs.size()) < max_segments);
       first += 100)
    segs.push_back(sos::extract_segment(g, first, 100));
  sos::CertifyOptions o;
  o.relaxation.structure = structure;
  o.relaxation.sdp.solver = solver;
  std::vector<double> times;
  int certified = 0, solved = 0;
  for (auto _ : state) {
    for (const auto& s : segs) {
      const auto t0 = core::Clock::now();
      const sos::CertifiedSolution c = sos::solve_certified(s.graph, o);
      times.push_back(core::seconds_since(t0));
      certified += c.status == keel::core::SearchStatus::optimal;
      ++solved;
      benchmark::DoNotOptimize(c.bound.upper);
    }
  }
  state.counters["segments"] = static_cast<double>(segs.size());
  state.counters["median_s"] = core::median(times);
  state.counters["max_s"] = times.empty() ? 0.0 : *std::max_element(times.begin(), times.end());
  state.counters["certified_pct"] = 100.0 * certified / std::max(solved, 1);
}

void BM_M3500_dense_dsdp(benchmark::State& s) {
  segments(s, manhattan(), sos::Structure::dense, convex::SdpSolver::dsdp, 0);
}
void BM_M3500_dense_sdpa(benchmark::State& s) {
  segments(s, manhattan(), sos::Structure::dense, convex::SdpSolver::sdpa, 0);
}
void BM_M3500_cliques_dsdp(benchmark::State& s) {
  segments(s, manhattan(), sos::Structure::cliques, convex::SdpSolver::dsdp, 2);
}
void BM_CityTrees_dense_dsdp(benchmark::State& s) {
  segments(s, city_trees(), sos::Structure::dense, convex::SdpSolver::dsdp, 0);
}
void BM_CityTrees_dense_sdpa(benchmark::State& s) {
  segments(s, city_trees(), sos::Structure::dense, convex::SdpSolver::sdpa, 0);
}

}  // namespace

BENCHMARK(BM_M3500_dense_dsdp)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_M3500_dense_sdpa)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_M3500_cliques_dsdp)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_CityTrees_dense_dsdp)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_CityTrees_dense_sdpa)->Unit(benchmark::kSecond)->Iterations(1);

KEEL_BENCHMARK_MAIN()
