// The meaning of the marginals (thesis §5.8.2): on a small loopy 2D graph far from the origin, sample the
// measurement noise from each edge's Ω⁻¹, re-solve the MAP (a small Gauss-Newton, test-only), and compare the
// sample covariance of ξ_i = log(T̂_i T_i⁻¹) — the left perturbation of eq. 5.14 — with the predicted joint
// marginals at the truth. The coordinate-based covariance (Jacobians with respect to (x, y, θ)) predicts the
// spread of the coordinates instead, and read as a Lie-algebra covariance it is measurably wrong for poses
// far from the origin.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "cov/test_graphs.hpp"
#include "kit/test_kit.hpp"
#include "lie/euler.hpp"

using namespace keel;
using namespace keel::cov;

namespace {

// Gauss-Newton on the edges of g with pose 0 held fixed, Lie-algebra updates T ← exp(δ^) T.
std::vector<SE2> solve_map(const PoseGraph2D& g, std::vector<SE2> T) {
  const int n = static_cast<int>(T.size()), N = 3 * (n - 1);
  for (int it = 0; it < 20; ++it) {
    MatX H = MatX::Zero(N, N);
    VecX b = VecX::Zero(N);
    for (const auto& e : g.edges) {
      const auto lin = linearize_edge(e.measurement, T[e.i], T[e.j]);
      const int idx[2] = {e.i, e.j};
      const Mat3* A[2] = {&lin.J_r_xi_i, &lin.J_r_xi_j};
      for (int a = 0; a < 2; ++a) {
        if (idx[a] == 0) continue;
        b.segment<3>(3 * (idx[a] - 1)) -= A[a]->transpose() * e.information * lin.residual;
        for (int c = 0; c < 2; ++c) {
          if (idx[c] == 0) continue;
          H.block<3, 3>(3 * (idx[a] - 1), 3 * (idx[c] - 1)) += A[a]->transpose() * e.information * *A[c];
        }
      }
    }
    const VecX d = H.ldlt().solve(b);
    for (int i = 1; i < n; ++i) T[i] = SE2::exp(d.segment<3>(3 * (i - 1))) * T[i];
    if (d.norm() < 1e-13) break;
  }
  return T;
}

struct Gaussian3 {
  Eigen::LLT<Mat3> llt;
  explicit Gaussian3(const Mat3& information) : llt(information.inverse()) {}
  Vec3 operator()(core::Rng& rng) const { return llt.matrixL() * Vec3(testkit::random_vector(rng, 3)); }
};

// max over the entries of |S − P| / (standard error of a sample covariance entry under P)
double max_z_score(const MatX& S, const MatX& P, int samples) {
  double worst = 0.0;
  for (int a = 0; a < P.rows(); ++a)
    for (int b = 0; b <= a; ++b) {
      const double se = std::sqrt((P(a, a) * P(b, b) + P(a, b) * P(a, b)) / samples);
      worst = std::max(worst, std::abs(S(a, b) - P(a, b)) / se);
    }
  return worst;
}

}  // namespace

TEST_CASE(
    "Monte Carlo: the joint marginals are the covariance of the left perturbations xi = log(T_hat T^-1)" *
    doctest::test_suite("monte_carlo")) {
  // 8 poses far from the origin with loop closures; small noise so that first order holds.
  auto tg = test::small_graph_2d(8, 0, /*seed=*/31, /*noise=*/0.0);
  const std::vector<SE2> truth = tg.graph.poses;
  const int n = static_cast<int>(truth.size());
  for (auto& e : tg.graph.edges) {
    Mat3 cov = Mat3::Zero();
    cov.diagonal() << 0.03 * 0.03, 0.02 * 0.02, 0.01 * 0.01;
    cov(0, 1) = cov(1, 0) = 0.3 * 0.03 * 0.02;
    e.information = cov.inverse();
  }
  // Prediction at the truth (pose 0 fixed: the MAP below holds it at the truth).
  const auto H = information_matrix(tg.graph, truth);
  const MarginalCovariance mc(H);
  std::vector<int> all;
  for (int i = 1; i < n; ++i) all.push_back(i);
  const MatX P = mc.joint(all);

  // Coordinate-based covariance: Jacobians with respect to (x, y, θ), by central differences of the residual.
  MatX Hc = MatX::Zero(3 * (n - 1), 3 * (n - 1));
  for (const auto& e : tg.graph.edges) {
    Eigen::Matrix<double, 3, Eigen::Dynamic> A =
        Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, 3 * (n - 1));
    for (int which : {e.i, e.j}) {
      if (which == 0) continue;
      auto residual_at = [&](const VecX& c) -> VecX {
        std::vector<SE2> T = truth;
        T[which] = SE2(c(0), c(1), c(2));
        return edge_residual(e.measurement, T[e.i], T[e.j]);
      };
      const Vec3 c0(truth[which].translation().x(), truth[which].translation().y(), truth[which].angle());
      A.middleCols(3 * (which - 1), 3) += testkit::numerical_jacobian(residual_at, VecX(c0), 1e-6);
    }
    Hc += A.transpose() * e.information * A;
  }
  const MatX Pc = Hc.inverse();

  // The two are related by ξ_i = G_i δc_i, G_i = [I, (t_y, −t_x)ᵀ; 0, 1] (first order) — exactly, as
  // matrices.
  MatX G = MatX::Zero(3 * (n - 1), 3 * (n - 1));
  for (int i = 1; i < n; ++i) {
    Mat3 Gi = Mat3::Identity();
    Gi(0, 2) = truth[i].translation().y();
    Gi(1, 2) = -truth[i].translation().x();
    G.block<3, 3>(3 * (i - 1), 3 * (i - 1)) = Gi;
  }
  CHECK((G * Pc * G.transpose() - P).norm() / P.norm() < 1e-6);

  // Monte Carlo: noisy measurements z = (T_i⁻¹ T_j) E⁻¹ with ρ(E) = r ~ N(0, Ω⁻¹), i.e. the residual at the
  // truth is r.
  constexpr int kSamples = 3000;
  core::Rng rng(2024);
  std::vector<Gaussian3> noise;
  for (const auto& e : tg.graph.edges) noise.emplace_back(e.information);
  MatX S = MatX::Zero(P.rows(), P.cols()), Sc = MatX::Zero(P.rows(), P.cols());
  VecX mean = VecX::Zero(P.rows());
  for (int s = 0; s < kSamples; ++s) {
    PoseGraph2D g = tg.graph;
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      auto& e = g.edges[k];
      const Vec3 r = noise[k](rng);
      e.measurement = truth[e.i].inverse() * truth[e.j] * SE2(r(0), r(1), r(2)).inverse();
    }
    const auto T = solve_map(g, truth);
    VecX xi(3 * (n - 1)), dc(3 * (n - 1));
    for (int i = 1; i < n; ++i) {
      xi.segment<3>(3 * (i - 1)) = (T[i] * truth[i].inverse()).log();  // eq. 5.59
      dc.segment<3>(3 * (i - 1)) << T[i].translation() - truth[i].translation(),
          lie::wrap_angle(T[i].angle() - truth[i].angle());
    }
    S += xi * xi.transpose();
    Sc += dc * dc.transpose();
    mean += xi;
  }
  S /= kSamples;
  Sc /= kSamples;
  mean /= kSamples;

  // Agreement within Monte-Carlo error: the whole 21×21 joint (incl. cross-covariances between poses), and
  // the 6×6 joint of two poses on opposite sides of the loop.
  const double z_lie = max_z_score(S, P, kSamples);
  const double z_coord_as_lie = max_z_score(S, Pc, kSamples);
  const double z_coord = max_z_score(Sc, Pc, kSamples);
  MESSAGE("max z-score: Lie prediction vs ξ samples "
          << z_lie << ", coordinate covariance vs ξ samples " << z_coord_as_lie
          << ", coordinate covariance vs coordinate samples " << z_coord);
  CHECK(z_lie < 4.5);
  CHECK(z_coord < 4.5);          // the coordinate covariance does describe the coordinates ...
  CHECK(z_coord_as_lie > 50.0);  // ... but not the Lie-algebra perturbation of far-away poses
  const std::vector<int> pair = {2, 6};
  const MatX Ppair = mc.joint(pair);
  MatX Spair(6, 6);
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      Spair.block<3, 3>(3 * a, 3 * b) = S.block<3, 3>(3 * (pair[a] - 1), 3 * (pair[b] - 1));
  CHECK(max_z_score(Spair, Ppair, kSamples) < 4.5);
  CHECK(Ppair.block<3, 3>(0, 3).norm() > 0.3 * Ppair.block<3, 3>(0, 0).norm());  // strongly cross-correlated
  // Frobenius distance: the Lie prediction is within sampling noise, the coordinate one is not.
  const double err_lie = (S - P).norm() / P.norm(), err_coord = (S - Pc).norm() / P.norm();
  MESSAGE("relative Frobenius error vs ξ samples: Lie " << err_lie << ", coordinates " << err_coord);
  CHECK(err_lie < 0.1);
  CHECK(err_coord > 0.5);
  // The mean of ξ is zero to within Monte-Carlo error (the MAP is unbiased to first order).
  for (int a = 0; a < mean.size(); ++a) CHECK(std::abs(mean(a)) < 5.0 * std::sqrt(P(a, a) / kSamples));
}
