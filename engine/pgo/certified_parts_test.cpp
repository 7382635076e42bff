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

namespace {

// DataPreconditioner's two forms against dense linear algebra at a random point of rank r: the ambient
// operator Â = 2M₀ ⊗ I_r (M₀ assembled from the edges' entries as the certificate does), the tangent basis
// E (each coordinate's ambient vector), G = EᵀE, and then
//   joint:   G⁻¹ Eᵀ Â⁻¹ E G⁻¹ c;
//   reduced: u = E G⁻¹ c, z_y = Π S⁻¹ Π (u_y − Â_yt Â_tt⁻¹ u_t), z_t = Â_tt⁻¹ (u_t − Â_ty z_y), G⁻¹ Eᵀ z,
// with S the Schur complement of the translations and Π the projection onto the rotations' tangent space.
void check_preconditioners(const Problem& P, int r, core::Rng& rng, double scale_translations) {
  const int d = P.d, w = d + 1, N0 = (P.n - 1) * w;
  const auto gens = generators(r, d);
  const int prot = static_cast<int>(gens.size()), p = prot + r, N = (P.n - 1) * p;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(N0, N0);
  for (const auto& e : P.edges)
    edge_entries(e, d, [&](int a, int b, int row, int col, DD value, double) {
      if (a == 0 || b == 0) return;
      const int gr = (a - 1) * w + row, gc = (b - 1) * w + col;
      if (a == b && row != 0 && col != 0 && gr > gc) return;
      A(gr, gc) += 2.0 * (value.hi + value.lo);
      if (gr != gc) A(gc, gr) += 2.0 * (value.hi + value.lo);
    });
  const Point X = random_point(P.n, r, rng);
  // The ambient vector of a coordinate: column a of the N0 × r matrix [t_v, Y_v] rows, stacked column-major.
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(N0) * r, N);
  for (int v = 1; v < P.n; ++v) {
    const int o0 = (v - 1) * p, row = (v - 1) * w;
    for (int k = 0; k < prot; ++k) {
      const Small D =
          tangent_basis(X.Q[static_cast<std::size_t>(v)], d, gens[static_cast<std::size_t>(k)].first,
                        gens[static_cast<std::size_t>(k)].second);  // r × d
      for (int a = 0; a < r; ++a)
        for (int i = 0; i < d; ++i) E(a * N0 + row + 1 + i, o0 + k) = D(a, i);
    }
    for (int a = 0; a < r; ++a) E(a * N0 + row, o0 + prot + a) = 1.0;
  }
  Eigen::MatrixXd Ahat =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(N0) * r, static_cast<Eigen::Index>(N0) * r);
  for (int a = 0; a < r; ++a) Ahat.block(a * N0, a * N0, N0, N0) = A;
  const Eigen::MatrixXd G = E.transpose() * E;
  const Eigen::MatrixXd Ginv = G.inverse();
  std::vector<int> ti, yi;
  for (int k = 0; k < N0 * r; ++k) ((k % N0) % w == 0 ? ti : yi).push_back(k);
  const auto sub = [](const Eigen::MatrixXd& M, const std::vector<int>& rows, const std::vector<int>& cols) {
    Eigen::MatrixXd out(rows.size(), cols.size());
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (std::size_t j = 0; j < cols.size(); ++j)
        out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = M(rows[i], cols[j]);
    return out;
  };
  const Eigen::MatrixXd Att = sub(Ahat, ti, ti), Aty = sub(Ahat, ti, yi), Ayy = sub(Ahat, yi, yi);
  const Eigen::MatrixXd S = Ayy - Aty.transpose() * Att.ldlt().solve(Aty);
  const Eigen::MatrixXd Ey = sub(E, yi, [&] {
    std::vector<int> cols;
    for (int c = 0; c < N; ++c)
      if (c % p < prot) cols.push_back(c);
    return cols;
  }());
  const Eigen::MatrixXd Pi = Ey * (Ey.transpose() * Ey).inverse() * Ey.transpose();
  const Eigen::MatrixXd Xs = Pi * S.inverse() * Pi;

  DataPreconditioner pre(P);
  REQUIRE(pre.ok());
  double tt = 0.0;
  for (const auto& e : P.edges) tt += e.tau * e.t.squaredNorm();
  CHECK(pre.translation_energy() == doctest::Approx(tt).epsilon(1e-12));
  Eigen::MatrixXd joint(N, N), reduced(N, N);
  for (int c = 0; c < N; ++c) {
    const Eigen::VectorXd unit = Eigen::VectorXd::Unit(N, c);
    Eigen::VectorXd z;
    pre.apply(X.Q, gens, r, unit, z);
    joint.col(c) = z;
    pre.apply_reduced(X.Q, gens, r, unit, z);
    reduced.col(c) = z;
  }
  const Eigen::MatrixXd joint_ref = Ginv * E.transpose() * Ahat.inverse() * E * Ginv;
  Eigen::MatrixXd reduced_ref(N, N);
  for (int c = 0; c < N; ++c) {
    const Eigen::VectorXd u = E * Ginv.col(c);
    Eigen::VectorXd ut(ti.size()), uy(yi.size());
    for (std::size_t i = 0; i < ti.size(); ++i) ut(static_cast<Eigen::Index>(i)) = u(ti[i]);
    for (std::size_t i = 0; i < yi.size(); ++i) uy(static_cast<Eigen::Index>(i)) = u(yi[i]);
    const Eigen::VectorXd zy = Xs * (uy - Aty.transpose() * Att.ldlt().solve(ut));
    const Eigen::VectorXd zt = Att.ldlt().solve(ut - Aty * zy);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(N0 * r);
    for (std::size_t i = 0; i < ti.size(); ++i) z(ti[i]) = zt(static_cast<Eigen::Index>(i));
    for (std::size_t i = 0; i < yi.size(); ++i) z(yi[i]) = zy(static_cast<Eigen::Index>(i));
    reduced_ref.col(c) = Ginv * E.transpose() * z;
  }
  INFO("translations × " << scale_translations << ", rank " << r);
  const double scale = joint_ref.norm();
  CHECK((joint - joint_ref).norm() <= 1e-9 * scale);
  CHECK((reduced - reduced_ref).norm() <= 1e-9 * reduced_ref.norm());
  // Symmetric and positive definite on the coordinates.
  CHECK((reduced - reduced.transpose()).norm() <= 1e-10 * reduced.norm());
  CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (reduced + reduced.transpose()))
            .eigenvalues()
            .minCoeff() > 0.0);
  // Without translations to couple, the two forms are one; with them, not.
  if (scale_translations == 0.0)
    CHECK((reduced - joint).norm() <= 1e-9 * scale);
  else
    CHECK((reduced - joint).norm() > 1e-3 * scale);
}

}  // namespace

TEST_CASE("certified parts: the trust region's preconditioners, joint and reduced, against dense algebra") {
  core::Rng rng(20261207);
  for (const double scale : {0.0, 1.0, 20.0}) {
    auto g = ring(8, 0.3, 0.1, rng);
    for (auto& e : g.edges)
      e.measurement = lie::SE2(scale * e.measurement.translation()(0), scale * e.measurement.translation()(1),
                               e.measurement.angle());
    const Problem P = make_problem(g, 2);
    for (int r : {2, 3, 4}) check_preconditioners(P, r, rng, scale);
  }
}

// The trust region's trial translations (DataPreconditioner::optimal_translations, on the preconditioner's
// factor of A_tt) against the free optimal_translations (its own Laplacian, assembled and factorized anew) at
// random points of rank 2–4: the same translations, ∂F/∂t = 0 there, and F no larger than at the point's own.
TEST_CASE("certified parts: the trust region's optimal translations are the least-squares ones") {
  core::Rng rng(20261224);
  auto g = ring(12, 0.3, 0.1, rng);
  for (const auto [i, j] : {std::pair{0, 6}, std::pair{3, 9}, std::pair{2, 7}}) {
    graph::Edge2 e = g.edges.front();
    e.i = i;
    e.j = j;
    e.measurement = g.poses[static_cast<std::size_t>(i)].inverse() * g.poses[static_cast<std::size_t>(j)];
    e.information = isotropic_information(40.0, 90.0);
    g.edges.push_back(e);
  }
  const Problem P = make_problem(g, 2);
  const DataPreconditioner pre(P);
  REQUIRE(pre.ok());
  for (int r : {2, 3, 4}) {
    Point X = random_point(P.n, r, rng);
    X.T.col(0).setZero();
    const double f0 = cost(P, X);
    Point A = X, B = X;
    pre.optimal_translations(P, A);
    optimal_translations(P, B);
    INFO("rank " << r);
    CHECK((A.T - B.T).norm() <= 1e-10 * B.T.norm());
    CHECK(A.T.col(0).norm() == 0.0);
    const Gradient G0 = gradient(P, X), GA = gradient(P, A);
    CHECK(GA.GT.rightCols(P.n - 1).norm() <= 1e-10 * G0.GT.rightCols(P.n - 1).norm());
    CHECK(cost(P, A) <= f0);
  }
}

}  // namespace keel_certified_parts_test
