// Google Benchmark for keel.align (thesis ch. 3) on one world of ch3_table3_1_alignment's generator (default
// AlignmentWorldOptions: 1,891 reference and 325 query positions): round 0's hulls, one sector LP of eq. 3.19
// on them, and whole alignments (every round) per method. Run: build/release/bench/bench_align
import keel.align;
import keel.sim;
import keel.core;
import keel.study;

#include <benchmark/benchmark.h>

#include "csv_union.hpp"

#include <cstdint>

namespace align = keel::align;
namespace sim = keel::sim;

namespace {

const align::AlignmentProblem& problem() {
  static const align::AlignmentProblem p =
      keel::study::ch3::problem_of(sim::make_alignment_world({}, 20181022, 0));
  return p;
}

// Arg: the hull back end (0 qhull, 1 CGAL's regular triangulation).
align::HullBackend backend(const benchmark::State& state, int arg) {
  return state.range(arg) == 0 ? align::HullBackend::qhull : align::HullBackend::regular_triangulation;
}

void BM_GlobalHulls(benchmark::State& state) {
  align::AlignOptions o;
  o.hull.backend = backend(state, 0);
  std::size_t planes = 0;
  for (auto _ : state) {
    const auto reg = align::global_regions(problem(), o);
    planes = reg.plane_count;
    benchmark::DoNotOptimize(planes);
  }
  state.counters["planes"] = static_cast<double>(planes);
}
BENCHMARK(BM_GlobalHulls)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

// One sector LP (sector = arg) of round 0 with lazy rows, from scratch.
void BM_SectorLp(benchmark::State& state) {
  align::AlignOptions o;
  const auto reg = align::global_regions(problem(), o);
  const auto& p = problem();
  int solves = 0, iterations = 0;
  std::size_t rows = 0;
  for (auto _ : state) {
    align::HullLp lp(align::Parameterization::rotation_like, p.query_x, p.query_y, reg.planes, reg.boxes,
                     o.lp);
    lp.set_cs_rows(align::sector_rows(static_cast<int>(state.range(0))));
    const auto s = lp.solve();
    solves = s.solves, rows = s.plane_rows, iterations = s.iterations;
    benchmark::DoNotOptimize(s.cost);
  }
  state.counters["solves"] = solves;
  state.counters["plane_rows"] = static_cast<double>(rows);
  state.counters["iterations"] = iterations;
}
BENCHMARK(BM_SectorLp)->DenseRange(0, 7)->Unit(benchmark::kMillisecond);

// A whole alignment (round-0 hulls shared beforehand, as the study does). Args: method index, threads, hull
// back end.
void BM_AlignWorld(benchmark::State& state) {
  const align::Method methods[] = {align::Method::proposed, align::Method::so_conv_hull,
                                   align::Method::symmetric, align::Method::affine};
  align::AlignOptions o;
  o.method = methods[state.range(0)];
  o.threads = static_cast<unsigned>(state.range(1));
  o.hull.backend = backend(state, 2);
  const auto reg = align::global_regions(problem(), o);
  double hull = 0, lp = 0;
  int rounds = 0, solves = 0;
  for (auto _ : state) {
    const auto r = align::align(problem(), o, &reg);
    hull = lp = 0;
    solves = 0;
    for (const auto& t : r.rounds) hull += t.hull_time_s, lp += t.lp_time_s, solves += t.solves;
    rounds = static_cast<int>(r.rounds.size());
    benchmark::DoNotOptimize(r.cost);
  }
  state.SetLabel(std::string(align::to_string(o.method)));
  state.counters["rounds"] = rounds;
  state.counters["solves"] = solves;
  state.counters["hull_s"] = hull;
  state.counters["lp_s"] = lp;
}
BENCHMARK(BM_AlignWorld)
    ->ArgsProduct({{0, 1, 2, 3}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The certificate of round 0 (branch and bound over θ).
void BM_Certificate(benchmark::State& state) {
  align::AlignOptions o;
  const auto reg = align::global_regions(problem(), o);
  std::size_t nodes = 0;
  for (auto _ : state) {
    const auto c = align::certify_rotation(problem(), reg, o.lp, {});
    nodes = c.nodes;
    benchmark::DoNotOptimize(c.bound.upper);
  }
  state.counters["nodes"] = static_cast<double>(nodes);
}
BENCHMARK(BM_Certificate)->Unit(benchmark::kMillisecond);

}  // namespace

KEEL_BENCHMARK_MAIN()
