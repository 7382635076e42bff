// Lie-algebra Jacobians of the pose-graph residuals against central differences of the actual residuals (at
// random poses and measurements, so E = z⁻¹ T_i⁻¹ T_j is far from the identity), and the assembly of H.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "cov/information.hpp"
#include "cov/test_graphs.hpp"
#include "kit/test_kit.hpp"

using namespace keel;
using namespace keel::cov;

namespace {

constexpr double kStep = 1e-6;

// A random group element: rotation entries of the tangent N(0, r_scale²), translation entries N(0, t_scale²).
template <class G>
G random_group(core::Rng& rng, double t_scale, double r_scale) {
  return testkit::random_pose<G>(rng, r_scale, t_scale);
}

// Central difference of f(D) with respect to the left perturbation D = exp(δ^) of one argument.
template <class G, class F>
MatX numeric_jacobian(const F& f) {
  return testkit::numerical_jacobian_tangent<G>(
      [&](const typename G::Tangent& d) -> VecX { return f(G::exp(d)); }, kStep);
}

double rel_err(const MatX& a, const MatX& b) { return (a - b).norm() / std::max(1.0, b.norm()); }

}  // namespace

TEST_CASE("2D edge Jacobians match central differences of the residual (large E)") {
  core::Rng rng(11);
  int tested = 0;
  while (tested < 200) {
    const SE2 Ti = random_group<SE2>(rng, 50.0, 3.0), Tj = random_group<SE2>(rng, 50.0, 3.0);
    const SE2 z = random_group<SE2>(rng, 20.0, 3.0);
    const auto lin = linearize_edge(z, Ti, Tj);
    if (std::abs(lin.residual(2)) > 3.0) continue;  // keep the wrap of θ_E away from the differences
    ++tested;
    CHECK((lin.residual - edge_residual(z, Ti, Tj)).norm() == doctest::Approx(0.0));
    const MatX Ji = numeric_jacobian<SE2>([&](const SE2& D) -> VecX { return edge_residual(z, D * Ti, Tj); });
    const MatX Jj = numeric_jacobian<SE2>([&](const SE2& D) -> VecX { return edge_residual(z, Ti, D * Tj); });
    CHECK(rel_err(lin.J_r_xi_i, Ji) < 1e-7);
    CHECK(rel_err(lin.J_r_xi_j, Jj) < 1e-7);
  }
}

TEST_CASE("2D edge Jacobians differ from the coordinate Jacobians away from the origin") {
  // Sanity of the premise of §5.8.2: ∂r/∂ξ ≠ ∂r/∂(x, y, θ) once the poses are not at the origin.
  const SE2 Ti(40.0, -25.0, 0.7), Tj(43.0, -21.0, 1.1);
  const SE2 z = Ti.inverse() * Tj;
  const auto lin = linearize_edge(z, Ti, Tj);
  // Central differences in the coordinates (x, y, θ) of T_j.
  const MatX Jc = testkit::numerical_jacobian(
      [&](const VecX& c) -> VecX { return edge_residual(z, Ti, SE2(c(0), c(1), c(2))); },
      VecX(Vec3(Tj.translation().x(), Tj.translation().y(), Tj.angle())), kStep);
  CHECK(rel_err(lin.J_r_xi_j, Jc) > 0.5);
  // ... and they are related by ξ = G δc, G = [I, (t_y, −t_x)ᵀ; 0, 1]: J_coord = J_ξ G.
  Mat3 G = Mat3::Identity();
  G(0, 2) = Tj.translation().y();
  G(1, 2) = -Tj.translation().x();
  CHECK(rel_err(lin.J_r_xi_j * G, Jc) < 1e-7);
}

TEST_CASE("3D edge Jacobians match central differences of the residual (large E)") {
  core::Rng rng(12);
  int tested = 0;
  while (tested < 200) {
    const SE3 Ti = random_group<SE3>(rng, 30.0, 2.5), Tj = random_group<SE3>(rng, 30.0, 2.5);
    const SE3 z = random_group<SE3>(rng, 10.0, 2.5);
    const auto lin = linearize_edge(z, Ti, Tj);
    if (lin.residual.tail<3>().norm() > 2.9) continue;  // Log is not differentiable at |φ| = π
    ++tested;
    CHECK((lin.residual - edge_residual(z, Ti, Tj)).norm() == doctest::Approx(0.0));
    const MatX Ji = numeric_jacobian<SE3>([&](const SE3& D) -> VecX { return edge_residual(z, D * Ti, Tj); });
    const MatX Jj = numeric_jacobian<SE3>([&](const SE3& D) -> VecX { return edge_residual(z, Ti, D * Tj); });
    CHECK(rel_err(lin.J_r_xi_i, Ji) < 1e-6);
    CHECK(rel_err(lin.J_r_xi_j, Jj) < 1e-6);
  }
}

TEST_CASE("3D edge Jacobians at the identity and at a consistent measurement") {
  core::Rng rng(13);
  for (int t = 0; t < 20; ++t) {
    const SE3 Ti = random_group<SE3>(rng, 5.0, 3.0), Tj = random_group<SE3>(rng, 5.0, 3.0);
    const SE3 z = Ti.inverse() * Tj;  // E = I: D(E) = I, A_j = Ad(T_j⁻¹)
    const auto lin = linearize_edge(z, Ti, Tj);
    CHECK(lin.residual.norm() < 1e-9);
    CHECK(rel_err(lin.J_r_xi_j, Tj.inverse().adjoint()) < 1e-9);
    const MatX Jj = numeric_jacobian<SE3>([&](const SE3& D) -> VecX { return edge_residual(z, Ti, D * Tj); });
    CHECK(rel_err(lin.J_r_xi_j, Jj) < 1e-6);
  }
}

TEST_CASE("2D landmark Jacobians match central differences") {
  core::Rng rng(14);
  for (int t = 0; t < 100; ++t) {
    const SE2 T = random_group<SE2>(rng, 50.0, 3.0);
    Vec2 l, z;
    for (int k = 0; k < 2; ++k) l(k) = rng.uniform(-60.0, 60.0);
    for (int k = 0; k < 2; ++k) z(k) = rng.uniform(-60.0, 60.0);
    const auto lin = linearize_landmark(z, T, l);
    CHECK((lin.residual - landmark_residual(z, T, l)).norm() < 1e-12);
    const MatX Jx =
        numeric_jacobian<SE2>([&](const SE2& D) -> VecX { return landmark_residual(z, D * T, l); });
    CHECK(rel_err(lin.J_r_xi, Jx) < 1e-7);
    const MatX Jl = testkit::numerical_jacobian(
        [&](const VecX& x) -> VecX { return landmark_residual(z, T, Vec2(x)); }, VecX(l), kStep);
    CHECK(rel_err(lin.J_r_l, Jl) < 1e-7);
  }
}

TEST_CASE(
    "information_matrix assembles sum of A^T Omega A (2D with landmarks; fixed pose and prior gauges)") {
  const auto tg = test::small_graph_2d(9, 3, /*seed=*/5, /*noise=*/0.05);
  for (const Gauge kind : {Gauge::fix_pose, Gauge::prior}) {
    GaugeOptions gauge;
    gauge.kind = kind;
    gauge.pose = 2;
    if (kind == Gauge::prior) gauge.prior_information = Mat3::Identity() * 7.0;
    const auto H = information_matrix(tg.graph, tg.estimate, tg.landmarks, gauge);
    H.validate();
    const int n = 9, m = 3;
    CHECK(H.num_variables() == n + m);
    CHECK(H.size == 3 * n + 2 * m - (kind == Gauge::fix_pose ? 3 : 0));
    // dense reference over all variables, then drop the fixed pose
    const int N = 3 * n + 2 * m;
    MatX Hd = MatX::Zero(N, N);
    for (const auto& e : tg.graph.edges) {
      const auto lin = linearize_edge(e.measurement, tg.estimate[e.i], tg.estimate[e.j]);
      MatX A = MatX::Zero(3, N);
      A.block(0, 3 * e.i, 3, 3) += lin.J_r_xi_i;
      A.block(0, 3 * e.j, 3, 3) += lin.J_r_xi_j;
      Hd += A.transpose() * e.information * A;
    }
    for (const auto& lm : tg.graph.landmark_measurements) {
      const auto lin = linearize_landmark(lm.position, tg.estimate[lm.pose], tg.landmarks[lm.landmark]);
      MatX A = MatX::Zero(2, N);
      A.block(0, 3 * lm.pose, 2, 3) = lin.J_r_xi;
      A.block(0, 3 * n + 2 * lm.landmark, 2, 2) = lin.J_r_l;
      Hd += A.transpose() * lm.information * A;
    }
    if (kind == Gauge::prior) Hd.block(6, 6, 3, 3) += gauge.prior_information;
    std::vector<int> keep;
    for (int r = 0; r < N; ++r)
      if (kind == Gauge::prior || r / 3 != 2 || r >= 3 * n) keep.push_back(r);
    MatX Hk(static_cast<int>(keep.size()), static_cast<int>(keep.size()));
    for (std::size_t a = 0; a < keep.size(); ++a)
      for (std::size_t b = 0; b < keep.size(); ++b)
        Hk(static_cast<int>(a), static_cast<int>(b)) = Hd(keep[a], keep[b]);
    CHECK(rel_err(H.dense(), Hk) < 1e-13);
    // layout helpers
    for (int v = 0; v < H.num_variables(); ++v) {
      if (H.offset[static_cast<std::size_t>(v)] < 0) continue;
      for (int d = 0; d < H.variable_dim(v); ++d)
        CHECK(H.variable_of_row(H.offset[static_cast<std::size_t>(v)] + d) == v);
    }
  }
}

TEST_CASE("information_matrix (3D) and input errors") {
  const auto tg = test::small_graph_3d(7, /*seed=*/6, /*noise=*/0.05);
  const auto H = information_matrix(tg.graph, tg.estimate);
  H.validate();
  CHECK(H.size == 36);
  CHECK(H.offset[0] == -1);
  // symmetric positive definite
  const MatX Hd = H.dense();
  CHECK((Hd - Hd.transpose()).norm() == doctest::Approx(0.0));
  CHECK(Eigen::LLT<MatX>(Hd).info() == Eigen::Success);

  auto bad = tg.graph;
  bad.edges[2].j = 99;
  bad.edges[2].line = 17;
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)information_matrix(bad, tg.estimate); },
                                                    "edge 2 (source line 17) refers to pose 99"));
  GaugeOptions g;
  g.kind = Gauge::prior;
  CHECK_THROWS_AS((void)information_matrix(tg.graph, tg.estimate, g), std::invalid_argument);
  g.prior_information = -Mat6::Identity();
  CHECK_THROWS_AS((void)information_matrix(tg.graph, tg.estimate, g), std::invalid_argument);
  g.kind = Gauge::fix_pose;
  g.pose = 7;
  CHECK_THROWS_AS((void)information_matrix(tg.graph, tg.estimate, g), std::invalid_argument);
}

TEST_CASE("Gauge names round-trip; an unknown name is an error naming the valid ones") {
  for (Gauge g : {Gauge::fix_pose, Gauge::prior}) CHECK(gauge_from_string(to_string(g)) == g);
  CHECK(to_string(Gauge::fix_pose) == "fix_pose");
  CHECK(testkit::throws_with<std::invalid_argument>([] { (void)gauge_from_string("nope"); },
                                                    "unknown cov::Gauge 'nope' (valid: fix_pose, prior)"));
  CHECK(testkit::throws_with<std::invalid_argument>([] { (void)gauge_from_string("Prior"); }, "'Prior'"));
}
