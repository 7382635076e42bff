// solve_certified() and certify(): the isotropic weights, recovery of the truth on noise-free graphs, the
// certified cost against a brute-force grid over the rotations and against many local solves from random
// starts, the certificate accepting the optimum and rejecting perturbed points, the rounding margin refusing
// a shift below rounding, the staircase on a hard instance, and input errors.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "kit/test_kit.hpp"
#include "lie/euler.hpp"
#include "pgo/certified.hpp"

using namespace keel;
using namespace keel::pgo;

namespace {

double normal(core::Rng& rng, double sigma) { return sigma * rng.normal(); }

lie::Mat3 info2(double tau, double kappa) {
  lie::Mat3 I = lie::Mat3::Zero();
  I(0, 0) = I(1, 1) = tau;
  I(2, 2) = kappa;
  return I;
}

lie::Mat6 info3(double tau, double kappa) {
  lie::Mat6 I = lie::Mat6::Zero();
  I.topLeftCorner<3, 3>().diagonal().setConstant(tau);
  I.bottomRightCorner<3, 3>().diagonal().setConstant(kappa);
  return I;
}

// A circle of n poses (20 a lap, `radius` m) with odometry, loop closures one lap back and chords;
// measurements with rotation noise sr (rad) and translation noise st (m).
graph::PoseGraph2D circle_graph(int n, double sr, double st, core::Rng& rng, double radius = 8.0) {
  std::vector<lie::SE2> T;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * lie::kPi * k / 20.0;
    T.emplace_back(radius * std::cos(a), radius * std::sin(a), lie::wrap_angle(a + lie::kPi / 2));
  }
  graph::PoseGraph2D g;
  auto add = [&](int i, int j) {
    graph::Edge2 e;
    e.i = i;
    e.j = j;
    const lie::SE2 z = T[i].inverse() * T[j];
    e.measurement = lie::SE2(z.translation()(0) + normal(rng, st), z.translation()(1) + normal(rng, st),
                             lie::wrap_angle(z.angle() + normal(rng, sr)));
    e.information = info2(1.0 / std::max(st * st, 1e-2), 1.0 / std::max(sr * sr, 1e-2));
    g.edges.push_back(e);
  };
  for (int k = 0; k + 1 < n; ++k) add(k, k + 1);
  for (int k = 20; k < n; ++k) add(k - 20, k);
  for (int k = 0; k + 7 < n; k += 5) add(k + 7, k);  // stored backwards
  g.poses = T;
  g.has_initial_poses = true;
  g.source = "circle";
  return g;
}

// One lap of the circle (n poses, odometry and the one closure back to pose 0): the rotation errors around
// the single cycle can wind k times, and every winding with |2πk/n| well below π/2 per edge is a local
// minimum of the rank-2 problem that is not the global one (the lifted problem has no such minima).
graph::PoseGraph2D ring_graph(int n, double sigma, core::Rng& rng) {
  graph::PoseGraph2D g = circle_graph(n, sigma, sigma, rng);
  g.edges.resize(static_cast<std::size_t>(n - 1));  // the odometry
  graph::Edge2 e;
  e.i = n - 1;
  e.j = 0;
  const lie::SE2 z = g.poses[static_cast<std::size_t>(n - 1)].inverse() * g.poses[0];
  e.measurement = lie::SE2(z.translation()(0) + normal(rng, sigma), z.translation()(1) + normal(rng, sigma),
                           lie::wrap_angle(z.angle() + normal(rng, sigma)));
  e.information = info2(1.0 / (sigma * sigma), 1.0 / (sigma * sigma));
  g.edges.push_back(e);
  return g;
}

graph::PoseGraph3D helix_graph(int n, double sr, double st, core::Rng& rng) {
  std::vector<lie::SE3> T;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * lie::kPi * k / 20.0;
    lie::Vec6 xi = lie::Vec6::Zero();
    xi(5) = a;
    xi(3) = 0.3 * std::sin(1.3 * k);
    T.emplace_back(lie::SE3::exp(xi).so3(), lie::Vec3(6 * std::cos(a), 6 * std::sin(a), 0.15 * k));
  }
  graph::PoseGraph3D g;
  auto add = [&](int i, int j) {
    graph::Edge3 e;
    e.i = i;
    e.j = j;
    lie::Vec6 xi;
    for (int c = 0; c < 3; ++c) xi(c) = normal(rng, st);
    for (int c = 3; c < 6; ++c) xi(c) = normal(rng, sr);
    e.measurement = (T[i].inverse() * T[j]) * lie::SE3::exp(xi);
    e.information = info3(1.0 / std::max(st * st, 1e-2), 1.0 / std::max(sr * sr, 1e-2));
    g.edges.push_back(e);
  };
  for (int k = 0; k + 1 < n; ++k) add(k, k + 1);
  for (int k = 20; k < n; ++k) add(k - 20, k);
  for (int k = 0; k + 9 < n; k += 4) add(k + 9, k);
  g.poses = T;
  g.has_initial_poses = true;
  g.source = "helix";
  return g;
}

// The isotropic cost written out per edge (an independent evaluation of F).
double direct_cost(const graph::PoseGraph2D& g, const std::vector<lie::SE2>& x) {
  double f = 0.0;
  for (const auto& e : g.edges) {
    const IsotropicWeights w = isotropic_weights(e);
    const lie::Mat2 Ri = x[e.i].rotation(), Rj = x[e.j].rotation();
    f += w.kappa * (Rj - Ri * e.measurement.rotation()).squaredNorm() +
         w.tau *
             (x[e.j].translation() - x[e.i].translation() - Ri * e.measurement.translation()).squaredNorm();
  }
  return f;
}

// min over translations of F for given angles (pose 0 at the origin): the normal equations of the
// translation least squares.
double cost_over_translations(const graph::PoseGraph2D& g, const std::vector<double>& theta) {
  const int n = static_cast<int>(theta.size());
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(2 * n);
  double c = 0.0;
  std::vector<lie::Mat2> R(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) R[v] = lie::SE2(0, 0, theta[v]).rotation();
  for (const auto& e : g.edges) {
    const IsotropicWeights w = isotropic_weights(e);
    c += w.kappa * (R[e.j] - R[e.i] * e.measurement.rotation()).squaredNorm();
    const lie::Vec2 m = R[e.i] * e.measurement.translation();
    // τ‖t_j − t_i − m‖²
    for (int a = 0; a < 2; ++a) {
      L(2 * e.i + a, 2 * e.i + a) += w.tau;
      L(2 * e.j + a, 2 * e.j + a) += w.tau;
      L(2 * e.i + a, 2 * e.j + a) -= w.tau;
      L(2 * e.j + a, 2 * e.i + a) -= w.tau;
      b(2 * e.j + a) += w.tau * m(a);
      b(2 * e.i + a) -= w.tau * m(a);
    }
    c += w.tau * m.squaredNorm();
  }
  // Pose 0 fixed at the origin: drop its rows.
  const Eigen::MatrixXd Lr = L.bottomRightCorner(2 * n - 2, 2 * n - 2);
  const Eigen::VectorXd br = b.tail(2 * n - 2);
  const Eigen::VectorXd t = Lr.ldlt().solve(br);
  return c - br.dot(t);
}

std::vector<lie::SE2> random_poses_2d(int n, core::Rng& rng) {
  std::vector<lie::SE2> p;
  for (int k = 0; k < n; ++k)
    p.emplace_back(normal(rng, 10.0), normal(rng, 10.0), lie::kPi * (2 * rng.uniform() - 1));
  return p;
}

// The certified solve of g started from random poses instead of the chordal initialization; max_rank = 2
// keeps the local solve and its certificate only (no staircase).
CertifiedResult2D from_random_start(const graph::PoseGraph2D& g, core::Rng& rng, int max_rank) {
  auto start = g;
  start.poses = random_poses_2d(static_cast<int>(g.poses.size()), rng);
  CertifiedOptions o;
  o.chordal_initialization = false;
  o.max_rank = max_rank;
  return solve_certified(start, o);
}

}  // namespace

TEST_CASE("isotropic weights: SE-Sync's reduction of the information") {
  graph::Edge2 e2;
  e2.information = info2(4.0, 9.0);
  e2.information(0, 1) = e2.information(1, 0) = 1.0;  // Σ_tt = inv([[4,1],[1,4]]), tr = 8/15
  const IsotropicWeights w2 = isotropic_weights(e2);
  CHECK(w2.tau == doctest::Approx(2.0 / (8.0 / 15.0)));
  CHECK(w2.kappa == doctest::Approx(9.0));
  graph::Edge3 e3;
  e3.information = info3(5.0, 2.0);  // Ω_φφ = 2 I: Ω_qq = 8 I, tr(Ω_qq⁻¹) = 3/8
  const IsotropicWeights w3 = isotropic_weights(e3);
  CHECK(w3.tau == doctest::Approx(5.0));
  CHECK(w3.kappa == doctest::Approx(3.0 / (2.0 * 3.0 / 8.0)));
  // Indefinite cross terms do not matter: only the diagonal blocks are read.
  e3.information(0, 4) = e3.information(4, 0) = 100.0;
  CHECK(isotropic_weights(e3).kappa == doctest::Approx(w3.kappa));
}

TEST_CASE("solve_certified recovers the truth of noise-free graphs, certified") {
  core::Rng rng(3);
  // F ≈ 0 makes the gap tolerance absolute (relative to max(F, 1)); 1e-4 leaves the shift well above the
  // rounding margin at these weights (κ = τ = 100).
  CertifiedOptions o;
  o.gap_tolerance = 1e-4;
  const auto g2 = circle_graph(50, 0.0, 0.0, rng);
  const auto r2 = solve_certified(g2, o);
  CHECK(r2.summary.termination == CertifiedTermination::certified);
  CHECK(r2.summary.status == core::SearchStatus::optimal);
  CHECK(r2.summary.final_cost < 1e-12);
  for (int k = 0; k < 50; ++k) {
    const lie::SE2 err = (g2.poses[0].inverse() * g2.poses[k]).inverse() * r2.poses[k];
    CHECK(err.log().norm() < 1e-7);
  }
  const auto g3 = helix_graph(45, 0.0, 0.0, rng);
  const auto r3 = solve_certified(g3, o);
  CHECK(r3.summary.termination == CertifiedTermination::certified);
  CHECK(r3.summary.final_cost < 1e-12);
  for (int k = 0; k < 45; ++k) {
    const lie::SE3 err = (g3.poses[0].inverse() * g3.poses[k]).inverse() * r3.poses[k];
    CHECK(err.log().norm() < 1e-7);
  }
}

TEST_CASE("the certified cost against a brute-force grid over the rotations (three poses)") {
  // Three poses joined by conflicting measurements: several local minima over the two free angles.
  graph::PoseGraph2D g;
  auto add = [&](int i, int j, double x, double y, double th, double kappa) {
    graph::Edge2 e;
    e.i = i;
    e.j = j;
    e.measurement = lie::SE2(x, y, th);
    e.information = info2(1.0, kappa);
    g.edges.push_back(e);
  };
  add(0, 1, 1.0, 0.0, 0.3, 2.0);
  add(1, 2, 1.0, 0.5, 2.2, 1.0);
  add(0, 2, 0.2, 1.5, -2.0, 1.5);
  add(0, 1, 0.8, -0.3, 2.8, 0.7);
  add(2, 1, -0.5, 0.9, 1.1, 1.2);
  g.poses.assign(3, lie::SE2());
  const auto r = solve_certified(g);
  REQUIRE(r.summary.termination == CertifiedTermination::certified);
  double grid_min = std::numeric_limits<double>::infinity();
  const int steps = 720;
  for (int a = 0; a < steps; ++a)
    for (int b = 0; b < steps; ++b)
      grid_min = std::min(
          grid_min, cost_over_translations(g, {0.0, 2 * lie::kPi * a / steps, 2 * lie::kPi * b / steps}));
  const auto& bound = r.summary.certificate.bound;
  // The grid's minimum is a feasible cost: never below the proven lower bound, never below the certified cost
  // by more than the gap; and the grid (0.5° steps) gets within 1e-3 of the certified cost.
  CHECK(grid_min >= bound.lower);
  CHECK(r.summary.final_cost <= grid_min * (1.0 + 1e-9));
  CHECK(grid_min <= r.summary.final_cost * (1.0 + 1e-3));
  CHECK(isotropic_cost(g, r.poses) == doctest::Approx(direct_cost(g, r.poses)).epsilon(1e-12));
  CHECK(r.summary.final_cost == doctest::Approx(direct_cost(g, r.poses)).epsilon(1e-12));
}

TEST_CASE("no local solve from random starts ends below the certified cost") {
  core::Rng rng(11);
  const auto g = ring_graph(20, 0.1, rng);
  const auto r = solve_certified(g);
  REQUIRE(r.summary.termination == CertifiedTermination::certified);
  int above = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const auto local = from_random_start(g, rng, 2);  // the local solve and its certificate only
    CHECK(local.summary.final_cost >= r.summary.certificate.bound.lower);
    if (local.summary.final_cost > r.summary.final_cost * (1.0 + 1e-6)) {
      ++above;
      // A local minimum above the certified cost can never carry a certificate.
      CHECK(local.summary.termination != CertifiedTermination::certified);
    }
  }
  INFO("local minima above the certified cost: " << above);
  CHECK(above > 0);  // the random starts do find worse local minima (otherwise the test shows nothing)
}

TEST_CASE("certify accepts the optimum and rejects perturbed poses") {
  core::Rng rng(5);
  const auto g = circle_graph(60, 0.05, 0.1, rng);
  const auto r = solve_certified(g);
  REQUIRE(r.summary.termination == CertifiedTermination::certified);
  const Certificate at_opt = certify(g, r.poses);
  CHECK(at_opt.certified);
  CHECK(at_opt.bound.lower <= r.summary.final_cost);
  CHECK(at_opt.bound.relative_gap() <= 1e-6);
  // Moved as a whole (gauge): still certified.
  auto moved = r.poses;
  const lie::SE2 M(3.0, -2.0, 0.7);
  for (auto& p : moved) p = M * p;
  CHECK(certify(g, moved).certified);
  // One pose moved by 1 cm / 0.01 rad: the cost rises by less than 1e-3 relative, and the certificate
  // refuses.
  auto perturbed = r.poses;
  perturbed[17] = lie::SE2(perturbed[17].translation()(0) + 0.01, perturbed[17].translation()(1),
                           perturbed[17].angle() + 0.01);
  const double f = isotropic_cost(g, perturbed);
  CHECK(f > r.summary.final_cost);
  CHECK(f < r.summary.final_cost * (1.0 + 1e-1));
  CHECK_FALSE(certify(g, perturbed).certified);
}

TEST_CASE("the rounding margin: a shift below rounding never certifies") {
  core::Rng rng(7);
  const auto g = circle_graph(40, 0.05, 0.1, rng);
  const auto r = solve_certified(g);
  REQUIRE(r.summary.termination == CertifiedTermination::certified);
  // A gap tolerance of 1e-15 leaves a shift η* of order 1e-15·F/(dn): at or below the factorization's
  // backward error (and F − tr Λ is itself of that order). The unmargined Cholesky could succeed here; the
  // margined test must not.
  const Certificate c = certify(g, r.poses, 1e-15);
  CHECK_FALSE(c.certified);
  // The margin is reported and positive whenever the factorization was attempted.
  const Certificate ok = certify(g, r.poses, 1e-6);
  CHECK(ok.rounding_margin > 0.0);
  CHECK(ok.max_row_count >= 3);
}

TEST_CASE("positions far from the gauge: certified through the double-double factor") {
  // A 2 km circle measured to centimetres: the near-null vectors of S carry the positions (D is zero on
  // them), and the scaled shift that a 1e-6 gap asks for lies below what a double factor resolves.
  core::Rng rng(3);
  const auto g = circle_graph(60, 0.01, 0.01, rng, 2000.0);
  const auto r = solve_certified(g);
  CHECK(r.summary.termination == CertifiedTermination::certified);
  CHECK(r.summary.certificate.extended_precision);
  CHECK(r.summary.certificate.residual < 1e-20);
  // The same graph at 8 m needs no extended precision.
  core::Rng rng2(3);
  const auto small = solve_certified(circle_graph(60, 0.01, 0.01, rng2));
  CHECK(small.summary.termination == CertifiedTermination::certified);
  CHECK_FALSE(small.summary.certificate.extended_precision);
}

TEST_CASE("the staircase: a hard start is lifted and ends certified") {
  // A ring and random starts: the rank-2 solve stops at a local minimum (a winding of the rotation errors)
  // that the certificate rejects, the staircase climbs, and the rounded answer is certified at the chordal
  // solve's cost.
  core::Rng rng(21);
  const auto g = ring_graph(20, 0.1, rng);
  const auto chordal = solve_certified(g);
  REQUIRE(chordal.summary.termination == CertifiedTermination::certified);
  int lifted = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const auto r = from_random_start(g, rng, CertifiedOptions{}.max_rank);
    CHECK(r.summary.termination == CertifiedTermination::certified);
    CHECK(r.summary.final_cost == doctest::Approx(chordal.summary.final_cost).epsilon(1e-6));
    if (r.summary.staircase.size() > 1) {
      ++lifted;
      CHECK_FALSE(r.summary.staircase.front().certified);
      CHECK(r.summary.staircase.front().lambda_min_estimate < 0.0);
      CHECK(r.summary.final_rank > 2);
    }
  }
  CHECK(lifted > 0);
}

TEST_CASE("3D: certified, and no random-start local solve ends below") {
  core::Rng rng(9);
  const auto g = helix_graph(40, 0.1, 0.1, rng);
  const auto r = solve_certified(g);
  REQUIRE(r.summary.termination == CertifiedTermination::certified);
  CHECK(certify(g, r.poses).certified);
  for (int trial = 0; trial < 4; ++trial) {
    auto start = g;
    for (auto& p : start.poses) p = testkit::random_pose<lie::SE3>(rng, 2.0, 10.0);
    CertifiedOptions o;
    o.chordal_initialization = false;
    o.max_rank = 3;
    const auto local = solve_certified(start, o);
    CHECK(local.summary.final_cost >= r.summary.certificate.bound.lower);
  }
}

TEST_CASE("inexact Newton steps (CG on an earlier factor) reach the same certified optimum") {
  // The same solve with a factorization at every step and with CG steps preconditioned by an earlier factor:
  // both certified, the same cost to well inside the gap tolerance, and the inexact one factorizes less.
  core::Rng rng(21);
  const auto g3 = helix_graph(60, 0.05, 0.05, rng);
  const auto g2 = circle_graph(80, 0.05, 0.05, rng);
  CertifiedOptions exact;
  exact.inexact_newton = false;
  const auto check = [&](const CertifiedSummary& a, const CertifiedSummary& b) {
    INFO("exact: " << a.iterations << " steps, " << a.factorizations
                   << " factorizations; inexact: " << b.iterations << " steps, " << b.factorizations
                   << " factorizations, " << b.cg_steps << " by CG");
    CHECK(a.termination == CertifiedTermination::certified);
    CHECK(b.termination == CertifiedTermination::certified);
    CHECK(std::abs(a.final_cost - b.final_cost) <= 1e-9 * a.final_cost);
    CHECK(a.cg_steps == 0);
    CHECK(a.factorizations == a.iterations);
    CHECK(b.cg_steps > 0);
    CHECK(b.factorizations < a.factorizations);
  };
  check(solve_certified(g3, exact).summary, solve_certified(g3).summary);
  check(solve_certified(g2, exact).summary, solve_certified(g2).summary);
}

TEST_CASE("solve_certified: bad input gives a clear error") {
  core::Rng rng(1);
  auto g = circle_graph(10, 0.0, 0.0, rng);
  CertifiedOptions o;
  o.max_rank = 13;
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)solve_certified(g, o); }, "max_rank"));
  o = {};
  o.gap_tolerance = 0.0;
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)solve_certified(g, o); }, "gap_tolerance"));
  o = {};
  o.max_rank = 1;
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)solve_certified(g, o); }, "max_rank"));
  auto disconnected = g;  // poses 10 and 11 joined to each other only
  disconnected.poses.resize(12);
  graph::Edge2 apart;
  apart.i = 10;
  apart.j = 11;
  disconnected.edges.push_back(apart);
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)solve_certified(disconnected); },
                                                    "not connected"));
  auto zero = g;
  zero.edges[2].information(2, 2) = 0.0;
  zero.edges[2].line = 7;
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)solve_certified(zero); }, "line 7"));
  auto nan = g;
  nan.edges[1].information(0, 0) = std::numeric_limits<double>::quiet_NaN();
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)solve_certified(nan); },
                                                    "not positive and finite"));
  auto with_landmark = g;
  with_landmark.landmark_measurements.emplace_back();
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)solve_certified(with_landmark); },
                                                    "landmarks"));
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)certify(g, std::vector<lie::SE2>(3)); },
                                                    "3 poses"));
}

TEST_CASE("the Newton model is exact: quadratic convergence from a perturbed start") {
  // With the exact Riemannian Hessian (Gauss–Newton matrix plus the retraction's curvature), the local solve
  // from poses 0.05 away from a noise-free optimum reaches F ≈ 0 in a handful of steps; a wrong curvature
  // term (or Jacobian) stalls it at first order.
  core::Rng rng(13);
  for (int dim = 2; dim <= 3; ++dim) {
    CertifiedOptions o;
    o.chordal_initialization = false;
    o.max_rank = dim;
    o.gap_tolerance = 1e-4;
    CertifiedSummary s;
    if (dim == 2) {
      auto g = circle_graph(40, 0.0, 0.0, rng);
      for (auto& p : g.poses) p = p * lie::SE2(normal(rng, 0.05), normal(rng, 0.05), normal(rng, 0.05));
      s = solve_certified(g, o).summary;
    } else {
      auto g = helix_graph(40, 0.0, 0.0, rng);
      for (auto& p : g.poses) p = p * testkit::random_pose<lie::SE3>(rng, 0.05, 0.05);
      s = solve_certified(g, o).summary;
    }
    INFO("dimension " << dim << ": " << s.staircase.front().iterations << " iterations, F " << s.final_cost);
    CHECK(s.initial_cost > 1.0);
    CHECK(s.final_cost < 1e-12);
    CHECK(s.staircase.front().iterations <= 15);
    CHECK(s.termination == CertifiedTermination::certified);
  }
}

namespace {

// The counterexample to the exactness of the order-1 relaxation (sos::exactness_counterexample, Theorems
// 4.5.3–4.5.4): K4, rotation-only measurements, unit weights. The rank-2 estimate cannot be certified; the
// staircase's higher-rank point proves the relaxation's value, a valid bound below the minimum.
graph::PoseGraph2D exactness_counterexample() {
  const double theta[6] = {0.23, 0.43, 1.13, -1.81, 1.36, -1.35};
  const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  graph::PoseGraph2D g;
  g.poses.assign(4, lie::SE2::identity());
  for (int k = 0; k < 6; ++k) {
    graph::Edge2 e;
    e.i = pairs[k][0], e.j = pairs[k][1];
    e.measurement = lie::SE2(0, 0, theta[k]);
    e.information = lie::Mat3(Eigen::Vector3d(1, 1, 2).asDiagonal());
    g.edges.push_back(e);
  }
  return g;
}

// min F over SO(2)⁴ (translations 0 at the optimum), θ_0 = 0: a 90³ grid polished by gradient steps (an
// upper estimate of the minimum, within 1e-6 of it).
double counterexample_minimum() {
  const double theta[6] = {0.23, 0.43, 1.13, -1.81, 1.36, -1.35};
  const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  auto f = [&](const double* th) {  // κ = 2: ‖R(a) − R(b)‖²_F = 4(1 − cos(a − b))
    double s = 0.0;
    for (int k = 0; k < 6; ++k) s += 8.0 * (1.0 - std::cos(th[pairs[k][1]] - th[pairs[k][0]] - theta[k]));
    return s;
  };
  double best[4] = {0, 0, 0, 0}, fbest = std::numeric_limits<double>::infinity();
  const double kPi = std::acos(-1.0);
  for (int a = 0; a < 90; ++a)
    for (int b = 0; b < 90; ++b)
      for (int c = 0; c < 90; ++c) {
        const double th[4] = {0.0, -kPi + 2 * kPi * a / 90, -kPi + 2 * kPi * b / 90, -kPi + 2 * kPi * c / 90};
        if (const double v = f(th); v < fbest) fbest = v, std::copy(th, th + 4, best);
      }
  for (int it = 0; it < 2000; ++it) {
    double g[4] = {0, 0, 0, 0};
    for (int k = 0; k < 6; ++k) {
      const double s = 8.0 * std::sin(best[pairs[k][1]] - best[pairs[k][0]] - theta[k]);
      g[pairs[k][1]] += s, g[pairs[k][0]] -= s;
    }
    for (int v = 1; v < 4; ++v) best[v] -= 0.01 * g[v];
  }
  return std::min(fbest, f(best));
}

}  // namespace

TEST_CASE("a failed certificate reports no figure of a proof, only what failed") {
  CertifiedOptions o;
  o.max_rank = 2;  // no staircase: the rank-2 test is the only one
  const auto r = solve_certified(exactness_counterexample(), o);
  const Certificate& c = r.summary.certificate;
  CHECK_FALSE(c.certified);
  CHECK_FALSE(c.proven);
  CHECK(std::isinf(c.bound.lower));
  CHECK(c.bound.lower < 0.0);
  // The failed attempts' margin, residual and shift are not reported as the certificate's.
  CHECK(c.shift == 0.0);
  CHECK(c.rounding_margin == 0.0);
  CHECK(c.residual == 0.0);
  CHECK(c.worst_case_residual == 0.0);
  CHECK(c.formation_error == 0.0);
  CHECK_FALSE(c.extended_precision);
  // What failed is reported as failed: λ_min(S) ≈ −0.7, far below every shift tried.
  CHECK(c.failed_shift > 0.1);
  CHECK(c.attempts >= 5);
  CHECK(c.message.rfind("no lower bound: ", 0) == 0);
  CHECK(c.message.find("proven") == std::string::npos);
  CHECK(r.summary.message.find("proven") == std::string::npos);
  CHECK_FALSE(r.summary.bound_from_staircase);
}

TEST_CASE("the staircase's proof is reported with its own fields; the returned point's failure apart") {
  const auto r = solve_certified(exactness_counterexample());
  const CertifiedSummary& s = r.summary;
  const Certificate& c = s.certificate;
  CHECK(s.termination == CertifiedTermination::not_certified);
  CHECK_FALSE(c.certified);
  REQUIRE(c.proven);
  CHECK(c.rank > 2);
  CHECK(s.bound_from_staircase);
  // The bound is the relaxation's value: proven, below the minimum, rounded down past tr Λ − η·d·n.
  const double minimum = counterexample_minimum();
  CHECK(c.bound.lower < minimum - 1.0);
  CHECK(c.bound.lower < c.trace_lambda - c.shift * 2.0 * 4.0);
  CHECK(c.rounding_margin > 0.0);
  CHECK(c.residual > 0.0);
  CHECK(c.residual <= c.rounding_margin);
  CHECK(c.message.find("proven") != std::string::npos);
  // The returned estimate (the minimum, to the solver's accuracy) fails its own test, reported as failed.
  CHECK(s.final_cost == doctest::Approx(minimum).epsilon(1e-6));
  CHECK_FALSE(s.returned_point.proven);
  CHECK(std::isinf(s.returned_point.bound.lower));
  CHECK(s.returned_point.rounding_margin == 0.0);
  CHECK(s.returned_point.failed_shift > 0.1);
  CHECK(s.returned_point.message.find("proven") == std::string::npos);
  // The upper end is F at the returned estimate rounded up, the gap measured from both ends, rounded up.
  CHECK(c.bound.upper >= s.final_cost * (1.0 - 1e-13));  // exact comparisons: residual_bound_test.cpp
  CHECK(c.bound.upper <= s.final_cost * (1.0 + 1e-12));
  CHECK(c.bound.relative_gap_up() >= (c.bound.upper - c.bound.lower) / c.bound.upper);
}

namespace {

// A circle with large rotation noise on every measurement (σ_R = 1.5 rad): far from the regime where the
// relaxation is exact, so the staircase climbs and its higher-rank points have rank-deficient Y (a singular,
// nearby indefinite Hessian). Where the Hessian was indefinite the local solve used to take Gauss–Newton
// steps, which crawled there (every rank at the 300-iteration cap on a 500-pose Manhattan subset with 2 rad
// on its loop closures); both local solvers now take trust-region steps on the exact Hessian instead.
graph::PoseGraph2D noisy_circle(int n, core::Rng& rng) { return circle_graph(n, 1.5, 0.1, rng); }
graph::PoseGraph3D noisy_helix(int n, core::Rng& rng) { return helix_graph(n, 1.5, 0.1, rng); }

template <class Graph>
void check_hard_instance(const Graph& g, int d) {
  // Every rank to the full tolerance (the local solvers' convergence is what is compared here).
  CertifiedOptions full;
  full.staircase_stationarity = 0.0;
  CertifiedOptions newton = full;
  newton.trust_region_above_d = false;
  const auto tr = solve_certified(g, full).summary;
  const auto nw = solve_certified(g, newton).summary;
  INFO("trust region: final rank " << tr.final_rank << ", " << tr.iterations << " iterations, "
                                   << tr.tcg_iterations << " tCG; Newton: final rank " << nw.final_rank
                                   << ", " << nw.iterations << " iterations");
  REQUIRE(tr.staircase.size() > 1);
  for (const auto& rec : tr.staircase) {
    INFO("rank " << rec.rank << ": " << rec.iterations << " iterations, ‖grad‖ " << rec.gradient_norm);
    // Each rank's local solve ends at a stationary point before the iteration cap.
    CHECK(rec.iterations < CertifiedOptions{}.max_iterations);
    CHECK(rec.gradient_norm <= 1e-6 * std::max(rec.cost, 1.0));
    if (rec.rank > d) {
      CHECK(rec.factorizations == 0);  // matrix-free: no Newton system is formed
      CHECK(rec.tcg_iterations > 0);
    }
  }
  // Both local solvers end the staircase at a point that is optimal for the relaxation, whose value is
  // unique: their proven lower bounds agree to well inside the gap tolerance and lie below both costs.
  REQUIRE(tr.staircase.back().certified);
  REQUIRE(nw.staircase.back().certified);
  REQUIRE(tr.certificate.proven);
  REQUIRE(nw.certificate.proven);
  CHECK(std::abs(tr.certificate.bound.lower - nw.certificate.bound.lower) <=
        2e-6 * std::max(1.0, std::abs(nw.certificate.bound.lower)));
  CHECK(tr.certificate.bound.lower <= tr.final_cost);
  CHECK(tr.certificate.bound.lower <= nw.final_cost);
  CHECK(nw.certificate.bound.lower <= tr.final_cost);
}

}  // namespace

TEST_CASE(
    "above rank d the trust region converges where the relaxation is not exact; the same relaxation value") {
  core::Rng rng(41);
  SUBCASE("2D") { check_hard_instance(noisy_circle(24, rng), 2); }
  SUBCASE("3D") { check_hard_instance(noisy_helix(24, rng), 3); }
}

TEST_CASE("the trust region's two preconditioners reach the same relaxation value; auto follows the rule") {
  // The preconditioner changes the local solves' path, never what they converge to: with every rank solved
  // to the full tolerance, both end at the relaxation's optimum (its value, the bound) on an instance whose
  // relaxation is not exact. Auto takes whichever form its rule names, with the same steps as asking for it.
  core::Rng rng(41);
  const auto g = noisy_circle(24, rng);
  CertifiedOptions joint, reduced, automatic;
  joint.staircase_stationarity = reduced.staircase_stationarity = automatic.staircase_stationarity = 0.0;
  joint.preconditioner = TrustRegionPreconditioner::joint;
  reduced.preconditioner = TrustRegionPreconditioner::reduced;
  const auto a = solve_certified(g, joint).summary;
  const auto b = solve_certified(g, reduced).summary;
  const auto c = solve_certified(g, automatic).summary;
  INFO("joint: " << a.tcg_iterations << " tCG, bound " << a.certificate.bound.lower
                 << "; reduced: " << b.tcg_iterations << " tCG, bound " << b.certificate.bound.lower);
  REQUIRE(a.staircase.back().certified);
  REQUIRE(b.staircase.back().certified);
  REQUIRE(a.staircase.size() > 1);
  CHECK(b.staircase.back().cost == doctest::Approx(a.staircase.back().cost).epsilon(1e-7));
  CHECK(b.certificate.bound.lower == doctest::Approx(a.certificate.bound.lower).epsilon(1e-6));
  CHECK(b.certificate.bound.lower <= a.final_cost);
  CHECK(a.certificate.bound.lower <= b.final_cost);
  CHECK(b.tcg_iterations != a.tcg_iterations);  // the two forms did differ along the way
  // Σ τ‖t̃‖² against F at the start of each rank's solve, which lies between the relaxation's value and the
  // rank-d cost: beyond both bounds the rule picks one form at every rank.
  double energy = 0.0;
  for (const auto& e : g.edges)
    energy += isotropic_weights(e).tau * e.measurement.translation().squaredNorm();
  INFO("Σ τ‖t̃‖² = " << energy << ", F from " << a.staircase.front().cost << " to "
                    << a.staircase.back().cost);
  REQUIRE((energy >= a.staircase.front().cost || energy < a.staircase.back().cost));
  CHECK(c.tcg_iterations == (energy >= a.staircase.front().cost ? b.tcg_iterations : a.tcg_iterations));
}

TEST_CASE("trust_region_preconditioner names: every value round-trips, a bad name lists the valid ones") {
  for (const auto p : {TrustRegionPreconditioner::automatic, TrustRegionPreconditioner::joint,
                       TrustRegionPreconditioner::reduced})
    CHECK(trust_region_preconditioner_from_string(to_string(p)) == p);
  CHECK_THROWS_WITH_AS((void)trust_region_preconditioner_from_string("schur"),
                       doctest::Contains("(valid: auto, joint, reduced)"), std::invalid_argument);
}

TEST_CASE("the matrix-free trust region and damped Newton reach the same K4 relaxation value") {
  CertifiedOptions full;
  full.staircase_stationarity = 0.0;
  CertifiedOptions newton = full;
  newton.trust_region_above_d = false;
  const auto tr = solve_certified(exactness_counterexample(), full).summary;
  const auto nw = solve_certified(exactness_counterexample(), newton).summary;
  REQUIRE(tr.certificate.proven);
  REQUIRE(nw.certificate.proven);
  CHECK(tr.certificate.rank > 2);
  CHECK(tr.certificate.bound.lower == doctest::Approx(nw.certificate.bound.lower).epsilon(1e-7));
  CHECK(tr.final_cost == doctest::Approx(nw.final_cost).epsilon(1e-9));
  CHECK(tr.tcg_iterations > 0);
}

namespace {

// The staged staircase (CertifiedOptions::staircase_stationarity, the default) against every rank solved to
// the full tolerance, on an instance whose relaxation is not exact: the full staircase ends at the
// relaxation's optimum, whose F bounds every provable lower bound from above, and its rounded answer is not
// certified.
template <class Graph>
void check_staged_staircase(const Graph& g, int d) {
  CertifiedOptions full;
  full.staircase_stationarity = 0.0;
  const auto f = solve_certified(g, full).summary;
  const auto s = solve_certified(g).summary;
  INFO("full: rank " << f.final_rank << ", " << f.tcg_iterations << " tCG, F " << f.final_cost << ", bound "
                     << f.certificate.bound.lower << "; staged: rank " << s.final_rank << ", "
                     << s.tcg_iterations << " tCG, F " << s.final_cost << ", bound "
                     << s.certificate.bound.lower << "; " << s.message);
  REQUIRE(f.staircase.back().certified);  // the full staircase reached the relaxation's optimum ...
  REQUIRE(!f.certificate.certified);      // ... and its answer is not certified: not exact
  const double relaxation = f.staircase.back().cost;
  // Nothing is certified that the relaxation cannot certify, and the staged bound is a bound.
  CHECK(!s.certificate.certified);
  CHECK(s.termination == CertifiedTermination::not_certified);
  REQUIRE(s.certificate.proven);
  CHECK(s.certificate.bound.lower <= relaxation);
  CHECK(s.certificate.bound.lower <= s.final_cost);
  CHECK(s.certificate.bound.lower <= f.final_cost);
  // It stopped at a loose point above rank d, said why, and spent less of the trust region's inner work. Two
  // stops are possible there, and which one comes depends on rounding (OpenBLAS's kernels differ between
  // CPUs; on the 2D instance an Intel Xeon took the first and an AMD EPYC the second): the rank-d answer
  // rounded from a loose point costs too much for any bound to certify it, or the loose point is itself the
  // relaxation's optimum (its certificate holds) and the answer rounded from it is not certified.
  REQUIRE(s.staircase.size() > 1);
  CHECK(s.staircase.front().rank == d);
  CHECK(!s.staircase.front().loose);  // rank d is always solved to the full tolerance
  CHECK(s.staircase.back().loose);
  const bool uncertifiable = s.message.find("the staircase stopped at rank") != std::string::npos;
  const bool at_relaxation = s.staircase.back().certified &&
                             s.message.find("the returned point's own test failed") != std::string::npos;
  CHECK((uncertifiable || at_relaxation));
  CHECK(s.tcg_iterations < f.tcg_iterations);
  // Its bound trades tightness for time, by no more than the loose stationarity allows for (relative to F).
  CHECK(s.certificate.bound.lower >= f.certificate.bound.lower - 1e-2 * std::max(1.0, relaxation));
}

}  // namespace

TEST_CASE("the staged staircase stops where no bound can certify the answer, and never certifies more") {
  core::Rng rng(41);
  SUBCASE("2D") { check_staged_staircase(noisy_circle(40, rng), 2); }
  SUBCASE("3D") { check_staged_staircase(noisy_helix(24, rng), 3); }
}

TEST_CASE("staircase_stationarity outside [0, 1) is refused") {
  for (const double bad : {-1e-3, 1.0, std::numeric_limits<double>::quiet_NaN()}) {
    CertifiedOptions o;
    o.staircase_stationarity = bad;
    CHECK_THROWS_WITH_AS(o.validate(), doctest::Contains("staircase_stationarity"), std::invalid_argument);
    o = CertifiedOptions{};
    o.staircase_relative_decrease = bad;
    CHECK_THROWS_WITH_AS(o.validate(), doctest::Contains("staircase_relative_decrease must be in [0, 1)"),
                         std::invalid_argument);
  }
}

namespace {

// The relative-decrease stop of the loose solves (CertifiedOptions::staircase_relative_decrease, off by
// default) against the staged staircase without it. Up to the step where it fires, the first loose rank's
// trust region takes the same steps from the same point (the rank-d solve before it is untouched), so it
// cannot take more iterations there; a rule that fires at once (0.5: any accepted step that does not halve F)
// ends that rank after its first accepted step. Either way every bound stays a bound: below the relaxation's
// value and both answers' costs, and nothing is certified that the relaxation cannot certify.
template <class Graph>
void check_relative_decrease(const Graph& g, int d) {
  CertifiedOptions full, off, rule, eager;  // off: the default
  full.staircase_stationarity = 0.0;
  rule.staircase_relative_decrease = 1e-7;
  eager.staircase_relative_decrease = 0.5;
  const auto f = solve_certified(g, full).summary;
  const auto o = solve_certified(g, off).summary;
  REQUIRE(f.staircase.back().certified);  // the relaxation's optimum: its F bounds every lower bound
  const double relaxation = f.staircase.back().cost;
  int eager_iterations = 0;
  for (const CertifiedOptions& with : {rule, eager}) {
    const auto s = solve_certified(g, with).summary;
    INFO("relative decrease " << with.staircase_relative_decrease << ": rank " << s.final_rank << ", "
                              << s.tcg_iterations << " tCG, F " << s.final_cost << ", bound "
                              << s.certificate.bound.lower << "; without: rank " << o.final_rank << ", "
                              << o.tcg_iterations << " tCG, F " << o.final_cost << ", bound "
                              << o.certificate.bound.lower);
    REQUIRE(s.staircase.size() > 1);
    REQUIRE(o.staircase.size() > 1);
    const RankRecord& first = s.staircase[1];
    CHECK(first.rank == d + 1);
    CHECK(first.loose);
    CHECK(s.staircase[0].cost == o.staircase[0].cost);  // rank d is solved alike
    CHECK(first.iterations <= o.staircase[1].iterations);
    CHECK(first.tcg_iterations <= o.staircase[1].tcg_iterations);
    CHECK(!s.certificate.certified);
    // A bound when one was proven (a point that far from stationary may prove none: lower = −∞).
    CHECK(s.certificate.bound.lower <= relaxation);
    CHECK(s.certificate.bound.lower <= s.final_cost);
    CHECK(s.certificate.bound.lower <= o.final_cost);
    CHECK(o.certificate.bound.lower <= s.final_cost);
    CHECK(s.certificate.proven == std::isfinite(s.certificate.bound.lower));
    eager_iterations = first.iterations;  // the last pass is the eager one
  }
  CHECK(eager_iterations < o.staircase[1].iterations);
}

}  // namespace

TEST_CASE("the loose solves' relative-decrease stop takes no more steps and never certifies more") {
  core::Rng rng(41);
  SUBCASE("2D") { check_relative_decrease(noisy_circle(40, rng), 2); }
  SUBCASE("3D") { check_relative_decrease(noisy_helix(24, rng), 3); }
}

TEST_CASE("time_limit_s: the solve stops, says so, and reports only what was proven") {
  core::Rng rng(43);
  const auto g = noisy_circle(40, rng);
  CertifiedOptions o;
  o.time_limit_s = 1e-9;  // passed before the first iteration: the chordal estimate is tested as it is
  const auto r = solve_certified(g, o);
  const auto& s = r.summary;
  CHECK(s.termination == CertifiedTermination::time_limit);
  CHECK(s.status == core::SearchStatus::unproven);
  CHECK_FALSE(s.certificate.certified);
  CHECK(s.iterations == 0);
  CHECK(s.staircase.size() == 1);
  CHECK(s.message.find("time limit") != std::string::npos);
  if (s.certificate.proven)
    CHECK(s.certificate.bound.lower <= s.final_cost);
  else
    CHECK(std::isinf(s.certificate.bound.lower));
  // Without a limit the same graph gets further (a lower cost), and a limit it does not reach changes
  // nothing.
  const auto full = solve_certified(g).summary;
  CHECK(full.termination != CertifiedTermination::time_limit);
  CHECK(full.final_cost <= s.final_cost);
  CertifiedOptions generous;
  generous.time_limit_s = 3600.0;
  const auto same = solve_certified(g, generous).summary;
  CHECK(same.final_cost == full.final_cost);
  CHECK(same.termination == full.termination);
  for (const double bad : {-1.0, std::numeric_limits<double>::infinity(), std::nan("")}) {
    CertifiedOptions b;
    b.time_limit_s = bad;
    CHECK_THROWS_WITH_AS(b.validate(), doctest::Contains("time_limit_s"), std::invalid_argument);
  }
}
