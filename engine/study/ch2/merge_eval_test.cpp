// The metrics of Tables 2.1–2.2 and one data set with every method (merge.hpp) on small synthetic two-robot
// graphs: metrics vanish for identical solutions and match hand-computed values; every method runs on one
// data set, deterministically, with NO-OUT as the reference.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "pcm/consistency.hpp"
#include "study/ch2/merge_eval.hpp"
#include "sim/two_robot.hpp"
#include "sim/two_robot_test_graphs.hpp"
#include "kit/test_kit.hpp"
#include "kit/two_robot_pipeline.hpp"

using namespace keel;
using namespace keel::pcm;
using namespace keel::sim;
using namespace keel::study::ch2;
using keel::sim::testing::small_candidate_options;
using keel::sim::testing::square_laps;

using keel::testkit::contains;
using keel::testkit::message_of;

namespace {

template <class G>
void check_anchor_metrics() {
  const auto p = testkit::two_robot_pipeline<G>(31);
  CHECK(p.a.summary.termination == pgo::Termination::converged);
  CHECK(p.a.covariance->num_poses() == 60);
  const auto c = generate_candidates(p.scenario, small_candidate_options(), 5, 0);
  const auto inliers = c.inliers();
  const auto merged = merge_maps(p.a, p.b, c.candidates, inliers);
  const double dt = (merged.anchor_b.translation() - p.scenario.true_anchor.translation()).norm();
  // Metrics of the reference against itself: zero errors, exact classification.
  const auto m = evaluate_merge(merged, merged, p.scenario, inliers, c.labels);
  CHECK(m.map.translation_mse == 0.0);
  CHECK(m.map.rotation < 1e-12);
  CHECK(m.map.count == 120);
  CHECK(m.classification.tp == 10);
  CHECK(m.classification.fp == 0);
  CHECK(m.classification.fn == 0);
  CHECK(m.classification.tn == 40);
  CHECK(m.anchor_translation_sq == doctest::Approx(dt * dt));
  CHECK(m.trajectory.count == 118);
  CHECK(m.trajectory.translation_mse < 0.05);

  // All candidates without a kernel: the outliers drag the map away (normalized χ² far above 1).
  const auto all = merge_maps(p.a, p.b, c.candidates, c.all());
  const auto mall = evaluate_merge(all, merged, p.scenario, c.all(), c.labels);
  CHECK(all.summary.normalized_chi2 > 5.0);
  CHECK(mall.map.translation_mse > 0.1);
  CHECK(mall.classification.fpr() == 1.0);
  CHECK(mall.classification.tpr() == 1.0);
}

}  // namespace

// The q values of pairs of true inliers follow χ²(3) when the noise is what the information says (§2.4.1:
// "this normalized squared error follows a chi-squared distribution with degree of freedom equal to the
// number of degrees of freedom"). 40 independent graphs × 190 pairs of the 20 true closures; the pairs of one
// graph are correlated, so the tolerances are loose: mean 3 ± 0.35 (about 4 standard errors), tail above
// γ(0.05) in [2 %, 9 %].

TEST_CASE("metrics of the inlier merge against itself; all candidates drag the map away (2D, 3D)") {
  check_anchor_metrics<lie::SE2>();
  check_anchor_metrics<lie::SE3>();
}

TEST_CASE("metrics: zero for identical solutions, hand-computed values on a tiny case") {
  const std::vector<lie::SE2> ref = {lie::SE2(0, 0, 0), lie::SE2(1, 0, 0), lie::SE2(1, 1, 1.0)};
  const auto same = absolute_error(ref, ref);
  CHECK(same.translation_mse == 0.0);
  CHECK(same.rotation == 0.0);
  CHECK(same.count == 3);
  const std::vector<lie::SE2> est = {lie::SE2(1, 0, 0.1), lie::SE2(1, 2, 0), lie::SE2(1, 1, 1.0 - 0.3)};
  const auto e = absolute_error(est, ref);
  CHECK(e.translation_mse == doctest::Approx((1.0 + 4.0 + 0.0) / 3.0));
  CHECK(e.rotation == doctest::Approx(std::sqrt(2.0) * (0.1 + 0.0 + 0.3) / 3.0));
  // Wrapping: 3.1 vs −3.1 differ by 2π − 6.2.
  CHECK(rotation_error(lie::SE2(0, 0, 3.1), lie::SE2(0, 0, -3.1)) ==
        doctest::Approx(std::sqrt(2.0) * (2 * lie::kPi - 6.2)));
  // Consecutive relative poses: the reference steps are (1, 0, 0) and (0, 1, 1).
  const auto r = relative_error(est, ref);
  CHECK(r.count == 2);
  const lie::SE2 d1 = est[0].inverse() * est[1], d2 = est[1].inverse() * est[2];
  const double t1 = (d1.translation() - lie::Vec2(1, 0)).squaredNorm(),
               t2 = (d2.translation() - lie::Vec2(0, 1)).squaredNorm();
  CHECK(r.translation_mse == doctest::Approx((t1 + t2) / 2));
  CHECK(r.rotation == doctest::Approx(std::sqrt(2.0) * (0.1 + 0.3) / 2));
  // By hand: d1 = (R(−0.1)(0, 2), −0.1) = (2 sin 0.1, 2 cos 0.1, −0.1).
  CHECK(t1 == doctest::Approx(std::pow(1 - 2 * std::sin(0.1), 2) + std::pow(2 * std::cos(0.1), 2)));
  // 3D: a rotation by 0.2 rad about any axis has ‖log‖_F = √2 · 0.2.
  const lie::SE3 R3(lie::SO3::exp(lie::Vec3(0.0, 0.2 / std::sqrt(2.0), 0.2 / std::sqrt(2.0))),
                    lie::Vec3(1, 2, 3));
  CHECK(rotation_error(R3, lie::SE3()) == doctest::Approx(std::sqrt(2.0) * 0.2));
  const auto e3 = absolute_error(std::vector<lie::SE3>{R3}, std::vector<lie::SE3>{lie::SE3()});
  CHECK(e3.translation_mse == doctest::Approx(14.0));

  // Classification.
  std::vector<CandidateLabel> labels(6);
  labels[3].kind = labels[4].kind = MeasurementLabel::random;
  labels[5].kind = MeasurementLabel::aliased;
  const auto c = classify({0, 1, 4}, labels);  // inliers 0,1,2; outliers 3,4,5
  CHECK(c.tp == 2);
  CHECK(c.fn == 1);
  CHECK(c.fp == 1);
  CHECK(c.tn == 2);
  CHECK(c.tpr() == doctest::Approx(2.0 / 3.0));
  CHECK(c.fpr() == doctest::Approx(1.0 / 3.0));
  CHECK(message_of([&] { (void)classify({0, 0}, labels); }).find("selected twice") != std::string::npos);
  CHECK(message_of([&] { (void)classify({6}, labels); }).find("out of range") != std::string::npos);
  CHECK(message_of([&] {
          (void)absolute_error(est, std::vector<lie::SE2>{});
        }).find("need equal, non-zero sizes") != std::string::npos);
  CHECK(message_of([&] {
          (void)relative_error(std::vector<lie::SE2>{ref[0]}, std::vector<lie::SE2>{ref[0]});
        }).find("at least 2") != std::string::npos);
}

TEST_CASE("run_merge_dataset: every method on one data set, deterministic, NO-OUT is the reference") {
  const auto p = testkit::two_robot_pipeline<lie::SE2>(61);
  const std::vector<MergeMethod> methods = {
      MergeMethod::make("no_out", MergeMethodKind::no_outliers),
      MergeMethod::make("dcs", MergeMethodKind::dcs),
      MergeMethod::make("scgp", MergeMethodKind::scgp),
      MergeMethod::make("ransac", MergeMethodKind::ransac, 0.01),
      MergeMethod::make("pcm_exact", MergeMethodKind::pcm_exact),
      MergeMethod::make("pcm_heu", MergeMethodKind::pcm_heuristic),
      MergeMethod::make("pcm_exact_ind", MergeMethodKind::pcm_exact, 0.11, Composition::independent)};
  const auto d = run_merge_dataset(p.scenario, p.a, p.b, small_candidate_options(), methods, 12, 4,
                                   /*keep_solutions=*/true);
  REQUIRE(d.methods.size() == 7);
  CHECK(d.candidates.candidates.size() == 50);
  CHECK(d.matrix_time_s > 0.0);
  CHECK(d.matrix_independent_time_s > 0.0);
  const auto& ref = d.methods[0];
  CHECK(ref.metrics.map.translation_mse == 0.0);
  CHECK(ref.metrics.classification.tpr() == 1.0);
  CHECK(ref.metrics.classification.fpr() == 0.0);
  CHECK(ref.merged.poses_a.size() == 60);
  // PCM's selection is pairwise consistent (eq. 2.3) and proven maximum; the heuristic's is consistent too.
  const auto maps = local_maps(p.a, p.b, d.candidates.candidates);
  const auto Q = consistency_matrix(maps.a, maps.b, d.candidates.candidates);
  const double gamma = consistency_threshold(0.11, 3);
  for (int k : {4, 5}) {
    const auto& sel = d.methods[k].selection.selected;
    CHECK(!sel.empty());
    for (std::size_t u = 0; u < sel.size(); ++u)
      for (std::size_t v = u + 1; v < sel.size(); ++v) CHECK(Q.at(sel[u], sel[v]) <= gamma);
  }
  CHECK(d.methods[4].selection.proven_optimal());
  CHECK(d.methods[4].selection.search->upper_bound ==
        static_cast<int>(d.methods[4].selection.selected.size()));
  // PCM-Exact on this easy data set: no outlier accepted, most inliers kept, map close to the reference.
  CHECK(d.methods[4].metrics.classification.fp == 0);
  CHECK(d.methods[4].metrics.classification.tp >= 7);
  CHECK(d.methods[4].metrics.map.translation_mse < 0.05);
  // DCS's selection is its accepted candidates; its solve was kept.
  CHECK(d.methods[1].merged.inter_robot.size() == 50);
  CHECK(d.methods[1].selection.selected == accepted_candidates(d.methods[1].merged, 0.5));
  CHECK_FALSE(d.methods[1].selection.search.has_value());

  const auto again = run_merge_dataset(p.scenario, p.a, p.b, small_candidate_options(), methods, 12, 4);
  for (std::size_t k = 0; k < methods.size(); ++k) {
    CHECK(again.methods[k].selection.selected == d.methods[k].selection.selected);
    CHECK(again.methods[k].metrics.map.translation_mse == d.methods[k].metrics.map.translation_mse);
    CHECK(again.methods[k].metrics.residual == d.methods[k].metrics.residual);
    CHECK(again.methods[k].merged.poses_a.empty());  // not kept
  }

  auto bad = methods;
  std::get<merge::Ransac>(bad[3].options).p = 1.0;
  CHECK(message_of([&] {
          (void)run_merge_dataset(p.scenario, p.a, p.b, small_candidate_options(), bad, 12, 4);
        }).find("MergeMethod 'ransac': p must be in (0, 1)") != std::string::npos);
}

TEST_CASE(
    "run_merge_dataset: methods that select the same candidates share one solve, equal to a fresh one") {
  const auto p = testkit::two_robot_pipeline<lie::SE2>(61);
  const std::vector<MergeMethod> methods = {
      MergeMethod::make("no_out", MergeMethodKind::no_outliers),
      MergeMethod::make("pcm_exact", MergeMethodKind::pcm_exact, 0.11),
      MergeMethod::make("pcm_exact_b", MergeMethodKind::pcm_exact, 0.1100001),
      MergeMethod::make("pcm_heu", MergeMethodKind::pcm_heuristic, 0.11),
      MergeMethod::make("ransac", MergeMethodKind::ransac, 0.01)};
  const auto d = run_merge_dataset(p.scenario, p.a, p.b, small_candidate_options(), methods, 12, 4,
                                   /*keep_solutions=*/true);
  REQUIRE(d.methods.size() == methods.size());
  const auto& cands = d.candidates.candidates;
  int shared = 0;
  for (std::size_t k = 1; k < methods.size(); ++k) {
    const auto& mk = d.methods[k];
    // The solve a method reports is the solve of its selection, bit for bit.
    const auto fresh = merge_maps(p.a, p.b, cands, mk.selection.selected);
    REQUIRE(fresh.poses_a.size() == mk.merged.poses_a.size());
    for (std::size_t i = 0; i < fresh.poses_a.size(); ++i) {
      CHECK(fresh.poses_a[i].translation() == mk.merged.poses_a[i].translation());
      CHECK(fresh.poses_a[i].angle() == mk.merged.poses_a[i].angle());
    }
    CHECK(fresh.chi2 == mk.merged.chi2);
    CHECK(fresh.residual == mk.merged.residual);
    for (std::size_t j = 0; j < k; ++j)
      if (d.methods[j].selection.selected == mk.selection.selected) {
        ++shared;  // one solve: its time is reported for both
        CHECK(d.methods[j].solve_time_s == mk.solve_time_s);
      }
  }
  CHECK(shared >= 2);  // the two PCM-Exact thresholds at least, and the heuristic on this easy data set
}
