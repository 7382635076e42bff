// Google Benchmark for keel.lie (thesis ch. 5): exp/log per group, the joint relative-pose operation
// (eq. 5.51), and Monte-Carlo throughput of the Fig. 5.6 study. Run: build/release/bench/bench_lie Note:
// Debian's libbenchmark prints "Library was built as DEBUG"; that concerns the library's own timing loop
// only.
import keel.core;
import keel.lie;
import keel.repro;
import keel.study;

#include <benchmark/benchmark.h>

#include "csv_union.hpp"

#include <cmath>
#include <vector>

namespace lie = keel::lie;
namespace ch5 = keel::study::ch5;

namespace {

template <class G>
typename G::Tangent tangent(double scale) {
  typename G::Tangent xi;
  for (int i = 0; i < G::DoF; ++i) xi(i) = scale * std::sin(1.7 * (i + 1));
  return xi;
}

template <class G>
void BM_Exp(benchmark::State& state) {
  const auto xi = tangent<G>(0.3);
  for (auto _ : state) benchmark::DoNotOptimize(G::exp(xi));
}

template <class G>
void BM_Log(benchmark::State& state) {
  const G g = G::exp(tangent<G>(0.3));
  for (auto _ : state) benchmark::DoNotOptimize(g.log());
}

template <class G>
void BM_Compose(benchmark::State& state) {
  const G a = G::exp(tangent<G>(0.3)), b = G::exp(tangent<G>(-0.2));
  for (auto _ : state) benchmark::DoNotOptimize(a * b);
}

void BM_RelativePoseJoint(benchmark::State& state) {
  const auto s =
      ch5::relative_pose_setup(M_PI / 4, {3, 3, 0}, {4.5, 4.5, 0}, {0.005, 0.005, 1e-5, 1e-5, 1e-5, 0.006},
                               {0.0005, 0.0005, 0, 0, 0, 0.005}, 1.0);
  const lie::UncertainPose<lie::SE3> g1(s.T_g1, s.cov_g1), g2(s.T_g2, s.cov_g2);
  for (auto _ : state) benchmark::DoNotOptimize(lie::relative(g1, g2, s.cov_g1_g2));
}

void BM_RelativePoseIndependent(benchmark::State& state) {
  const auto s =
      ch5::relative_pose_setup(M_PI / 4, {3, 3, 0}, {4.5, 4.5, 0}, {0.005, 0.005, 1e-5, 1e-5, 1e-5, 0.006},
                               {0.0005, 0.0005, 0, 0, 0, 0.005}, 1.0);
  const lie::UncertainPose<lie::SE3> g1(s.T_g1, s.cov_g1), g2(s.T_g2, s.cov_g2);
  for (auto _ : state) benchmark::DoNotOptimize(lie::relative(g1, g2));
}

// Monte-Carlo samples per second of the relative-pose study (keel.study) (sampling, two exp, inverse,
// compose, log), one thread.
void BM_MonteCarloRelativePose(benchmark::State& state) {
  auto s =
      ch5::relative_pose_setup(M_PI / 4, {3, 3, 0}, {4.5, 4.5, 0}, {0.005, 0.005, 1e-5, 1e-5, 1e-5, 0.006},
                               {0.0005, 0.0005, 0, 0, 0, 0.005}, 1.0);
  s.samples = static_cast<std::size_t>(state.range(0));
  const keel::repro::RunContext one_thread(keel::core::Streams(0), 1);
  for (auto _ : state) benchmark::DoNotOptimize(ch5::simulate_relative_pose(s, one_thread).error_joint);
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

// Monte-Carlo trajectories per second of the composition study (keel.study) (N = 10 steps, four predictions
// scored), one thread.
void BM_MonteCarloComposition(benchmark::State& state) {
  ch5::CompositionSetup s;
  s.steps = 10;
  s.trajectories = static_cast<std::size_t>(state.range(0));
  const keel::repro::RunContext one_thread(keel::core::Streams(0), 1);
  for (auto _ : state) benchmark::DoNotOptimize(ch5::simulate_composition(s, one_thread).lie_joint.inside);
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

}  // namespace

BENCHMARK(BM_Exp<lie::SO2>);
BENCHMARK(BM_Exp<lie::SO3>);
BENCHMARK(BM_Exp<lie::SE2>);
BENCHMARK(BM_Exp<lie::SE3>);
BENCHMARK(BM_Log<lie::SO2>);
BENCHMARK(BM_Log<lie::SO3>);
BENCHMARK(BM_Log<lie::SE2>);
BENCHMARK(BM_Log<lie::SE3>);
BENCHMARK(BM_Compose<lie::SE3>);
BENCHMARK(BM_RelativePoseJoint);
BENCHMARK(BM_RelativePoseIndependent);
BENCHMARK(BM_MonteCarloRelativePose)->Arg(10000);
BENCHMARK(BM_MonteCarloComposition)->Arg(10000);
KEEL_BENCHMARK_MAIN()
