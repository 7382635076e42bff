// The §2.6 map-merging pipeline and the metrics of Tables 2.1–2.2 (merge.hpp) on small synthetic two-robot
// graphs: inliers alone recover the true anchor; the consistency of true inlier pairs follows χ²(dof);
// aliased groups are mutually consistent and random outliers are not; metrics vanish for identical solutions
// and match hand-computed values; bad inputs give clear std::invalid_argument errors.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "pcm/consistency.hpp"
#include "eval/merge.hpp"
#include "sim/two_robot.hpp"
#include "sim/two_robot_test_graphs.hpp"
#include "kit/test_kit.hpp"

using namespace keel;
using namespace keel::pcm;
using namespace keel::sim;
using namespace keel::eval;
using keel::sim::testing::small_candidate_options;
using keel::sim::testing::square_laps;

using keel::testkit::contains;
using keel::testkit::message_of;

namespace {

template <class G>
struct Pipeline {
  TwoRobotScenario<G> scenario;
  LocalSolution<G> a, b;
};

template <class G>
Pipeline<G> pipeline(std::uint64_t seed, int laps = 3) {
  const auto syn = square_laps<G>(laps, 2, seed);
  Pipeline<G> p;
  p.scenario = split_two_robots(syn.graph, syn.truth, {0, 20 * laps, 40 * laps});
  p.a = solve_local(p.scenario.robot_a);
  p.b = solve_local(p.scenario.robot_b);
  return p;
}

template <class G>
void check_anchor_recovery() {
  const auto p = pipeline<G>(31);
  CHECK(p.a.summary.termination == pgo::Termination::converged);
  CHECK(p.a.covariance->num_poses() == 60);
  const auto c = generate_candidates(p.scenario, small_candidate_options(), 5, 0);
  const auto inliers = c.inliers();
  const auto merged = merge_maps(p.a, p.b, c.candidates, inliers);
  CHECK(merged.summary.termination == pgo::Termination::converged);
  REQUIRE(merged.poses_a.size() == 60);
  REQUIRE(merged.poses_b.size() == 60);
  CHECK(merged.inter_robot.size() == inliers.size());
  // Anchor within a few σ of the truth (closures 0.1 m / 0.01 rad, 10 of them; precise odometry).
  const double dt = (merged.anchor_b.translation() - p.scenario.true_anchor.translation()).norm();
  const double dr = rotation_error(merged.anchor_b, p.scenario.true_anchor);
  INFO("anchor error: translation " << dt << " m, rotation " << dr);
  CHECK(dt < 0.15);
  CHECK(dr < 0.03);
  // The merged graph is consistent: normalized χ² near 1 (it is a χ²/dof of a correctly modelled graph).
  CHECK(merged.summary.normalized_chi2 > 0.5);
  CHECK(merged.summary.normalized_chi2 < 1.6);
  CHECK(merged.residual == doctest::Approx(merged.chi2));  // no kernel: every weight is 1
  CHECK(merged.chi2 == doctest::Approx(merged.summary.final_chi2).epsilon(1e-9));
  for (const auto& e : merged.inter_robot) CHECK(e.weight == 1.0);
  CHECK(merged.poses_a[0].is_approx(G(), 1e-12));  // a's pose 0 and anchor are the gauge
  CHECK(merged.poses_b[0].is_approx(merged.anchor_b, 1e-12));

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

TEST_CASE("merge_maps with the inliers alone recovers the true anchor (2D)") {
  check_anchor_recovery<lie::SE2>();
}
TEST_CASE("merge_maps with the inliers alone recovers the true anchor (3D)") {
  check_anchor_recovery<lie::SE3>();
}

TEST_CASE("local_maps: ids are the distinct poses touched, joint their marginal covariance") {
  const auto p = pipeline<lie::SE2>(8);
  const auto c = generate_candidates(p.scenario, small_candidate_options(), 2, 1);
  const auto maps = local_maps(p.a, p.b, c.candidates);
  CHECK(std::is_sorted(maps.a.ids.begin(), maps.a.ids.end()));
  CHECK(std::adjacent_find(maps.b.ids.begin(), maps.b.ids.end()) == maps.b.ids.end());
  for (const auto& m : c.candidates) {
    CHECK(std::binary_search(maps.a.ids.begin(), maps.a.ids.end(), m.pose_a));
    CHECK(std::binary_search(maps.b.ids.begin(), maps.b.ids.end(), m.pose_b));
  }
  CHECK(maps.a.joint.rows() == 3 * static_cast<int>(maps.a.ids.size()));
  CHECK(maps.b.joint.cols() == 3 * static_cast<int>(maps.b.ids.size()));
  CHECK((maps.a.joint - p.a.covariance->joint(maps.a.ids)).cwiseAbs().maxCoeff() == 0.0);
  CHECK(maps.a.poses.size() == 60);
  CHECK(maps.time_s >= 0.0);
}

// The q values of pairs of true inliers follow χ²(3) when the noise is what the information says (§2.4.1:
// "this normalized squared error follows a chi-squared distribution with degree of freedom equal to the
// number of degrees of freedom"). 40 independent graphs × 190 pairs of the 20 true closures; the pairs of one
// graph are correlated, so the tolerances are loose: mean 3 ± 0.35 (about 4 standard errors), tail above
// γ(0.05) in [2 %, 9 %].
TEST_CASE("consistency of true inlier pairs follows chi2(3)") {
  std::vector<double> q;
  for (std::uint64_t g = 0; g < 40; ++g) {
    const auto p = pipeline<lie::SE2>(1000 + g);
    const auto maps = local_maps(p.a, p.b, p.scenario.pool);
    const auto Q = consistency_matrix(maps.a, maps.b, p.scenario.pool);
    REQUIRE(Q.dof == 3);
    for (int u = 0; u < Q.n; ++u)
      for (int v = u + 1; v < Q.n; ++v) q.push_back(Q.at(u, v));
  }
  double mean = 0.0;
  for (double x : q) mean += x;
  mean /= static_cast<double>(q.size());
  const double gamma = consistency_threshold(0.05, 3);
  const double tail =
      static_cast<double>(std::count_if(q.begin(), q.end(), [&](double x) { return x > gamma; })) /
      static_cast<double>(q.size());
  INFO("mean q " << mean << ", tail above gamma(0.05) " << tail << " over " << q.size() << " pairs");
  CHECK(mean > 2.65);
  CHECK(mean < 3.35);
  CHECK(tail > 0.02);
  CHECK(tail < 0.09);
}

TEST_CASE("aliased groups are mutually consistent, random outliers are not") {
  const auto p = pipeline<lie::SE2>(77);
  const double gamma = consistency_threshold(0.01, 3);
  int same_group = 0, same_group_ok = 0, random_pairs = 0, random_ok = 0, cross = 0, cross_ok = 0;
  for (std::uint64_t d = 0; d < 10; ++d) {
    const auto c = generate_candidates(p.scenario, small_candidate_options(), 404, d);
    const auto maps = local_maps(p.a, p.b, c.candidates);
    const auto Q = consistency_matrix(maps.a, maps.b, c.candidates);
    for (int u = 0; u < Q.n; ++u)
      for (int v = u + 1; v < Q.n; ++v) {
        const auto &lu = c.labels[u], &lv = c.labels[v];
        const bool ok = Q.at(u, v) <= gamma;
        if (lu.kind == MeasurementLabel::aliased && lv.kind == MeasurementLabel::aliased &&
            lu.group == lv.group) {
          ++same_group;
          same_group_ok += ok;
        } else if (lu.kind == MeasurementLabel::random && lv.kind == MeasurementLabel::random) {
          ++random_pairs;
          random_ok += ok;
        } else if (lu.is_inlier() != lv.is_inlier()) {
          ++cross;
          cross_ok += ok;
        }
      }
  }
  INFO("same aliased group consistent " << same_group_ok << "/" << same_group << ", random pairs "
                                        << random_ok << "/" << random_pairs << ", inlier-outlier " << cross_ok
                                        << "/" << cross);
  CHECK(same_group == 10 * 2 * 10);
  CHECK(same_group_ok >= 0.95 * same_group);
  CHECK(random_ok <= 0.05 * random_pairs);
  CHECK(cross_ok <= 0.05 * cross);
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

TEST_CASE("merge_maps: empty selection, DCS, and the accepted candidates") {
  const auto p = pipeline<lie::SE2>(55);
  const auto c = generate_candidates(p.scenario, small_candidate_options(), 9, 0);
  // Nothing selected: b's anchor has nothing to align it and stays at the identity; both maps stay solved.
  const auto none = merge_maps(p.a, p.b, c.candidates, {});
  CHECK(none.summary.termination == pgo::Termination::converged);
  CHECK(none.anchor_b.is_approx(lie::SE2(), 1e-12));
  CHECK(none.inter_robot.empty());
  CHECK(accepted_candidates(none, 0.5).empty());

  // DCS on every candidate from the identity (the thesis's baseline): runs; the residual is the DCS-weighted
  // χ².
  const auto dcs = merge_maps(p.a, p.b, c.candidates, c.all(), MergeOptions::dcs(5.0));
  CHECK(dcs.summary.termination != pgo::Termination::failure);
  CHECK(dcs.inter_robot.size() == c.candidates.size());
  CHECK(dcs.residual <= dcs.chi2 + 1e-9);
  const auto kept = accepted_candidates(dcs, 0.5);
  CHECK(kept.size() <= c.candidates.size());
  for (std::size_t k = 0; k < dcs.inter_robot.size(); ++k) {
    CHECK(dcs.inter_robot[k].robust);
    CHECK(dcs.inter_robot[k].scale == doctest::Approx(std::min(1.0, 10.0 / (5.0 + dcs.inter_robot[k].chi2))));
  }
  // Without a kernel every selected candidate counts as accepted.
  const auto plain = merge_maps(p.a, p.b, c.candidates, {3, 1});
  CHECK(accepted_candidates(plain, 0.5) == std::vector<int>{1, 3});
  CHECK(to_string(AnchorInit::identity) == "identity");
  CHECK(anchor_init_from_string("selected_edges") == AnchorInit::selected_edges);
  CHECK(message_of([] {
          (void)anchor_init_from_string("truth");
        }).find("unknown eval::AnchorInit 'truth' (valid: selected_edges, identity)") != std::string::npos);
}

TEST_CASE("merge: bad inputs give clear errors") {
  const auto p = pipeline<lie::SE2>(3);
  auto c = generate_candidates(p.scenario, small_candidate_options(), 1, 0);
  CHECK(message_of([&] {
          (void)merge_maps(p.a, p.b, c.candidates, {50});
        }).find("selected candidate 50 out of range") != std::string::npos);
  CHECK(message_of([&] {
          (void)merge_maps(p.a, p.b, c.candidates, {2, 2});
        }).find("candidate 2 is selected twice") != std::string::npos);
  auto bad = c.candidates;
  bad[4].pose_b = 60;
  CHECK(message_of([&] {
          (void)local_maps(p.a, p.b, bad);
        }).find("candidate 4 touches pose 60 of robot b, which has 60 poses") != std::string::npos);
  CHECK(message_of([&] {
          (void)merge_maps(p.a, p.b, bad, {4});
        }).find("candidate 4 touches pose 60 of robot b") != std::string::npos);
  bad = c.candidates;
  bad[7].pose_a = -1;
  CHECK(message_of([&] { (void)local_maps(p.a, p.b, bad); }).find("candidate 7 touches pose -1 of robot a") !=
        std::string::npos);
  // The nested solver options are validated by pgo::Options::validate.
  MergeOptions mo = MergeOptions::dcs(0.0);
  CHECK(message_of([&] { mo.validate(); }).find("robust_parameter must be finite and > 0") !=
        std::string::npos);
  mo = {};
  mo.solver.max_time_s = 0.0;
  CHECK(message_of([&] {
          (void)merge_maps(p.a, p.b, c.candidates, {0}, mo);
        }).find("max_time_s must be > 0") != std::string::npos);
  LocalSolveOptions lo;
  CHECK(lo.solver.initial_guess == pgo::InitialGuess::odometry);
  lo.solver.initial_guess = pgo::InitialGuess::random;
  CHECK(message_of([&] {
          (void)solve_local(p.scenario.robot_a, lo);
        }).find("solver.initial_guess must be as_read or odometry") != std::string::npos);
  lo = {};
  lo.solver.max_iterations = -1;
  CHECK(message_of([&] { lo.validate(); }).find("max_iterations must be >= 0") != std::string::npos);
}

TEST_CASE("run_merge_dataset: every method on one data set, deterministic, NO-OUT is the reference") {
  const auto p = pipeline<lie::SE2>(61);
  std::vector<MergeMethod> methods(7);
  methods[0].name = "no_out";
  methods[0].kind = MergeMethodKind::no_outliers;
  methods[1].name = "dcs";
  methods[1].kind = MergeMethodKind::dcs;
  methods[2].name = "scgp";
  methods[2].kind = MergeMethodKind::scgp;
  methods[3].name = "ransac";
  methods[3].kind = MergeMethodKind::ransac;
  methods[3].p = 0.01;
  methods[4].name = "pcm_exact";
  methods[4].kind = MergeMethodKind::pcm_exact;
  methods[5].name = "pcm_heu";
  methods[5].kind = MergeMethodKind::pcm_heuristic;
  methods[6].name = "pcm_exact_ind";
  methods[6].kind = MergeMethodKind::pcm_exact;
  methods[6].composition = Composition::independent;
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

  CHECK(to_string(MergeMethodKind::pcm_heuristic) == "pcm_heuristic");
  CHECK(merge_method_kind_from_string("densest") == MergeMethodKind::densest);
  CHECK(merge_method_kind_from_string("ransac") == MergeMethodKind::ransac);
  CHECK(message_of([] {
          (void)merge_method_kind_from_string("jcbb");
        }).find("unknown eval::MergeMethodKind 'jcbb' (valid: no_outliers, dcs,") != std::string::npos);
  auto bad = methods;
  bad[3].p = 1.0;
  CHECK(message_of([&] {
          (void)run_merge_dataset(p.scenario, p.a, p.b, small_candidate_options(), bad, 12, 4);
        }).find("MergeMethod 'ransac': p must be in (0, 1)") != std::string::npos);
  bad = methods;
  bad[1].dcs_accept_scale = 0.0;
  CHECK(message_of([&] { bad[1].validate(); }).find("dcs_accept_scale must be in (0, 1]") !=
        std::string::npos);
  bad = methods;
  bad[0].name.clear();
  CHECK(message_of([&] { bad[0].validate(); }).find("name must not be empty") != std::string::npos);
}
