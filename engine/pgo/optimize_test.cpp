// optimize(): recovery of ground truth on noise-free synthetic graphs (2D with landmarks, 3D), robust kernels
// against a gross outlier, anchors of two robots, deterministic random initial guesses, options and input
// errors.
#include <doctest/doctest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "kit/test_kit.hpp"
#include "lie/euler.hpp"
#include "pgo/optimize.hpp"
#include "pgo/robust.hpp"

using namespace keel;
using namespace keel::pgo;
using keel::testkit::InformationDraw;
// Information as scale · (B Bᵀ / N + I) (InformationDraw::spd, minimum eigenvalue 1): eigenvalues ≥ scale.
using keel::testkit::random_information;

namespace {

double normal(core::Rng& rng, double sigma) { return sigma * rng.normal(); }

// Three laps of a circle of radius 8 (20 poses a lap), heading along the circle.
std::vector<lie::SE2> circle_truth(int n, double radius = 8.0, double phase = 0.0) {
  std::vector<lie::SE2> poses;
  for (int k = 0; k < n; ++k) {
    const double a = phase + 2 * lie::kPi * k / 20.0;
    poses.emplace_back(radius * std::cos(a), radius * std::sin(a), lie::wrap_angle(a + lie::kPi / 2));
  }
  return poses;
}

graph::Edge2 edge2(const std::vector<lie::SE2>& T, int i, int j, const lie::Mat3& info) {
  graph::Edge2 e;
  e.i = i;
  e.j = j;
  e.measurement = T[i].inverse() * T[j];
  e.information = info;
  return e;
}

// Noise-free 2D graph: odometry, loop closures one and two laps back and a few chords, landmarks seen from
// nearby.
graph::PoseGraph2D synthetic_2d(const std::vector<lie::SE2>& T, const std::vector<lie::Vec2>& L,
                                core::Rng& rng, double info_scale = 50.0) {
  graph::PoseGraph2D g;
  const int n = static_cast<int>(T.size());
  for (int k = 0; k + 1 < n; ++k)
    g.edges.push_back(edge2(T, k, k + 1, random_information<3>(rng, InformationDraw::spd, info_scale, 1.0)));
  for (int k = 20; k < n; ++k)
    g.edges.push_back(edge2(T, k - 20, k, random_information<3>(rng, InformationDraw::spd, info_scale, 1.0)));
  for (int k = 0; k + 7 < n; k += 5)
    g.edges.push_back(edge2(T, k, k + 7, random_information<3>(rng, InformationDraw::spd, info_scale, 1.0)));
  for (int k = 0; k < n; ++k)
    for (int l = 0; l < static_cast<int>(L.size()); ++l)
      if ((T[k].translation() - L[l]).norm() < 9.0) {
        graph::LandmarkMeasurement2 m;
        m.pose = k;
        m.landmark = l;
        m.position = T[k].rotation().transpose() * (L[l] - T[k].translation());
        m.information = random_information<2>(rng, InformationDraw::spd, info_scale, 1.0);
        g.landmark_measurements.push_back(m);
      }
  g.poses = T;
  g.landmarks = L;
  g.has_initial_poses = true;
  g.source = "synthetic_2d";
  return g;
}

std::vector<lie::SE3> helix_truth(int n) {
  std::vector<lie::SE3> poses;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * lie::kPi * k / 20.0;
    lie::Vec6 xi_r = lie::Vec6::Zero();
    xi_r(5) = a;
    lie::Vec6 tilt = lie::Vec6::Zero();
    tilt(3) = 0.3 * std::sin(1.3 * k);
    tilt(4) = 0.2 * std::cos(0.7 * k);
    const lie::SE3 R = lie::SE3::exp(xi_r) * lie::SE3::exp(tilt);
    poses.emplace_back(R.so3(), lie::Vec3(6 * std::cos(a), 6 * std::sin(a), 0.15 * k));
  }
  return poses;
}

graph::PoseGraph3D synthetic_3d(const std::vector<lie::SE3>& T, core::Rng& rng) {
  graph::PoseGraph3D g;
  const int n = static_cast<int>(T.size());
  auto add = [&](int i, int j) {
    graph::Edge3 e;
    e.i = i;
    e.j = j;
    e.measurement = T[i].inverse() * T[j];
    e.information = random_information<6>(rng, InformationDraw::spd, 20.0, 1.0);
    g.edges.push_back(e);
  };
  for (int k = 0; k + 1 < n; ++k) add(k, k + 1);
  for (int k = 20; k < n; ++k) add(k - 20, k);
  for (int k = 0; k + 9 < n; k += 4) add(k + 9, k);  // stored backwards: z = T_{k+9}⁻¹ T_k
  g.poses = T;
  g.has_initial_poses = true;
  g.source = "synthetic_3d";
  return g;
}

lie::SE2 perturb(const lie::SE2& T, core::Rng& rng, double st, double sr) {
  const double dx = normal(rng, st), dy = normal(rng, st), dth = normal(rng, sr);
  return lie::SE2(T.translation()(0) + dx, T.translation()(1) + dy, lie::wrap_angle(T.angle() + dth));
}

lie::SE3 perturb(const lie::SE3& T, core::Rng& rng, double st, double sr) {
  lie::Vec6 xi;
  for (int k = 0; k < 3; ++k) xi(k) = normal(rng, st);
  for (int k = 3; k < 6; ++k) xi(k) = normal(rng, sr);
  return lie::SE3::exp(xi) * T;
}

double max_error(const std::vector<lie::SE2>& a, const std::vector<lie::SE2>& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    worst = std::max({worst, (a[k].translation() - b[k].translation()).norm(),
                      std::abs(lie::wrap_angle(a[k].angle() - b[k].angle()))});
  return worst;
}

double max_error(const std::vector<lie::SE3>& a, const std::vector<lie::SE3>& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    worst = std::max(worst, (b[k].inverse() * a[k]).log().cwiseAbs().maxCoeff());
  return worst;
}

Options tight() {
  Options o;
  o.function_tolerance = 1e-16;
  o.gradient_tolerance = 1e-16;
  o.parameter_tolerance = 1e-14;
  o.max_iterations = 200;
  return o;
}

std::vector<lie::Vec2> landmarks_truth() {
  std::vector<lie::Vec2> L;
  for (int l = 0; l < 8; ++l) L.emplace_back(4 * std::cos(0.8 * l), 4 * std::sin(0.8 * l) + 3.0);
  return L;
}

}  // namespace

TEST_CASE("2D noise-free graph with loops and landmarks: ground truth recovered from a perturbed guess") {
  core::Rng rng(1);
  const auto T = circle_truth(60);
  const auto L = landmarks_truth();
  const auto g = synthetic_2d(T, L, rng);
  std::vector<char> seen(L.size(), 0);
  for (const auto& m : g.landmark_measurements) seen[m.landmark] = 1;
  REQUIRE(std::count(seen.begin(), seen.end(), 1) == static_cast<long>(L.size()));
  Estimate2D guess{T, L};
  for (std::size_t k = 1; k < T.size(); ++k) guess.poses[k] = perturb(T[k], rng, 0.3, 0.15);
  for (auto& l : guess.landmarks) l += testkit::random_vector(rng, 2, 0.3);
  Options o = tight();
  o.initial_guess = InitialGuess::supplied;
  const Result2D r = optimize(g, o, &guess);
  INFO(r.summary.report);
  CHECK(r.summary.termination == Termination::converged);
  CHECK(r.summary.initial_cost > 1.0);
  CHECK(r.summary.final_cost < 1e-16);
  CHECK(max_error(r.estimate.poses, T) < 1e-6);
  double lm_err = 0.0;
  for (std::size_t l = 0; l < L.size(); ++l)
    lm_err = std::max(lm_err, (r.estimate.landmarks[l] - L[l]).norm());
  CHECK(lm_err < 1e-6);
  CHECK(r.estimate.poses[0].is_approx(T[0], 0.0));  // the gauge pose did not move
  // Dimensions: 3 per edge + 2 per landmark measurement; 3 per free pose (59) + 2 per landmark.
  CHECK(r.summary.residual_dimension ==
        static_cast<int>(3 * g.edges.size() + 2 * g.landmark_measurements.size()));
  CHECK(r.summary.free_parameter_dimension == 3 * 59 + 2 * 8);
  CHECK(r.edges.size() == g.edges.size());
  CHECK(r.landmark_edges.size() == g.landmark_measurements.size());
  CHECK(r.summary.iterations == r.summary.successful_steps + r.summary.unsuccessful_steps);
  REQUIRE(!r.summary.trace.empty());
  CHECK(r.summary.trace.front().iteration == 0);
  CHECK(r.summary.trace.front().cost == doctest::Approx(r.summary.initial_cost));
  CHECK(r.summary.total_time_s > 0.0);
}

TEST_CASE("3D noise-free graph with loops: ground truth recovered from a perturbed guess") {
  core::Rng rng(2);
  const auto T = helix_truth(60);
  const auto g = synthetic_3d(T, rng);
  Estimate3D guess{T};
  for (std::size_t k = 1; k < T.size(); ++k) guess.poses[k] = perturb(T[k], rng, 0.3, 0.15);
  Options o = tight();
  o.initial_guess = InitialGuess::supplied;
  const Result3D r = optimize(g, o, &guess);
  INFO(r.summary.report);
  CHECK(r.summary.termination == Termination::converged);
  CHECK(r.summary.initial_cost > 1.0);
  CHECK(max_error(r.estimate.poses, T) < 1e-6);
  CHECK(r.summary.free_parameter_dimension == 6 * 59);
  CHECK(r.summary.residual_dimension == static_cast<int>(6 * g.edges.size()));
  // Also with dogleg and a dense solver.
  o.method = Method::dogleg;
  o.linear_solver = LinearSolver::dense_qr;
  const Result3D d = optimize(g, o, &guess);
  CHECK(max_error(d.estimate.poses, T) < 1e-6);
}

TEST_CASE(
    "noisy 2D graph: evaluate() agrees with the solver's cost; normalized χ² ≈ 1 for the right noise model") {
  core::Rng rng(3);
  const auto T = circle_truth(200, 30.0);
  graph::PoseGraph2D g = synthetic_2d(T, {}, rng, 100.0);
  // Replace each measurement z by D E⁻¹ (D = T_i⁻¹ T_j) with E's residual vector e ~ N(0, Ω⁻¹): r(truth) = e.
  for (auto& e : g.edges) {
    const lie::Mat3 U = Eigen::LLT<lie::Mat3>(e.information).matrixU();
    const lie::Vec3 w = testkit::random_vector(rng, 3);
    const lie::Vec3 err = U.inverse() * w;
    e.measurement = (T[e.i].inverse() * T[e.j]) * lie::SE2(err(0), err(1), err(2)).inverse();
  }
  Options o;
  o.initial_guess = InitialGuess::odometry;
  const Result2D r = optimize(g, o);
  CHECK(r.summary.termination == Termination::converged);
  const Evaluation2D ev = evaluate(g, r.estimate, o);
  CHECK(ev.cost == doctest::Approx(r.summary.final_cost).epsilon(1e-9));
  CHECK(ev.chi2 == doctest::Approx(2 * r.summary.final_cost).epsilon(1e-9));
  CHECK(r.summary.final_chi2 == doctest::Approx(ev.chi2).epsilon(1e-12));
  const int dof = ev.residual_dimension - ev.free_parameter_dimension;
  CHECK(dof == static_cast<int>(3 * g.edges.size()) - 3 * 199);
  CHECK(r.summary.normalized_chi2 == doctest::Approx(2 * r.summary.final_cost / dof));
  MESSAGE("synthetic normalized chi2 = " << r.summary.normalized_chi2 << " (dof " << dof << ")");
  CHECK(r.summary.normalized_chi2 > 0.75);
  CHECK(r.summary.normalized_chi2 < 1.25);
  // Per-edge χ² sums to the total; residuals are the raw ones of pose_graph.hpp.
  double sum = 0.0;
  for (const auto& e : ev.edges) sum += e.chi2;
  CHECK(sum == doctest::Approx(ev.chi2));
  const auto& e0 = g.edges[0];
  const lie::SE2 E = e0.measurement.inverse() * r.estimate.poses[e0.i].inverse() * r.estimate.poses[e0.j];
  CHECK(ev.residuals[0](2) == doctest::Approx(E.angle()));
  CHECK(ev.residuals[0].dot(e0.information * ev.residuals[0]) == doctest::Approx(ev.edges[0].chi2));
}

TEST_CASE("a gross outlier loop closure: DCS switches it off, no kernel and Huber are pulled") {
  core::Rng rng(4);
  const auto T = circle_truth(60);
  graph::PoseGraph2D g = synthetic_2d(T, {}, rng, 100.0);
  graph::Edge2 outlier = edge2(T, 5, 33, random_information<3>(rng, InformationDraw::spd, 100.0, 1.0));
  outlier.measurement = outlier.measurement * lie::SE2(4.0, -3.0, 1.2);
  g.edges.push_back(outlier);
  const std::size_t k_out = g.edges.size() - 1;

  Options o;
  o.initial_guess = InitialGuess::odometry;  // the (noise-free) odometry chain
  o.robust_kernel = RobustKernel::none;
  const Result2D plain = optimize(g, o);
  o.robust_kernel = RobustKernel::huber;
  o.robust_parameter = 1.0;
  const Result2D huber = optimize(g, o);
  o.robust_kernel = RobustKernel::dcs;
  o.robust_parameter = 5.0;
  const Result2D dcs = optimize(g, o);

  MESSAGE("max pose error: none " << max_error(plain.estimate.poses, T) << ", huber "
                                  << max_error(huber.estimate.poses, T) << ", dcs "
                                  << max_error(dcs.estimate.poses, T) << "; DCS scale of the outlier "
                                  << dcs.edges[k_out].scale);
  CHECK(max_error(plain.estimate.poses, T) > 0.05);
  CHECK(max_error(huber.estimate.poses, T) > 1e-2);
  CHECK(max_error(dcs.estimate.poses, T) < 1e-3);
  CHECK(dcs.edges[k_out].robust);
  CHECK(dcs.edges[k_out].scale < 0.01);
  CHECK(dcs.edges[k_out].scale == doctest::Approx(dcs_scale(dcs.edges[k_out].chi2, 5.0)));
  CHECK(dcs.edges[k_out].weight == doctest::Approx(dcs.edges[k_out].scale * dcs.edges[k_out].scale));
  for (std::size_t k = 0; k < k_out; ++k) {
    CHECK(dcs.edges[k].scale == 1.0);  // every inlier kept its full weight
    const bool odometry = std::abs(g.edges[k].i - g.edges[k].j) == 1;
    CHECK(dcs.edges[k].robust == !odometry);  // RobustScope::loop_closures
  }
  CHECK_FALSE(plain.edges[k_out].robust);
  CHECK(plain.edges[k_out].weight == 1.0);
  // DCS cost at the solution: the outlier contributes about ½ρ ≤ 3φ/2.
  CHECK(dcs.summary.final_cost < 1.5 * 5.0 + 1e-3);
}

TEST_CASE("two robots with an unknown offset: anchors recover it (2D)") {
  core::Rng rng(5);
  // Local trajectories, each starting at its own origin.
  const auto A = circle_truth(40, 8.0);
  const auto B = circle_truth(40, 6.0, 1.0);
  std::vector<lie::SE2> localA, localB;
  for (const auto& T : A) localA.push_back(A[0].inverse() * T);
  for (const auto& T : B) localB.push_back(B[0].inverse() * T);
  const lie::SE2 delta_b(4.0, -2.0, 0.7);  // robot 1's local frame in the global (= robot 0's) frame
  MultiRobotGraph2D mg;
  mg.robots.push_back(synthetic_2d(localA, {}, rng));
  mg.robots.push_back(synthetic_2d(localB, {}, rng));
  for (int k = 0; k < 6; ++k) {
    InterRobotEdge2 e;
    e.robot_a = 0;
    e.pose_a = 3 + 6 * k;
    e.robot_b = 1;
    e.pose_b = 1 + 5 * k;
    e.measurement = localA[e.pose_a].inverse() * (delta_b * localB[e.pose_b]);
    e.information = random_information<3>(rng, InformationDraw::spd, 50.0, 1.0);
    mg.inter_robot_edges.push_back(e);
  }
  // Perturbed local guesses (pose 0 of each robot is the local gauge), identity anchors.
  for (std::size_t k = 1; k < localA.size(); ++k) mg.robots[0].poses[k] = perturb(localA[k], rng, 0.2, 0.1);
  for (std::size_t k = 1; k < localB.size(); ++k) mg.robots[1].poses[k] = perturb(localB[k], rng, 0.2, 0.1);
  Options o = tight();
  const MultiRobotResult2D r = optimize(mg, o);
  INFO(r.summary.report);
  CHECK(r.summary.termination == Termination::converged);
  REQUIRE(r.estimate.anchors.size() == 2);
  CHECK(r.estimate.anchors[0].is_approx(lie::SE2(), 0.0));
  CHECK(r.estimate.anchors[1].is_approx(delta_b, 1e-6));
  CHECK(max_error(r.estimate.robots[0].poses, localA) < 1e-6);
  CHECK(max_error(r.estimate.robots[1].poses, localB) < 1e-6);
  std::vector<lie::SE2> globalB;
  for (const auto& T : localB) globalB.push_back(delta_b * T);
  CHECK(max_error(global_poses(r.estimate, 1), globalB) < 1e-6);
  CHECK(r.inter_robot_edges.size() == 6);
  CHECK(r.summary.free_parameter_dimension == 3 * 39 * 2 + 3);
  // The anchor guess from the inter-robot edges is exact when the local poses are.
  MultiRobotGraph2D exact = mg;
  exact.robots[0].poses = localA;
  exact.robots[1].poses = localB;
  Options oa;
  oa.anchor_guess = AnchorGuess::inter_robot_edges;
  CHECK(initial_estimate(exact, oa).anchors[1].is_approx(delta_b, 1e-9));
  CHECK(initial_estimate(exact, Options{}).anchors[1].is_approx(lie::SE2(), 0.0));
  CHECK(evaluate(exact, MultiRobotEstimate2D{{lie::SE2(), delta_b}, {{localA, {}}, {localB, {}}}}, oa).cost <
        1e-20);
}

TEST_CASE("two robots with an unknown offset: anchors recover it (3D)") {
  core::Rng rng(6);
  const auto A = helix_truth(40);
  std::vector<lie::SE3> localA, localB;
  for (const auto& T : A) localA.push_back(A[0].inverse() * T);
  for (std::size_t k = 5; k < A.size(); ++k) localB.push_back(A[5].inverse() * A[k]);  // another start
  lie::Vec6 xi;
  xi << 3.0, -1.0, 0.5, 0.2, -0.3, 0.8;
  const lie::SE3 delta_b = lie::SE3::exp(xi);
  MultiRobotGraph3D mg;
  mg.robots.push_back(synthetic_3d(localA, rng));
  mg.robots.push_back(synthetic_3d(localB, rng));
  for (int k = 0; k < 5; ++k) {
    InterRobotEdge3 e;
    e.robot_a = 1;  // stored from robot 1 to robot 0
    e.pose_a = 2 + 6 * k;
    e.robot_b = 0;
    e.pose_b = 4 + 7 * k;
    e.measurement = (delta_b * localB[e.pose_a]).inverse() * localA[e.pose_b];
    e.information = random_information<6>(rng, InformationDraw::spd, 20.0, 1.0);
    mg.inter_robot_edges.push_back(e);
  }
  for (std::size_t k = 1; k < localA.size(); ++k) mg.robots[0].poses[k] = perturb(localA[k], rng, 0.2, 0.1);
  for (std::size_t k = 1; k < localB.size(); ++k) mg.robots[1].poses[k] = perturb(localB[k], rng, 0.2, 0.1);
  const MultiRobotResult3D r = optimize(mg, tight());
  INFO(r.summary.report);
  CHECK(r.summary.termination == Termination::converged);
  CHECK(r.estimate.anchors[1].is_approx(delta_b, 1e-6));
  CHECK(max_error(r.estimate.robots[0].poses, localA) < 1e-6);
  CHECK(max_error(r.estimate.robots[1].poses, localB) < 1e-6);
}

TEST_CASE("random initial guess: deterministic for a seed, different across seeds; gauge pose kept") {
  core::Rng rng(7);
  const auto T = circle_truth(30);
  const auto g = synthetic_2d(T, landmarks_truth(), rng);
  Options o;
  o.initial_guess = InitialGuess::random;
  o.seed = 42;
  o.random_extent = 3.0;
  const Estimate2D a = initial_estimate(g, o), b = initial_estimate(g, o);
  o.seed = 43;
  const Estimate2D c = initial_estimate(g, o);
  bool same = true, differ = false;
  for (std::size_t k = 0; k < T.size(); ++k) {
    same = same && a.poses[k].matrix() == b.poses[k].matrix();
    differ = differ || a.poses[k].matrix() != c.poses[k].matrix();
    if (k > 0) CHECK(std::abs(a.poses[k].translation()(0)) <= 3.0);
  }
  CHECK(same);
  CHECK(differ);
  CHECK(a.poses[0].is_approx(T[0], 0.0));
  o.seed = 42;
  const Result2D r1 = optimize(g, o), r2 = optimize(g, o);
  for (std::size_t k = 0; k < T.size(); ++k)
    CHECK(r1.estimate.poses[k].matrix() == r2.estimate.poses[k].matrix());
  CHECK(r1.summary.final_cost == r2.summary.final_cost);
  CHECK(r1.summary.iterations == r2.summary.iterations);
}

TEST_CASE("Options: validate names the violated constraint; enums round-trip through strings") {
  auto fails_with = [](Options o, const char* what) {
    CHECK_THROWS_WITH_AS(o.validate(), doctest::Contains(what), std::invalid_argument);
  };
  CHECK_NOTHROW(Options{}.validate());
  Options o;
  o.threads = 0;  // keel::core::default_threads()
  CHECK_NOTHROW(o.validate());
  o = {};
  o.max_iterations = -1;
  fails_with(o, "pgo::Options: max_iterations must be >= 0 (got -1)");
  o = {};
  o.function_tolerance = -1;
  fails_with(o, "function_tolerance must be >= 0");
  o = {};
  o.robust_kernel = RobustKernel::dcs;
  o.robust_parameter = 0.0;
  fails_with(o, "robust_parameter must be finite and > 0 for robust_kernel = dcs");
  o = {};
  o.method = Method::dogleg;
  o.linear_solver = LinearSolver::cgnr;
  fails_with(o, "dogleg needs a factorization-based linear_solver (got cgnr)");
  o = {};
  o.constant_poses = {0, -2};
  fails_with(o, "constant_poses must hold pose indices >= 0 (got -2)");
  o = {};
  o.initial_guess = InitialGuess::random;
  o.random_extent = 0.0;
  fails_with(o, "random_extent must be finite and > 0");
  o = {};
  o.max_time_s = 0.0;
  fails_with(o, "max_time_s must be > 0");
}

TEST_CASE("Options enums round-trip through their names; an unknown name is an error naming the valid ones") {
  // Every enumerator back through <enum>_from_string, then a bad name whose error names the type and every
  // name.
  auto round_trip = [](auto parse, const char* type, const char* valid, auto... values) {
    for (auto v : {values...}) CHECK(parse(to_string(v)) == v);
    const std::string expected = fmt::format("unknown {} 'bogus' (valid: {})", type, valid);
    CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)parse("bogus"); }, expected));
  };
  round_trip(method_from_string, "pgo::Method", "levenberg_marquardt, dogleg", Method::levenberg_marquardt,
             Method::dogleg);
  round_trip(linear_solver_from_string, "pgo::LinearSolver",
             "sparse_normal_cholesky, sparse_schur, dense_normal_cholesky, dense_qr, dense_schur, cgnr, "
             "iterative_schur",
             LinearSolver::sparse_normal_cholesky, LinearSolver::sparse_schur,
             LinearSolver::dense_normal_cholesky, LinearSolver::dense_qr, LinearSolver::dense_schur,
             LinearSolver::cgnr, LinearSolver::iterative_schur);
  round_trip(sparse_library_from_string, "pgo::SparseLibrary", "suite_sparse, eigen_sparse, cx_sparse",
             SparseLibrary::suite_sparse, SparseLibrary::eigen_sparse, SparseLibrary::cx_sparse);
  round_trip(initial_guess_from_string, "pgo::InitialGuess", "as_read, odometry, supplied, random",
             InitialGuess::as_read, InitialGuess::odometry, InitialGuess::supplied, InitialGuess::random);
  round_trip(robust_kernel_from_string, "pgo::RobustKernel", "none, huber, cauchy, dcs", RobustKernel::none,
             RobustKernel::huber, RobustKernel::cauchy, RobustKernel::dcs);
  round_trip(robust_scope_from_string, "pgo::RobustScope", "all_edges, loop_closures, inter_robot",
             RobustScope::all_edges, RobustScope::loop_closures, RobustScope::inter_robot);
  round_trip(anchor_guess_from_string, "pgo::AnchorGuess", "as_given, inter_robot_edges",
             AnchorGuess::as_given, AnchorGuess::inter_robot_edges);
  round_trip(termination_from_string, "pgo::Termination", "converged, no_convergence, failure",
             Termination::converged, Termination::no_convergence, Termination::failure);
  // Names match exactly.
  CHECK(testkit::throws_with<std::invalid_argument>([] { (void)method_from_string("Levenberg-Marquardt"); },
                                                    "unknown pgo::Method 'Levenberg-Marquardt'"));
  CHECK(to_string(RobustKernel::dcs) == "dcs");
}

TEST_CASE("the odometry initial guess chains from the first constant pose, which keeps its as-read value") {
  core::Rng rng(9);
  const auto T = circle_truth(30);
  auto g = synthetic_2d(T, {}, rng);  // exact measurements: the optimum is T up to a rigid motion
  for (auto& P : g.poses) P = P * lie::SE2(0.1, -0.2, 0.3);  // as read: off the chain of the measurements
  Options o;
  o.initial_guess = InitialGuess::odometry;
  for (const int k : {0, 5}) {
    CAPTURE(k);
    o.constant_poses = {k};
    const auto r = optimize(g, o);
    // Held, to the rounding of its (x, y, θ) parameters.
    CHECK((r.estimate.poses[k].matrix() - g.poses[k].matrix()).cwiseAbs().maxCoeff() <= 1e-15);
    CHECK(r.summary.initial_cost < 1e-20);  // the chain from pose k fits every measurement
    for (int v = 0; v < 30; v += 7)
      CHECK((r.estimate.poses[k].inverse() * r.estimate.poses[v]).is_approx(T[k].inverse() * T[v], 1e-9));
  }
}

TEST_CASE("input errors come back as exceptions naming the problem") {
  core::Rng rng(8);
  const auto T = circle_truth(10);
  auto g = synthetic_2d(T, {}, rng);
  Options o;
  o.constant_poses = {0, 10};
  CHECK_THROWS_WITH_AS((void)optimize(g, o), doctest::Contains("constant_poses: pose 10 is out of range"),
                       std::invalid_argument);
  o = {};
  o.initial_guess = InitialGuess::supplied;
  CHECK_THROWS_WITH_AS((void)optimize(g, o), doctest::Contains("initial_guess = supplied but no estimate"),
                       std::invalid_argument);
  Estimate2D short_guess{{T[0], T[1]}, {}};
  CHECK_THROWS_WITH_AS((void)optimize(g, o, &short_guess), doctest::Contains("has 2 poses, the graph 10"),
                       std::invalid_argument);
  o = {};
  g.edges[3].information(1, 1) = -5.0;
  g.edges[3].line = 17;
  CHECK_THROWS_WITH_AS((void)optimize(g, o), doctest::Contains("edge 3 (line 17 of 'synthetic_2d')"),
                       std::invalid_argument);
  g = synthetic_2d(T, {}, rng);
  g.poses.clear();
  CHECK_THROWS_WITH_AS((void)optimize(g, o), doctest::Contains("initial_guess = as_read"),
                       std::invalid_argument);
  o.initial_guess = InitialGuess::odometry;
  CHECK(optimize(g, o).summary.termination == Termination::converged);  // pose 0 = identity, chained
  // Without the odometry edge (4, 5) the chain has a gap; the loop closures still connect the graph, so the
  // initial guess follows a spanning tree across the gap and the (noise-free) solve recovers the truth.
  g.edges.erase(g.edges.begin() + 4);
  const Result2D bridged = optimize(g, o);
  CHECK(bridged.summary.termination == Termination::converged);
  CHECK(bridged.summary.final_cost < 1e-12);
  // Two poses that no edge path joins to pose 0: an error naming the first.
  const int n = static_cast<int>(T.size());
  graph::Edge2 island = g.edges[0];
  island.i = n;
  island.j = n + 1;
  g.edges.push_back(island);
  const std::string island_pose = fmt::format("pose {} of", n);
  CHECK_THROWS_WITH_AS((void)optimize(g, o), doctest::Contains(island_pose.c_str()), std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)optimize(g, o), doctest::Contains("is not connected to pose 0"),
                       std::invalid_argument);
}
