// Google Benchmark: the consistency matrix Q of eq. 2.4 (thesis §2.6: "the bottleneck in processing"; the
// thesis reports 70.8 s per City dataset without analytic Jacobians and parallelism). Synthetic local maps
// with a random SPD joint marginal over the touched poses; n candidates → n(n−1) loop errors. Arguments: n,
// threads. Two robots' maps (BM_ConsistencyMatrix) and one robot's (BM_ConsistencyMatrixOneMap).
import keel.core;
import keel.lie;
import keel.pcm;

#include <benchmark/benchmark.h>

#include "csv_union.hpp"

#include <vector>

namespace core = keel::core;
namespace lie = keel::lie;
namespace pcm = keel::pcm;

namespace {

template <class G>
G random_pose(core::Rng& rng, double scale) {
  typename G::Tangent xi;
  for (int i = 0; i < G::DoF; ++i) xi(i) = rng.uniform(-scale, scale);
  return G::exp(xi);
}

lie::MatX random_spd(core::Rng& rng, int d, double scale) {
  lie::MatX A(d, d);
  for (int j = 0; j < d; ++j)
    for (int i = 0; i < d; ++i) A(i, j) = scale * rng.normal();
  return A * A.transpose() + 0.2 * scale * scale * lie::MatX::Identity(d, d);
}

template <class G>
void BM_ConsistencyMatrix(benchmark::State& state) {
  constexpr int d = G::DoF;
  const int n = static_cast<int>(state.range(0));
  core::Rng rng(42);
  pcm::LocalMap<G> a, b;
  for (int s = 0; s < 2 * n; ++s) a.poses.push_back(random_pose<G>(rng, 50.0));
  for (int s = 0; s < 2 * n; ++s) b.poses.push_back(random_pose<G>(rng, 50.0));
  std::vector<pcm::InterRobotMeasurement<G>> c;
  for (int u = 0; u < n; ++u) {
    pcm::InterRobotMeasurement<G> m;
    m.pose_a = 2 * u;  // every candidate touches its own poses: the worst case for the marginal size
    m.pose_b = 2 * u + 1;
    m.z = random_pose<G>(rng, 20.0);
    m.covariance = random_spd(rng, d, 0.05);
    c.push_back(m);
    a.ids.push_back(m.pose_a);
    b.ids.push_back(m.pose_b);
  }
  a.joint = random_spd(rng, d * n, 0.05);
  b.joint = random_spd(rng, d * n, 0.05);
  pcm::ConsistencyOptions options;
  options.threads = static_cast<unsigned>(state.range(1));
  for (auto _ : state) {
    auto Q = pcm::consistency_matrix(a, b, c, options);
    benchmark::DoNotOptimize(Q.q.data());
  }
  state.counters["pairs"] = static_cast<double>(n) * (n - 1);
  state.counters["ns_per_pair"] =
      benchmark::Counter(static_cast<double>(n) * (n - 1),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// One robot's map (keel robust's own loop closures): both ends of every candidate in it, so Σ_uv carries the
// cross-covariance of the loop's two relative poses (consistency.hpp, the one-map form).
template <class G>
void BM_ConsistencyMatrixOneMap(benchmark::State& state) {
  constexpr int d = G::DoF;
  const int n = static_cast<int>(state.range(0));
  core::Rng rng(43);
  pcm::LocalMap<G> map;
  for (int s = 0; s < 2 * n; ++s) {
    map.poses.push_back(random_pose<G>(rng, 50.0));
    map.ids.push_back(s);
  }
  std::vector<pcm::InterRobotMeasurement<G>> c;
  for (int u = 0; u < n; ++u) {
    pcm::InterRobotMeasurement<G> m;
    m.pose_a = 2 * u;
    m.pose_b = 2 * u + 1;
    m.z = random_pose<G>(rng, 20.0);
    m.covariance = random_spd(rng, d, 0.05);
    c.push_back(m);
  }
  map.joint = random_spd(rng, d * 2 * n, 0.05);
  pcm::ConsistencyOptions options;
  options.threads = static_cast<unsigned>(state.range(1));
  for (auto _ : state) {
    auto Q = pcm::consistency_matrix(map, c, options);
    benchmark::DoNotOptimize(Q.q.data());
  }
  state.counters["pairs"] = static_cast<double>(n) * (n - 1);
  state.counters["ns_per_pair"] =
      benchmark::Counter(static_cast<double>(n) * (n - 1),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK(BM_ConsistencyMatrixOneMap<lie::SE2>)
    ->ArgsProduct({{50, 150}, {1}})
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ConsistencyMatrixOneMap<lie::SE3>)
    ->ArgsProduct({{50, 150}, {1}})
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ConsistencyMatrix<lie::SE2>)
    ->ArgsProduct({{50, 115, 300}, {1, 2}})
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ConsistencyMatrix<lie::SE3>)
    ->ArgsProduct({{50, 108, 300}, {1, 2}})
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

KEEL_BENCHMARK_MAIN()
