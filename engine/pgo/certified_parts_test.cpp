// The parts of the certified solver (certified_internal.hpp) one by one: the problem data's cost against its
// gradient, the retraction, the chordal initialization and the rounding, the certificate at a known optimum,
// the local solve, and the staircase's step — a rank-2 local minimum refused by the certificate, lifted along
// its escape direction to rank 3, where the local solve goes below it. solve_certified as a whole is tested
// in certified_test.cpp.
#include <doctest/doctest.h>

#include <Eigen/Dense>

#include <cmath>
#include <memory>
#include <vector>

#include "kit/test_kit.hpp"
#include "lie/euler.hpp"
#include "pgo/certified_internal.hpp"

namespace keel_certified_parts_test {

using namespace keel;
using namespace keel::pgo::certified;
using pgo::Certificate;
using pgo::CertifiedOptions;

lie::Mat3 isotropic_information(double tau, double kappa) {
  lie::Mat3 I = lie::Mat3::Zero();
  I(0, 0) = I(1, 1) = tau;
  I(2, 2) = kappa;
  return I;
}

// A ring of n poses on a circle of radius 5 (one lap): odometry and the closure back to pose 0, each
// measurement with rotation noise sigma_r and translation noise sigma_t.
graph::PoseGraph2D ring(int n, double sigma_r, double sigma_t, core::Rng& rng) {
  graph::PoseGraph2D g;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * lie::kPi * k / n;
    g.poses.emplace_back(5 * std::cos(a), 5 * std::sin(a), lie::wrap_angle(a + lie::kPi / 2));
  }
  for (int k = 0; k < n; ++k) {
    graph::Edge2 e;
    e.i = k;
    e.j = (k + 1) % n;
    const lie::SE2 z =
        g.poses[static_cast<std::size_t>(e.i)].inverse() * g.poses[static_cast<std::size_t>(e.j)];
    e.measurement =
        lie::SE2(z.translation()(0) + sigma_t * rng.normal(), z.translation()(1) + sigma_t * rng.normal(),
                 lie::wrap_angle(z.angle() + sigma_r * rng.normal()));
    e.information = isotropic_information(100.0, 400.0);
    g.edges.push_back(e);
  }
  g.has_initial_poses = true;
  g.source = "ring";
  return g;
}

// A rank-2 point from planar rotations and translations (pose 0 first; F does not depend on the gauge).
Point point_from(const std::vector<double>& theta, const Eigen::MatrixXd& T) {
  Point X;
  X.r = 2;
  X.T = T;
  for (double t : theta) {
    Small R(2, 2);
    R << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
    X.Q.push_back(R);
  }
  return X;
}

// A random point at rank r: Q_i random orthogonal (the Q factor of a Gaussian matrix), T Gaussian.
Point random_point(int n, int r, core::Rng& rng) {
  Point X;
  X.r = r;
  X.T = testkit::random_matrix(rng, r, n);
  for (int i = 0; i < n; ++i) {
    const Eigen::MatrixXd A = testkit::random_matrix(rng, r, r);
    X.Q.push_back(Small(Eigen::HouseholderQR<Eigen::MatrixXd>(A).householderQ()));
  }
  return X;
}

// ⟨∇F, E⟩ against the central difference of F along E (F is quadratic in X: the difference is exact up to
// rounding), for E on the Y blocks and on the translations.
TEST_CASE("certified parts: the gradient is the derivative of the cost") {
  core::Rng rng(20261205);
  const auto g = ring(15, 0.2, 0.1, rng);
  const Problem P = make_problem(g, 2);
  CHECK(P.n == 15);
  CHECK(P.edges.size() == 15);
  for (int r : {2, 4}) {
    const Point X = random_point(P.n, r, rng);
    const Gradient G = gradient(P, X);
    Point E = X;
    double inner = 0.0;
    for (int i = 0; i < P.n; ++i) {
      const Eigen::MatrixXd dy = testkit::random_matrix(rng, r, 2);
      E.Q[static_cast<std::size_t>(i)].setZero();
      E.Q[static_cast<std::size_t>(i)].leftCols(2) = dy;
      inner += (G.GY[static_cast<std::size_t>(i)].array() * dy.array()).sum();
    }
    E.T = testkit::random_matrix(rng, r, P.n);
    inner += (G.GT.array() * E.T.array()).sum();
    const double h = 1e-3;
    Point plus = X, minus = X;
    for (int i = 0; i < P.n; ++i) {
      plus.Q[static_cast<std::size_t>(i)] += h * E.Q[static_cast<std::size_t>(i)];
      minus.Q[static_cast<std::size_t>(i)] -= h * E.Q[static_cast<std::size_t>(i)];
    }
    plus.T += h * E.T;
    minus.T -= h * E.T;
    const double numeric = (cost(P, plus) - cost(P, minus)) / (2 * h);
    CHECK(std::abs(numeric - inner) <= 1e-7 * std::max(1.0, std::abs(inner)));
  }
}

TEST_CASE("certified parts: the retraction is orthogonal, the identity at 0 and exp to second order") {
  core::Rng rng(7);
  for (int r : {2, 3, 5}) {
    const Point X = random_point(1, r, rng);
    const Small& Q = X.Q[0];
    const Eigen::MatrixXd A = testkit::random_matrix(rng, r, r);
    const Small B = A - A.transpose();
    const Small R = retract(Q, B);
    CHECK((R.transpose() * R - Small::Identity(r, r)).norm() < 1e-12);
    CHECK((retract(Q, Small::Zero(r, r)) - Q).norm() == 0.0);
    // Q exp(tB) − retract(Q, tB) = Q (−(tB)³/12 + O(t⁴)): below ‖tB‖³/12 with room, and a tenth of t
    // divides the difference by a thousand.
    const auto error = [&](double t) {
      const Eigen::MatrixXd tB = t * Eigen::MatrixXd(B);
      Eigen::MatrixXd exp_tB = Eigen::MatrixXd::Identity(r, r), term = exp_tB;
      for (int k = 1; k <= 10; ++k) exp_tB += (term = term * tB / k);  // ‖tB‖ ≤ 0.1: the series to 1e-17
      return (Eigen::MatrixXd(retract(Q, t * B)) - Eigen::MatrixXd(Q) * exp_tB).norm();
    };
    const double t = 1e-2 / B.norm();
    CHECK(error(t) <= 0.1 * std::pow(t * B.norm(), 3));
    CHECK(error(t / 10) / error(t) == doctest::Approx(1e-3).epsilon(0.05));
  }
}

TEST_CASE("certified parts: chordal initialization and rounding recover a noise-free graph") {
  core::Rng rng(11);
  const auto g = ring(24, 0.0, 0.0, rng);
  const Problem P = make_problem(g, 2);
  const Point X = chordal_initialization(P);
  CHECK(X.r == 2);
  CHECK(cost(P, X) < 1e-18);
  for (const Small& R : X.Q) {
    CHECK((R.transpose() * R - Small::Identity(2, 2)).norm() < 1e-12);
    CHECK(R.determinant() > 0);
  }
  // Rounding a point already in SO(2)ⁿ at rank 2 keeps it.
  const Point Y = round_to_rotations(P, X);
  CHECK(cost(P, Y) < 1e-18);
  for (int i = 0; i < P.n; ++i)
    CHECK((Y.Q[static_cast<std::size_t>(i)] - X.Q[static_cast<std::size_t>(i)]).norm() < 1e-12);
  // project_to_rotation of a scaled, slightly sheared rotation is that rotation.
  Small A(2, 2);
  A << 2 * std::cos(0.3), -2 * std::sin(0.3) + 1e-9, 2 * std::sin(0.3), 2 * std::cos(0.3);
  const Small R = project_to_rotation(A);
  CHECK(std::abs(R(1, 0) - std::sin(0.3)) < 1e-9);
  CHECK(std::abs(R(0, 0) - std::cos(0.3)) < 1e-9);
}

TEST_CASE("certified parts: the certificate proves the optimum of a noisy graph, and cost_upper bounds F") {
  core::Rng rng(13);
  const auto g = ring(20, 0.02, 0.02, rng);
  const Problem P = make_problem(g, 2);
  Point X = chordal_initialization(P);
  CertifiedOptions o;
  std::unique_ptr<DataPreconditioner> pre;
  const double start = cost(P, X);
  const LocalOutcome out = local_solve(P, X, o, pre, Deadline{core::Clock::now(), 0.0});
  CHECK(out.cost <= start);
  CHECK(out.cost == doctest::Approx(cost(P, X)).epsilon(1e-12));
  CHECK(cost_upper(P, X) >= cost(P, X));
  const Certificate c = certificate_at(P, X, o.gap_tolerance, nullptr);
  CHECK(c.proven);
  CHECK(c.certified);
  CHECK(c.bound.lower <= cost(P, X));
  CHECK(c.bound.upper >= cost(P, X));
}

// One lap whose rotations wind once more than the truth: 2π/n of rotation error on every edge, a local
// minimum of the rank-2 problem for n = 16. The certificate refuses it with an escape direction; the lift
// along it reaches rank 3 without raising F, and the local solve there ends below the rank-2 minimum.
TEST_CASE("certified parts: a winding local minimum is refused, lifted and left") {
  core::Rng rng(17);
  const int n = 16;
  const auto g = ring(n, 0.0, 0.0, rng);
  const Problem P = make_problem(g, 2);
  std::vector<double> theta;
  // The truth turns by 2π/n per edge (rotations relative to pose 0); one more winding doubles it.
  for (int k = 0; k < n; ++k) theta.push_back(2 * (2 * lie::kPi * k / n));
  Point X = point_from(theta, Eigen::MatrixXd::Zero(2, n));
  optimal_translations(P, X);
  CertifiedOptions o;
  std::unique_ptr<DataPreconditioner> pre;
  const Deadline none{core::Clock::now(), 0.0};
  (void)local_solve(P, X, o, pre, none);
  const double wound = cost(P, X);
  REQUIRE(wound > 1.0);  // still wound: a local minimum, not the optimum 0
  EscapeDirection esc;
  const Certificate c = certificate_at(P, X, o.gap_tolerance, &esc);
  CHECK_FALSE(c.certified);
  REQUIRE(esc.found);
  CHECK(esc.rayleigh < 0.0);
  REQUIRE(lift(P, X, esc));
  CHECK(X.r == 3);
  CHECK(cost(P, X) <= wound);
  pre.reset();
  (void)local_solve(P, X, o, pre, none);
  CHECK(cost(P, X) < 0.99 * wound);
}

}  // namespace keel_certified_parts_test
