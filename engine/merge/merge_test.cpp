// The §2.6 map-merging pipeline (merge.hpp) on small synthetic two-robot graphs (keel.sim): inliers alone
// recover the true anchor; the consistency of true inlier pairs follows χ²(dof); aliased groups are mutually
// consistent and random outliers are not; DCS and its accepted candidates; the methods of §2.7 behind one
// MergeMethod; bad inputs give clear std::invalid_argument errors.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "kit/test_kit.hpp"
#include "merge/merge.hpp"
#include "pcm/consistency.hpp"
#include "sim/two_robot.hpp"
#include "sim/two_robot_test_graphs.hpp"
#include "kit/two_robot_pipeline.hpp"

using namespace keel;
using namespace keel::pcm;
using namespace keel::sim;
using namespace keel::merge;
using keel::sim::testing::small_candidate_options;
using keel::sim::testing::square_laps;

using keel::testkit::contains;
using keel::testkit::message_of;

namespace {

// ‖log(R_refᵀ R)‖_F (the rotation error of §2.7.2).
double rotation_error(const lie::SE2& estimate, const lie::SE2& reference) {
  return std::sqrt(2.0) * std::abs((reference.so2().inverse() * estimate.so2()).angle());
}
double rotation_error(const lie::SE3& estimate, const lie::SE3& reference) {
  return std::sqrt(2.0) * (reference.so3().inverse() * estimate.so3()).log().norm();
}

template <class G>
void check_anchor_recovery() {
  const auto p = testkit::two_robot_pipeline<G>(31);
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
}

}  // namespace

TEST_CASE("merge_maps with the inliers alone recovers the true anchor (2D)") {
  check_anchor_recovery<lie::SE2>();
}

TEST_CASE("merge_maps with the inliers alone recovers the true anchor (3D)") {
  check_anchor_recovery<lie::SE3>();
}

TEST_CASE("local_maps: ids are the distinct poses touched, joint their marginal covariance") {
  const auto p = testkit::two_robot_pipeline<lie::SE2>(8);
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

TEST_CASE("consistency of true inlier pairs follows chi2(3)" * doctest::test_suite("monte_carlo")) {
  std::vector<double> q;
  for (std::uint64_t g = 0; g < 40; ++g) {
    const auto p = testkit::two_robot_pipeline<lie::SE2>(1000 + g);
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
  const auto p = testkit::two_robot_pipeline<lie::SE2>(77);
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

TEST_CASE("merge_maps: empty selection, DCS, and the accepted candidates") {
  const auto p = testkit::two_robot_pipeline<lie::SE2>(55);
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
        }).find("unknown merge::AnchorInit 'truth' (valid: selected_edges, identity)") != std::string::npos);
}

TEST_CASE("merge: bad inputs give clear errors") {
  const auto p = testkit::two_robot_pipeline<lie::SE2>(3);
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

TEST_CASE("MergeMethod: one variant of per-kind options; select() is the selection of its kind") {
  const auto p = testkit::two_robot_pipeline<lie::SE2>(61);
  const auto c = generate_candidates(p.scenario, small_candidate_options(), 12, 4);
  const auto maps = local_maps(p.a, p.b, c.candidates);
  const auto Q = consistency_matrix(maps.a, maps.b, c.candidates);
  const double gamma = consistency_threshold(0.11, Q.dof);
  auto sorted = [](Selection s) {
    std::sort(s.selected.begin(), s.selected.end());
    return s.selected;
  };
  CHECK(select(MergeMethod::make("e", MergeMethodKind::pcm_exact), Q).selected ==
        sorted(select_pcm(Q, gamma, CliqueAlgorithm::exact)));
  CHECK(select(MergeMethod::make("h", MergeMethodKind::pcm_heuristic), Q).selected ==
        sorted(select_pcm(Q, gamma, CliqueAlgorithm::heuristic)));
  CHECK(select(MergeMethod::make("r", MergeMethodKind::ransac, 0.01), Q).selected ==
        sorted(select_ransac(Q, consistency_threshold(0.01, Q.dof))));
  CHECK(select(MergeMethod::make("s", MergeMethodKind::scgp), Q).selected == sorted(select_scgp(Q, {})));
  CHECK(select(MergeMethod::make("d", MergeMethodKind::densest), Q).selected ==
        sorted(select_densest(Q, gamma, {})));
  CHECK(message_of([&] {
          (void)select(MergeMethod::make("no_out", MergeMethodKind::no_outliers), Q);
        }).find("selects the caller's inliers") != std::string::npos);
  CHECK(message_of([&] {
          (void)select(MergeMethod::make("dcs", MergeMethodKind::dcs), Q);
        }).find("by merging") != std::string::npos);

  for (const auto kind :
       {MergeMethodKind::no_outliers, MergeMethodKind::dcs, MergeMethodKind::scgp, MergeMethodKind::ransac,
        MergeMethodKind::pcm_exact, MergeMethodKind::pcm_heuristic, MergeMethodKind::densest}) {
    const auto m = MergeMethod::make("m", kind, 0.2, Composition::independent);
    CHECK(m.kind() == kind);
    const bool thresholded = kind == MergeMethodKind::ransac || kind == MergeMethodKind::pcm_exact ||
                             kind == MergeMethodKind::pcm_heuristic || kind == MergeMethodKind::densest;
    CHECK(m.p().has_value() == thresholded);
    if (thresholded) CHECK(*m.p() == 0.2);
    CHECK(m.composition().has_value() == (thresholded || kind == MergeMethodKind::scgp));
    if (m.composition()) CHECK(*m.composition() == Composition::independent);
  }
  CHECK(to_string(MergeMethodKind::pcm_heuristic) == "pcm_heuristic");
  CHECK(merge_method_kind_from_string("densest") == MergeMethodKind::densest);
  CHECK(message_of([] {
          (void)merge_method_kind_from_string("jcbb");
        }).find("unknown merge::MergeMethodKind 'jcbb' (valid: no_outliers, dcs,") != std::string::npos);
  auto bad = MergeMethod::make("ransac", MergeMethodKind::ransac, 1.0);
  CHECK(message_of([&] { bad.validate(); }).find("MergeMethod 'ransac': p must be in (0, 1)") !=
        std::string::npos);
  bad = MergeMethod::make("dcs", MergeMethodKind::dcs);
  std::get<Dcs>(bad.options).accept_scale = 0.0;
  CHECK(message_of([&] { bad.validate(); }).find("dcs_accept_scale must be in (0, 1]") != std::string::npos);
  bad.name.clear();
  CHECK(message_of([&] { bad.validate(); }).find("name must not be empty") != std::string::npos);
}
