// The chapter-2 study layer: measurement regimes, data sets in parallel against one by one, per-method
// summaries, the pool's χ² at the truth and the calibration of Q (Monte-Carlo agreement with the stated
// noise), and the 1D studies behind Figs. 2.2–2.3 against their definitions.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "study/ch2/two_robot.hpp"
#include "study/ch2/world1d.hpp"
#include "kit/test_kit.hpp"
#include "pcm/consistency.hpp"
#include "sim/two_robot_test_graphs.hpp"

using namespace keel;
using namespace keel::study::ch2;
using keel::core::Streams;
using keel::repro::RunContext;
using keel::sim::testing::small_candidate_options;
using keel::sim::testing::square_laps;
using keel::testkit::contains;
using keel::testkit::message_of;

namespace {

sim::TwoRobotScenario2 scenario(std::uint64_t seed) {
  const auto syn = square_laps<lie::SE2>(3, 2, seed);
  return sim::split_two_robots(syn.graph, syn.truth, {0, 60, 120});
}

}  // namespace

TEST_CASE("data sets in parallel equal data sets one by one; summaries pool what the data sets hold") {
  const auto s = scenario(3);
  const auto local = solve_local_pair(s);
  const std::vector<MergeMethod> methods = {MergeMethod::make("no_out", MergeMethodKind::no_outliers),
                                            MergeMethod::make("pcm", MergeMethodKind::pcm_exact),
                                            MergeMethod::make("heu", MergeMethodKind::pcm_heuristic)};
  const auto runs =
      run_merge_datasets(s, local, small_candidate_options(), methods, RunContext(Streams(17), 2), 4, 1);
  REQUIRE(runs.size() == 4);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto one = run_merge_dataset(s, local.a, local.b, small_candidate_options(), methods, 17, i);
    for (std::size_t k = 0; k < methods.size(); ++k) {
      CHECK(runs[i].methods[k].selection.selected == one.methods[k].selection.selected);
      CHECK(runs[i].methods[k].metrics.normalized_chi2 == one.methods[k].metrics.normalized_chi2);
    }
    CHECK(runs[i].methods[0].merged.poses_a.empty() == (i != 1));  // only data set `keep` keeps its solutions
  }
  const auto sum = summarize_method(runs, 1);
  int tp = 0, fp = 0;
  for (const auto& d : runs) {
    tp += d.methods[1].metrics.classification.tp;
    fp += d.methods[1].metrics.classification.fp;
  }
  CHECK(sum.pooled.tp == tp);
  CHECK(sum.pooled.fp == fp);
  CHECK(sum.column("chi2").size() == 4);
  CHECK(sum.mean("tp") == doctest::Approx(tp / 4.0));
  CHECK(contains(message_of([&] { (void)sum.column("mse"); }), "no column 'mse' (valid: chi2, fp,"));
  CHECK(same_selections(runs, 1, 1) == 4);
  CHECK(proven_optimal(runs, 1) == 4);  // exact search on a small graph: always completed
  CHECK(proven_optimal(runs, 0) == 0);  // NO-OUT has no clique search
  CHECK(contains(message_of([&] { (void)method_index({}, "x", "[claims]"); }), "[claims] names method 'x'"));
}

TEST_CASE("the pool's χ² at the truth is s² and Q's calibration follows χ²(3) after resampling at scale s" *
          doctest::test_suite("monte_carlo")) {
  const auto base = scenario(5);
  for (double s : {1.0, 0.25}) {
    MeasurementRegime g{"s", "", true, s, 99};
    const auto x = apply_regime(base, g);
    // Mean of χ²(3)/3 over the pool: standard error sqrt(2/3 / pool) ≈ 0.1 for the ~60 closures here.
    const double chi2 = pool_chi2_at_truth(x);
    INFO("s = " << s << ", pool " << x.pool.size() << ", chi2/dof " << chi2);
    CHECK(chi2 / (s * s) == doctest::Approx(1.0).epsilon(0.35));
    CHECK(apply_regime(small_candidate_options(), g).aliased_noise_scale == s);
  }
  const auto local = solve_local_pair(base);
  const std::vector<double> gammas = {pcm::consistency_threshold(0.5, 3),
                                      pcm::consistency_threshold(0.01, 3)};
  const auto cal = pool_calibration(local, base, pcm::Composition::joint, gammas);
  REQUIRE(cal.fail.size() == 2);
  CHECK(cal.fail[0] >= cal.fail[1]);  // a larger γ fails fewer pairs
  CHECK(cal.q_mean > 0.0);
  MeasurementRegime bad{"bad", "", false, 0.5, 0};
  CHECK(contains(message_of([&] { bad.validate(); }), "own measurements have noise_scale 1"));
}

TEST_CASE(
    "the 1D comparison of Fig. 2.2 follows its definition; the timing sweep of Fig. 2.3 runs what it says") {
  World1DStudyOptions o;
  o.pcm_gamma = pcm::consistency_threshold(0.11, 1);
  o.ransac_gamma = o.pcm_gamma;
  o.worlds = 200;
  const auto study = run_world1d_study(o, RunContext(Streams(3)));
  const auto cmp = compare_to_combinatorial(study, {Selector1D::pcm_exact, Selector1D::ransac});
  REQUIRE(cmp.rows.size() == 2);
  CHECK(cmp.rows[0].match_rate == 1.0);  // PCM-Exact attains the combinatorial maximum (eq. 2.5)
  CHECK(cmp.rows[0].inconsistent_total == 0);
  for (const auto& row : cmp.rows) {
    CHECK(row.match_rate + row.larger_rate + row.smaller_rate == doctest::Approx(1.0));
    CHECK(std::accumulate(row.size_diff_hist.begin(), row.size_diff_hist.end(), 0.0) == doctest::Approx(1.0));
    CHECK(std::accumulate(row.inconsistent_hist.begin(), row.inconsistent_hist.end(), 0.0) ==
          doctest::Approx(1.0));
  }
  CHECK(cmp.heuristic_above_exact == 0);

  TimingSweepOptions t;
  t.base = o;
  t.base.worlds = 20;
  t.sizes = {4, 12, 40};
  t.exhaustive_max = 12;
  t.pruned_max = 12;
  const auto sweep = run_timing_sweep(t, RunContext(Streams(3)));
  REQUIRE(sweep.curves.size() == 6);
  CHECK(sweep.curves[0].m == std::vector<double>{4, 12});  // exhaustive only up to its cap
  CHECK(sweep.curves[2].m == std::vector<double>{4, 12, 40});
  CHECK(sweep.combinatorial_checked == 2 * 2 * 20);
  CHECK(sweep.combinatorial_mismatch == 0);
  CHECK(sweep.heuristic_match.size() == 3);
  CHECK(t.work() == 20 * (2 + 2 + 1));
  t.sizes = {5, 4};
  CHECK(contains(message_of([&] { t.validate(); }), "increasing order"));
}
