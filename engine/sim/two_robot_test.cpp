// Two-robot scenarios (thesis §2.7.2, scenario.hpp): the split keeps the right edges in the right frames, the
// pool holds exactly the true a–b loop closures, candidate generation is deterministic with the right counts
// and labels, and bad inputs give clear std::invalid_argument errors. The real-data cases (City10000,
// sphere2500) are in the doctest suite "datasets" (CTest datasets.sim): without a verified copy of the files
// they fail, naming the file and scripts/fetch-datasets (tests/kit/dataset_files.hpp).
#include <doctest/doctest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "core/random.hpp"
#include "graph/isam.hpp"
#include "graph/trajectory.hpp"
#include "pcm/consistency.hpp"
#include "sim/two_robot.hpp"
#include "sim/two_robot_test_graphs.hpp"
#include "kit/dataset_files.hpp"
#include "kit/test_kit.hpp"

using namespace keel;
using namespace keel::pcm;
using namespace keel::sim;
using keel::sim::testing::square_laps;

using keel::testkit::contains;
using keel::testkit::message_of;

namespace {

template <class M>
bool symmetric_pd(const M& m) {
  if ((m - m.transpose()).cwiseAbs().maxCoeff() > 1e-9 * std::max(1.0, m.cwiseAbs().maxCoeff())) return false;
  return Eigen::LLT<M>(m).info() == Eigen::Success;
}

template <class G>
double pose_distance(const G& x, const G& y) {
  return (x.inverse() * y).log().norm();
}

template <class G>
void check_split(bool with_poses) {
  // 3 laps of 40 poses, closures (i, i + 40) at every 2nd pose; noise-free so that the pool can be checked
  // exactly.
  const auto syn = square_laps<G>(3, 2, 7, /*noisy=*/false, with_poses);
  const SplitOptions split{0, 60, 120};
  const auto s = split_two_robots(syn.graph, syn.truth, split);
  CHECK(s.truth_a.size() == 60);
  CHECK(s.truth_b.size() == 60);
  // robot a: odometry 0..59 (59) + closures i < 20 (10); robot b: odometry (59) + closures 60 ≤ i < 80 (10);
  // the pool: closures 20 ≤ i < 60 (20); the odometry edge (59, 60) is dropped.
  CHECK(s.robot_a.edges.size() == 69);
  CHECK(s.robot_b.edges.size() == 69);
  CHECK(s.pool.size() == 20);
  CHECK(s.pool_information.size() == 20);
  CHECK(s.pool_lines.size() == 20);
  CHECK(s.dropped_odometry == 1);
  for (const auto& e : s.robot_a.edges) CHECK((e.i >= 0 && e.i < 60 && e.j >= 0 && e.j < 60));
  for (const auto& e : s.robot_b.edges) CHECK((e.i >= 0 && e.i < 60 && e.j >= 0 && e.j < 60));
  CHECK(s.truth_a[0].is_approx(G()));
  CHECK(s.truth_b[0].is_approx(G()));
  CHECK(s.true_anchor.is_approx(syn.truth[0].inverse() * syn.truth[60], 1e-12));
  for (int i = 0; i < 60; ++i) {
    CHECK(s.truth_a[i].is_approx(syn.truth[0].inverse() * syn.truth[i], 1e-9));
    CHECK((s.true_anchor * s.truth_b[i]).is_approx(syn.truth[0].inverse() * syn.truth[60 + i], 1e-9));
  }
  if (with_poses) {
    REQUIRE(s.robot_b.poses.size() == 60);
    CHECK(s.robot_b.poses[0].is_approx(G()));
    for (int i = 0; i < 60; ++i) CHECK(s.robot_b.poses[i].is_approx(s.truth_b[i], 1e-9));
  } else {
    CHECK(s.robot_a.poses.empty());
  }
  // Every pool entry is a true loop closure z = (T^a_i)⁻¹ T_ab T^b_k (exact without noise), and its left
  // covariance is that of its residual information.
  for (std::size_t u = 0; u < s.pool.size(); ++u) {
    const auto& m = s.pool[u];
    CHECK(m.pose_b == m.pose_a + 40 - 60);
    CHECK(m.z.is_approx(s.truth_a[m.pose_a].inverse() * s.true_anchor * s.truth_b[m.pose_b], 1e-9));
    CHECK(symmetric_pd(m.covariance));
    const auto cov = left_covariance_from_information(m.z, s.pool_information[u]);
    CHECK((cov - m.covariance).cwiseAbs().maxCoeff() < 1e-12);
  }
  // Bounding box of the ground truth in a's frame: the square is 10 m × 10 m (3D: tilted a little by the
  // wobble).
  const double tol = std::is_same_v<G, lie::SE2> ? 1e-9 : 0.05;
  CHECK(std::abs(s.extent_min(0)) < tol);
  CHECK(std::abs(s.extent_max(0) - 10.0) < tol);
  CHECK(std::abs(s.extent_max(1) - 10.0) < tol);
  for (const auto& T : s.truth_a)
    CHECK(((T.translation() - s.extent_min).minCoeff() >= 0 &&
           (s.extent_max - T.translation()).minCoeff() >= 0));
}

}  // namespace

TEST_CASE("split_two_robots: edges, frames and the pool of true a-b loop closures (2D and 3D)") {
  SUBCASE("2D, graph without initial poses") { check_split<lie::SE2>(false); }
  SUBCASE("2D, graph with initial poses") { check_split<lie::SE2>(true); }
  SUBCASE("3D") { check_split<lie::SE3>(false); }
}

TEST_CASE("split_two_robots: a cross edge stored b -> a is inverted into the pool") {
  auto syn = square_laps<lie::SE2>(3, 2, 7, /*noisy=*/true);
  // Store one cross closure (20, 60) reversed: (60, 20) with z⁻¹ and the information of the reversed
  // residual.
  auto it = std::find_if(syn.graph.edges.begin(), syn.graph.edges.end(),
                         [](const auto& e) { return e.i == 20 && e.j == 60; });
  REQUIRE(it != syn.graph.edges.end());
  const lie::SE2 z = it->measurement;
  const lie::Mat3 cov = left_covariance_from_information(z, it->information);
  const lie::SE2 w = z.inverse();
  const lie::Mat3 Ad = z.adjoint().inverse();  // Ad(z⁻¹)
  const lie::Mat3 cov_w = Ad * cov * Ad.transpose();
  it->i = 60;
  it->j = 20;
  it->measurement = w;
  it->information = information_from_left_covariance(w, cov_w);
  const auto s = split_two_robots(syn.graph, syn.truth, {0, 60, 120});
  auto m = std::find_if(s.pool.begin(), s.pool.end(),
                        [](const auto& c) { return c.pose_a == 20 && c.pose_b == 0; });
  REQUIRE(m != s.pool.end());
  CHECK(m->z.is_approx(z, 1e-12));
  CHECK((m->covariance - cov).cwiseAbs().maxCoeff() < 1e-10);
}

TEST_CASE("split_two_robots: bad inputs give clear errors") {
  const auto syn = square_laps<lie::SE2>(3, 2, 7);
  auto msg = [&](SplitOptions o) { return message_of([&] { split_two_robots(syn.graph, syn.truth, o); }); };
  CHECK(msg({0, 1, 120}).find("robot a = [first, split) needs at least 2 poses") != std::string::npos);
  CHECK(msg({0, 119, 120}).find("robot b = [split, last) needs at least 2 poses") != std::string::npos);
  CHECK(msg({0, 60, 121}).find("last must be <= the number of poses") != std::string::npos);
  CHECK(msg({-1, 60, 120}).find("first must be >= 0") != std::string::npos);
  CHECK(msg({0, 200, 100}).find("needs at least 2 poses") != std::string::npos);

  auto short_truth = syn.truth;
  short_truth.pop_back();
  auto with_poses = syn.graph;
  with_poses.poses = syn.truth;
  CHECK(message_of([&] {
          split_two_robots(with_poses, short_truth, {0, 60, 119});
        }).find("ground truth has 119") != std::string::npos);

  auto bad_truth = syn.truth;
  bad_truth[70] = lie::SE2(std::nan(""), 0.0, 0.0);
  CHECK(message_of([&] {
          split_two_robots(syn.graph, bad_truth, {0, 60, 120});
        }).find("pose 70 is not finite") != std::string::npos);

  // Remove the odometry edge (118, 119): pose 119 has no closure (79 is odd), so robot b falls apart.
  auto cut = syn.graph;
  cut.edges.erase(std::remove_if(cut.edges.begin(), cut.edges.end(),
                                 [](const auto& e) { return e.i == 118 && e.j == 119; }),
                  cut.edges.end());
  CHECK(message_of([&] {
          split_two_robots(cut, syn.truth, {0, 60, 120});
        }).find("robot b's local graph is not connected (its pose 59 = pose 119") != std::string::npos);
}

TEST_CASE("generate_candidates: deterministic, right counts, labels and members") {
  const auto syn = square_laps<lie::SE2>(3, 2, 21);
  const auto s = split_two_robots(syn.graph, syn.truth, {0, 60, 120});
  REQUIRE(s.pool.size() == 20);
  CandidateOptions o;
  o.num_inliers = 10;
  o.aliased_groups = 2;
  o.aliased_group_size = 5;
  o.random_outliers = 30;
  const auto c = generate_candidates(s, o, 99, 3);
  REQUIRE(c.candidates.size() == 50);
  REQUIRE(c.labels.size() == 50);
  REQUIRE(c.information.size() == 50);
  CHECK(c.false_anchors.size() == 2);
  int inl = 0, rnd = 0, group[2] = {0, 0};
  std::set<int> pool_used;
  for (std::size_t k = 0; k < c.candidates.size(); ++k) {
    const auto& m = c.candidates[k];
    const auto& l = c.labels[k];
    CHECK((m.pose_a >= 0 && m.pose_a < 60 && m.pose_b >= 0 && m.pose_b < 60));
    CHECK(symmetric_pd(m.covariance));
    CHECK((left_covariance_from_information(m.z, c.information[k]) - m.covariance).cwiseAbs().maxCoeff() <
          1e-12);
    switch (l.kind) {
      case MeasurementLabel::inlier:
        ++inl;
        CHECK(l.group == -1);
        REQUIRE((l.pool_index >= 0 && l.pool_index < 20));
        pool_used.insert(l.pool_index);
        CHECK(m.z.is_approx(s.pool[l.pool_index].z, 0.0));
        CHECK(m.pose_a == s.pool[l.pool_index].pose_a);
        break;
      case MeasurementLabel::aliased:
        REQUIRE((l.group == 0 || l.group == 1));
        ++group[l.group];
        CHECK(l.pool_index == -1);
        // Consistent with its group's false anchor: z ≈ (T^a_i)⁻¹ A_g T^b_k up to inlier-sized noise.
        CHECK(pose_distance(
                  m.z, s.truth_a[m.pose_a].inverse() * c.false_anchors[l.group] * s.truth_b[m.pose_b]) < 0.6);
        break;
      case MeasurementLabel::random:
        ++rnd;
        CHECK((l.group == -1 && l.pool_index == -1));
        break;
    }
  }
  CHECK(inl == 10);
  CHECK(rnd == 30);
  CHECK(group[0] == 5);
  CHECK(group[1] == 5);
  CHECK(pool_used.size() == 10);  // without replacement
  CHECK(c.inliers().size() == 10);
  CHECK(c.all().size() == 50);

  // Deterministic per (seed, index); another index gives another data set.
  const auto again = generate_candidates(s, o, 99, 3);
  const auto other = generate_candidates(s, o, 99, 4);
  bool same = true, differs = false;
  for (std::size_t k = 0; k < 50; ++k) {
    same = same && again.candidates[k].z.is_approx(c.candidates[k].z, 0.0) &&
           again.candidates[k].pose_a == c.candidates[k].pose_a && again.labels[k].kind == c.labels[k].kind;
    differs = differs || !other.candidates[k].z.is_approx(c.candidates[k].z, 1e-9);
  }
  CHECK(same);
  CHECK(differs);

  // Not shuffled: inliers, then the aliased groups in order, then the random outliers.
  o.shuffle = false;
  const auto ordered = generate_candidates(s, o, 99, 3);
  for (int k = 0; k < 50; ++k) {
    const auto& l = ordered.labels[k];
    if (k < 10)
      CHECK(l.kind == MeasurementLabel::inlier);
    else if (k < 20)
      CHECK((l.kind == MeasurementLabel::aliased && l.group == (k - 10) / 5));
    else
      CHECK(l.kind == MeasurementLabel::random);
  }

  // 3D: same counts.
  const auto syn3 = square_laps<lie::SE3>(3, 2, 21);
  const auto s3 = split_two_robots(syn3.graph, syn3.truth, {0, 60, 120});
  const auto c3 = generate_candidates(s3, o, 5, 0);
  CHECK(c3.candidates.size() == 50);
  CHECK(c3.inliers().size() == 10);
  for (const auto& m : c3.candidates) CHECK(symmetric_pd(m.covariance));
}

TEST_CASE("generate_candidates: near-miss groups agree on an alignment close to the truth (2D and 3D)") {
  CandidateOptions o;
  o.num_inliers = 10;
  o.aliased_groups = 8;
  o.aliased_group_size = 3;
  o.random_outliers = 5;
  o.near_miss_translation_min = 0.5;
  o.near_miss_translation_max = 2.0;
  o.near_miss_rotation_min = 0.05;
  o.near_miss_rotation_max = 0.2;
  const auto syn = square_laps<lie::SE2>(3, 2, 21);
  const auto s = split_two_robots(syn.graph, syn.truth, {0, 60, 120});
  for (std::uint64_t index = 0; index < 5; ++index) {
    const auto c = generate_candidates(s, o, 11, index);
    REQUIRE(c.false_anchors.size() == 8);
    for (const auto& A : c.false_anchors) {
      const auto d = s.true_anchor.inverse() * A;  // δ
      CHECK(d.translation().norm() >= 0.5 - 1e-12);
      CHECK(d.translation().norm() <= 2.0 + 1e-12);
      CHECK(std::fabs(d.angle()) >= 0.05 - 1e-12);
      CHECK(std::fabs(d.angle()) <= 0.2 + 1e-12);
    }
    for (std::size_t k = 0; k < c.candidates.size(); ++k)
      if (c.labels[k].kind == MeasurementLabel::aliased) {
        const auto& m = c.candidates[k];
        CHECK(pose_distance(m.z, s.truth_a[m.pose_a].inverse() * c.false_anchors[c.labels[k].group] *
                                     s.truth_b[m.pose_b]) < 0.6);
      }
  }
  const auto syn3 = square_laps<lie::SE3>(3, 2, 21);
  const auto s3 = split_two_robots(syn3.graph, syn3.truth, {0, 60, 120});
  const auto c3 = generate_candidates(s3, o, 11, 0);
  for (const auto& A : c3.false_anchors) {
    const auto d = s3.true_anchor.inverse() * A;
    CHECK(d.translation().norm() >= 0.5 - 1e-12);
    CHECK(d.translation().norm() <= 2.0 + 1e-12);
    const double angle = d.log().tail<3>().norm();
    CHECK(angle >= 0.05 - 1e-9);
    CHECK(angle <= 0.2 + 1e-9);
  }
  o.near_miss_rotation_min = 0.3;
  CHECK(message_of([&] { o.validate(); }).find("near_miss_rotation range must satisfy 0 <= min <= max") !=
        std::string::npos);
  o.near_miss_rotation_min = 0.0;
  o.near_miss_translation_min = o.near_miss_translation_max = 0.0;
  CHECK(message_of([&] { o.validate(); }).find("near_miss_translation max > 0") != std::string::npos);
}

TEST_CASE("generate_candidates and CandidateOptions: bad inputs give clear errors") {
  const auto syn = square_laps<lie::SE2>(3, 2, 21);
  const auto s = split_two_robots(syn.graph, syn.truth, {0, 60, 120});
  CandidateOptions o;
  o.num_inliers = 21;
  CHECK(message_of([&] {
          generate_candidates(s, o, 1, 0);
        }).find("num_inliers (21) exceeds the pool of true inter-robot loop closures (20)") !=
        std::string::npos);
  o = {};
  o.random_outliers = -1;
  CHECK(message_of([&] { o.validate(); }).find("random_outliers must be >= 0") != std::string::npos);
  o = {};
  o.aliased_group_size = 0;
  CHECK(message_of([&] { o.validate(); }).find("aliased_group_size must be >= 1") != std::string::npos);
  o = {};
  o.random_sigma_translation_min = 2.0;
  o.random_sigma_translation_max = 1.0;
  CHECK(message_of([&] { o.validate(); }).find("random_sigma_translation range") != std::string::npos);
  o = {};
  o.random_sigma_rotation_min = 0.0;
  CHECK(message_of([&] { o.validate(); }).find("random_sigma_rotation range") != std::string::npos);
  o = {};
  o.num_inliers = o.aliased_groups = o.random_outliers = 0;
  CHECK(message_of([&] { o.validate(); }).find("no candidates") != std::string::npos);
}

// Real data: the pool sizes the experiment ch2_table2_1_city and the 3D substitute of Table 2.2 rely on.
TEST_CASE("real data: City10000 (0, 750, 1500) has 209 true a-b loop closures, sphere2500 halves 50" *
          doctest::test_suite("datasets")) {
  const graph::PoseGraph2D city =
      graph::read_isam_2d(testkit::dataset_file("city10000", "isam/city10000.txt"));
  const std::vector<lie::SE2> city_truth =
      graph::read_poses_2d(testkit::dataset_file("city10000", "derived/city10000_groundtruth_poses.txt"));
  const graph::PoseGraph3D sphere =
      graph::read_isam_3d(testkit::dataset_file("sphere2500", "isam/sphere2500.txt"));
  const std::vector<lie::SE3> sphere_truth =
      graph::read_isam_ground_truth_3d(
          testkit::dataset_file("sphere2500", "isam/groundtruth/sphere2500_groundtruth.txt"))
          .poses;
  const auto c = split_two_robots(city, city_truth, {0, 750, 1500});
  CHECK(c.pool.size() == 209);
  CHECK(c.dropped_odometry == 1);
  CHECK(c.robot_a.edges.size() == 749 + 127);
  CHECK(c.robot_b.edges.size() == 749 + 110);
  // The pool's measurements agree with the ground truth to within their noise (City10000: σ 0.02 m, 0.01
  // rad).
  double worst = 0.0;
  for (const auto& m : c.pool)
    worst = std::max(worst,
                     pose_distance(m.z, c.truth_a[m.pose_a].inverse() * c.true_anchor * c.truth_b[m.pose_b]));
  CHECK(worst < 0.15);
  const auto s = split_two_robots(sphere, sphere_truth, {0, 1250, 2500});
  CHECK(s.pool.size() == 50);
  for (const auto& m : s.pool) CHECK(m.pose_b + 1250 - m.pose_a == 50);  // every closure joins i and i + 50
  CandidateOptions o;
  o.num_inliers = 10;
  o.random_outliers = 88;  // + 2 × 5 aliased = 98 outliers (Table 2.2)
  const auto cand = generate_candidates(s, o, 1, 0);
  CHECK(cand.candidates.size() == 108);
}

namespace {

// Mean whitened squared residual rᵀΩr (per degree of freedom) of every edge of a graph at the truth, and of
// the pool.
template <class G>
double mean_chi2_per_dof(const TwoRobotScenario<G>& s) {
  double sum = 0.0;
  int dof = 0;
  auto add = [&](const G& z, const G& X, const typename G::Jacobian& info) {
    const G E = z.inverse() * X;
    typename G::Tangent r;
    if constexpr (std::is_same_v<G, lie::SE2>) {
      r << E.translation(), E.log()(2);  // log's θ is wrapped to (−π, π]
    } else {
      r << E.translation(), E.log().template tail<3>();  // (t, Log R)
    }
    sum += r.dot(info * r);
    dof += G::DoF;
  };
  for (const auto& e : s.robot_a.edges)
    add(e.measurement, s.truth_a[e.i].inverse() * s.truth_a[e.j], e.information);
  for (const auto& e : s.robot_b.edges)
    add(e.measurement, s.truth_b[e.i].inverse() * s.truth_b[e.j], e.information);
  for (std::size_t u = 0; u < s.pool.size(); ++u) {
    const auto& c = s.pool[u];
    add(c.z, s.truth_a[c.pose_a].inverse() * s.true_anchor * s.truth_b[c.pose_b], s.pool_information[u]);
  }
  return sum / dof;
}

template <class G>
void check_resample() {
  const auto syn = square_laps<G>(6, 2, 5);
  auto s = split_two_robots(syn.graph, syn.truth, {0, 120, 240});
  auto s1 = s, s2 = s, tiny = s;
  resample_measurements(s1, 1.0, 7);
  resample_measurements(s2, 0.3, 7);
  resample_measurements(tiny, 1e-9, 7);
  MESSAGE("chi2/dof at the truth: scale 1 " << mean_chi2_per_dof(s1) << ", scale 0.3 "
                                            << mean_chi2_per_dof(s2));
  CHECK(mean_chi2_per_dof(s1) == doctest::Approx(1.0).epsilon(0.1));   // ~1500 residual dofs
  CHECK(mean_chi2_per_dof(s2) == doctest::Approx(0.09).epsilon(0.1));  // s²
  CHECK(mean_chi2_per_dof(tiny) < 1e-15);
  // The pool's left covariance is recomputed at the new measurement.
  for (std::size_t u = 0; u < s2.pool.size(); ++u)
    CHECK((s2.pool[u].covariance - left_covariance_from_information(s2.pool[u].z, s2.pool_information[u]))
              .cwiseAbs()
              .maxCoeff() == 0.0);
  // Deterministic, and nothing but the measurements changes.
  auto again = s;
  resample_measurements(again, 1.0, 7);
  CHECK(again.robot_a.edges.size() == s1.robot_a.edges.size());
  for (std::size_t k = 0; k < s1.robot_a.edges.size(); ++k) {
    CHECK(again.robot_a.edges[k].measurement.matrix() == s1.robot_a.edges[k].measurement.matrix());
    CHECK(again.robot_a.edges[k].information == s.robot_a.edges[k].information);
  }
  CHECK_THROWS_AS(resample_measurements(again, 0.0, 7), std::invalid_argument);
  CHECK_THROWS_AS(resample_measurements(again, std::nan(""), 7), std::invalid_argument);
}

}  // namespace

TEST_CASE("resample_measurements: residuals at the truth follow N(0, s² Ω⁻¹), deterministic (2D and 3D)") {
  SUBCASE("2D") { check_resample<lie::SE2>(); }
  SUBCASE("3D") { check_resample<lie::SE3>(); }
}

TEST_CASE(
    "real data: City10000's measurements are calibrated at the truth (chi2/dof about 1), after the split "
    "too" *
    doctest::test_suite("datasets")) {
  const graph::PoseGraph2D city =
      graph::read_isam_2d(testkit::dataset_file("city10000", "isam/city10000.txt"));
  const std::vector<lie::SE2> truth =
      graph::read_poses_2d(testkit::dataset_file("city10000", "derived/city10000_groundtruth_poses.txt"));
  const auto c = split_two_robots(city, truth, {0, 750, 1500});
  // Local graphs and the pool together: 3 × (876 + 859 + 209) residual dofs. The pool alone too.
  const double all = mean_chi2_per_dof(c);
  auto pool_only = c;
  pool_only.robot_a.edges.clear();
  pool_only.robot_b.edges.clear();
  const double pool = mean_chi2_per_dof(pool_only);
  MESSAGE("chi2/dof at the truth: all " << all << ", pool " << pool);
  CHECK(all == doctest::Approx(1.0).epsilon(0.1));
  CHECK(pool == doctest::Approx(1.0).epsilon(0.15));
}
