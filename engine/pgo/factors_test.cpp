// Unit tests of the Ceres side: analytic Jacobians against central differences, the autodiff residuals
// against the plain residual definitions of pose_graph.hpp, the kernel adapter, and manifold ⊞/⊟ consistency.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "kit/test_kit.hpp"

#include "pgo/ceres_factors.hpp"
#include "pgo/internal.hpp"

using namespace keel;
using namespace keel::pgo;
using namespace keel::pgo::detail;
using keel::testkit::InformationDraw;
// Information as B Bᵀ / N + ½ I (InformationDraw::spd): symmetric positive definite, eigenvalues ≥ ½.
using keel::testkit::random_information;

namespace {

double uni(core::Rng& rng, double a, double b) { return rng.uniform(a, b); }

lie::SE2 random_se2(core::Rng& rng, double t = 5.0) {
  const double x = uni(rng, -t, t), y = uni(rng, -t, t), th = uni(rng, -3.1, 3.1);
  return lie::SE2(x, y, th);
}

lie::SE3 random_se3(core::Rng& rng, double t = 5.0, double angle = 3.0) {
  lie::Vec6 xi;
  for (int k = 0; k < 3; ++k) xi(k) = uni(rng, -t, t);
  lie::Vec3 axis;
  for (int k = 0; k < 3; ++k) axis(k) = uni(rng, -1, 1);
  xi.tail<3>() = axis.normalized() * uni(rng, 0.0, angle);
  return lie::SE3::exp(xi);
}

// Central differences of a SizedCostFunction over its raw parameters, against its analytic Jacobian.
double max_jacobian_error(const ceres::CostFunction& f, std::vector<std::vector<double>> params) {
  const int m = f.num_residuals();
  const auto& sizes = f.parameter_block_sizes();
  std::vector<const double*> ptrs;
  for (auto& p : params) ptrs.push_back(p.data());
  std::vector<std::vector<double>> jac(sizes.size());
  std::vector<double*> jptrs;
  for (std::size_t b = 0; b < sizes.size(); ++b) {
    jac[b].resize(m * sizes[b]);
    jptrs.push_back(jac[b].data());
  }
  std::vector<double> r(m);
  REQUIRE(f.Evaluate(ptrs.data(), r.data(), jptrs.data()));
  double worst = 0.0;
  for (std::size_t b = 0; b < sizes.size(); ++b) {
    const Eigen::Index n = sizes[b];
    // The residual as a function of block b alone (the other blocks as given).
    auto residual_of_block = [&](const testkit::VecX& x) {
      const std::vector<double> keep = params[b];
      for (Eigen::Index c = 0; c < n; ++c) params[b][c] = x(c);
      testkit::VecX out(m);
      f.Evaluate(ptrs.data(), out.data(), nullptr);
      params[b] = keep;
      return out;
    };
    const testkit::MatX numeric =
        testkit::numerical_jacobian(residual_of_block, Eigen::Map<const testkit::VecX>(params[b].data(), n));
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> analytic(
        jac[b].data(), m, n);
    worst = std::max(worst, (numeric - analytic).cwiseAbs().maxCoeff());
  }
  return worst;
}

std::vector<double> vec(const Pose2Params& p) { return {p.begin(), p.end()}; }

}  // namespace

TEST_CASE(
    "pose edge 2D: residual matches pose_graph.hpp and the analytic Jacobian matches central differences") {
  core::Rng rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const lie::SE2 z = random_se2(rng), Ti = random_se2(rng), Tj = random_se2(rng);
    const lie::Mat3 omega = random_information<3>(rng, InformationDraw::spd);
    const lie::Mat3 U = sqrt_information(omega, "test");
    CHECK((U.transpose() * U - omega).norm() < 1e-10);
    PoseEdge2Cost f(z, U);
    auto pi = to_params(Ti), pj = to_params(Tj);
    const double* ptrs[] = {pi.data(), pj.data()};
    lie::Vec3 r;
    REQUIRE(f.Evaluate(ptrs, r.data(), nullptr));
    const lie::Vec3 expected = U * edge_residual(z, Ti, Tj);
    CHECK((r - expected).norm() < 1e-9);
    // Away from the wrap of θ_E (where the residual jumps by 2π) the Jacobian is smooth.
    if (std::abs(edge_residual(z, Ti, Tj)(2)) < 3.0) CHECK(max_jacobian_error(f, {vec(pi), vec(pj)}) < 1e-6);
  }
}

TEST_CASE("landmark 2D: residual and analytic Jacobian") {
  core::Rng rng(8);
  for (int trial = 0; trial < 200; ++trial) {
    const lie::SE2 Ti = random_se2(rng);
    lie::Vec2 z, l;
    for (int k = 0; k < 2; ++k) z(k) = uni(rng, -3, 3);
    for (int k = 0; k < 2; ++k) l(k) = uni(rng, -8, 8);
    const lie::Mat2 U = sqrt_information(random_information<2>(rng, InformationDraw::spd), "test");
    Landmark2Cost f(z, U);
    auto pi = to_params(Ti);
    std::array<double, 2> pl{l(0), l(1)};
    const double* ptrs[] = {pi.data(), pl.data()};
    lie::Vec2 r;
    REQUIRE(f.Evaluate(ptrs, r.data(), nullptr));
    CHECK((r - U * landmark_residual(z, Ti, l)).norm() < 1e-9);
    CHECK(max_jacobian_error(f, {vec(pi), {pl.begin(), pl.end()}}) < 1e-6);
  }
}

TEST_CASE("pose edge 3D (autodiff): residual matches pose_graph.hpp, including rotations near π") {
  core::Rng rng(9);
  for (int trial = 0; trial < 200; ++trial) {
    const lie::SE3 z = random_se3(rng), Ti = random_se3(rng), Tj = random_se3(rng);
    const lie::Mat6 U = sqrt_information(random_information<6>(rng, InformationDraw::spd), "test");
    std::unique_ptr<ceres::CostFunction> f(make_pose_edge3(z, U));
    auto pi = to_params(Ti), pj = to_params(Tj);
    if (trial % 2)
      for (int k = 0; k < 4; ++k) pj[k] = -pj[k];  // the other quaternion sign: same pose
    const double* ptrs[] = {pi.data(), pj.data()};
    lie::Vec6 r;
    REQUIRE(f->Evaluate(ptrs, r.data(), nullptr));
    CHECK((r - U * edge_residual(z, Ti, Tj)).norm() < 1e-8);
  }
  // Noise-free edge: zero residual.
  const lie::SE3 Ti = random_se3(rng), Tj = random_se3(rng);
  std::unique_ptr<ceres::CostFunction> f(make_pose_edge3(Ti.inverse() * Tj, lie::Mat6::Identity()));
  auto pi = to_params(Ti), pj = to_params(Tj);
  const double* ptrs[] = {pi.data(), pj.data()};
  lie::Vec6 r;
  REQUIRE(f->Evaluate(ptrs, r.data(), nullptr));
  CHECK(r.norm() < 1e-12);
}

TEST_CASE(
    "pose edge 3D: autodiff Jacobian through the manifold equals central differences in the tangent space") {
  core::Rng rng(10);
  const Se3Manifold manifold;
  for (int trial = 0; trial < 50; ++trial) {
    const lie::SE3 z = random_se3(rng, 2.0, 1.0), Ti = random_se3(rng), Tj = random_se3(rng);
    const lie::Mat6 U = sqrt_information(random_information<6>(rng, InformationDraw::spd), "test");
    std::unique_ptr<ceres::CostFunction> f(make_pose_edge3(z, U));
    Pose3Params p[2] = {to_params(Ti), to_params(Tj)};
    const double* ptrs[] = {p[0].data(), p[1].data()};
    Eigen::Matrix<double, 6, 7, Eigen::RowMajor> J[2];
    double* jptrs[] = {J[0].data(), J[1].data()};
    lie::Vec6 r0;
    REQUIRE(f->Evaluate(ptrs, r0.data(), jptrs));
    for (int b = 0; b < 2; ++b) {
      Eigen::Matrix<double, 7, 6, Eigen::RowMajor> P;
      REQUIRE(manifold.PlusJacobian(p[b].data(), P.data()));
      const Eigen::Matrix<double, 6, 6> analytic = J[b] * P;
      for (int c = 0; c < 6; ++c) {
        const double h = 1e-6;
        double delta[6] = {0, 0, 0, 0, 0, 0};
        Pose3Params keep = p[b], plus, minus;
        delta[c] = h;
        manifold.Plus(keep.data(), delta, plus.data());
        delta[c] = -h;
        manifold.Plus(keep.data(), delta, minus.data());
        lie::Vec6 rp, rm;
        p[b] = plus;
        f->Evaluate(ptrs, rp.data(), nullptr);
        p[b] = minus;
        f->Evaluate(ptrs, rm.data(), nullptr);
        p[b] = keep;
        CHECK(((rp - rm) / (2 * h) - analytic.col(c)).cwiseAbs().maxCoeff() < 1e-5);
      }
    }
  }
}

TEST_CASE("inter-robot edges (autodiff): residual of the global poses Δa Ti, Δb Tj") {
  core::Rng rng(11);
  for (int trial = 0; trial < 100; ++trial) {
    {
      const lie::SE2 z = random_se2(rng), Da = random_se2(rng), Ti = random_se2(rng), Db = random_se2(rng),
                     Tj = random_se2(rng);
      const lie::Mat3 U = sqrt_information(random_information<3>(rng, InformationDraw::spd), "test");
      std::unique_ptr<ceres::CostFunction> f(make_inter_robot2(z, U));
      auto a = to_params(Da), i = to_params(Ti), b = to_params(Db), j = to_params(Tj);
      const double* ptrs[] = {a.data(), i.data(), b.data(), j.data()};
      lie::Vec3 r;
      REQUIRE(f->Evaluate(ptrs, r.data(), nullptr));
      CHECK((r - U * edge_residual(z, Da * Ti, Db * Tj)).norm() < 1e-9);
    }
    {
      const lie::SE3 z = random_se3(rng), Da = random_se3(rng), Ti = random_se3(rng), Db = random_se3(rng),
                     Tj = random_se3(rng);
      const lie::Mat6 U = sqrt_information(random_information<6>(rng, InformationDraw::spd), "test");
      std::unique_ptr<ceres::CostFunction> f(make_inter_robot3(z, U));
      auto a = to_params(Da), i = to_params(Ti), b = to_params(Db), j = to_params(Tj);
      const double* ptrs[] = {a.data(), i.data(), b.data(), j.data()};
      lie::Vec6 r;
      REQUIRE(f->Evaluate(ptrs, r.data(), nullptr));
      CHECK((r - U * edge_residual(z, Da * Ti, Db * Tj)).norm() < 1e-8);
    }
  }
}

TEST_CASE("Se2Manifold: x ⊞ (y ⊟ x) = y, (x ⊞ δ) ⊟ x = δ, Jacobians") {
  core::Rng rng(12);
  const Se2Manifold m;
  for (int trial = 0; trial < 200; ++trial) {
    const auto x = to_params(random_se2(rng)), y = to_params(random_se2(rng));
    double d[3], xy[3], back[3];
    m.Minus(y.data(), x.data(), d);
    m.Plus(x.data(), d, xy);
    CHECK(from_params(Pose2Params{xy[0], xy[1], xy[2]}).is_approx(from_params(y), 1e-12));
    double delta[3];
    delta[0] = uni(rng, -2, 2);
    delta[1] = uni(rng, -2, 2);
    delta[2] = uni(rng, -3.0, 3.0);
    m.Plus(x.data(), delta, xy);
    m.Minus(xy, x.data(), back);
    for (int k = 0; k < 3; ++k) CHECK(back[k] == doctest::Approx(delta[k]).epsilon(1e-12));
    CHECK(std::abs(xy[2]) <= lie::kPi);
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> P, M;
    m.PlusJacobian(x.data(), P.data());
    m.MinusJacobian(x.data(), M.data());
    CHECK((M * P - lie::Mat3::Identity()).norm() < 1e-15);
  }
}

TEST_CASE("Se3Manifold (SO(3) × R³): x ⊞ (y ⊟ x) = y, (x ⊞ δ) ⊟ x = δ, Minus∘Plus Jacobians = I") {
  core::Rng rng(13);
  const Se3Manifold m;
  REQUIRE(m.AmbientSize() == 7);
  REQUIRE(m.TangentSize() == 6);
  for (int trial = 0; trial < 200; ++trial) {
    const auto x = to_params(random_se3(rng)), y = to_params(random_se3(rng, 5.0, 2.5));
    double d[6], back[6];
    Pose3Params xy;
    m.Minus(y.data(), x.data(), d);
    m.Plus(x.data(), d, xy.data());
    CHECK(from_params(xy).is_approx(from_params(y), 1e-9));
    double delta[6];
    for (double& v : delta) v = uni(rng, -0.5, 0.5);
    m.Plus(x.data(), delta, xy.data());
    m.Minus(xy.data(), x.data(), back);
    for (int k = 0; k < 6; ++k) CHECK(back[k] == doctest::Approx(delta[k]).epsilon(1e-9));
    Eigen::Matrix<double, 7, 6, Eigen::RowMajor> P;
    Eigen::Matrix<double, 6, 7, Eigen::RowMajor> M;
    m.PlusJacobian(x.data(), P.data());
    m.MinusJacobian(x.data(), M.data());
    CHECK((M * P - lie::Mat6::Identity()).norm() < 1e-12);
  }
}

TEST_CASE("KernelLoss passes ρ, ρ', ρ'' of robust_rho to Ceres") {
  for (auto kernel : {RobustKernel::huber, RobustKernel::cauchy, RobustKernel::dcs}) {
    const KernelLoss loss(kernel, 2.0);
    for (double s : {0.0, 0.5, 3.9, 4.1, 50.0, 1e6}) {
      double out[3];
      loss.Evaluate(s, out);
      const Rho r = robust_rho(kernel, 2.0, s);
      CHECK(out[0] == r.rho);
      CHECK(out[1] == r.d1);
      CHECK(out[2] == r.d2);
    }
  }
  // Huber and Cauchy agree with Ceres' own losses of the same parameter.
  const ceres::HuberLoss huber(2.0);
  const ceres::CauchyLoss cauchy(2.0);
  for (double s : {0.3, 3.0, 5.0, 80.0}) {
    double a[3], b[3];
    huber.Evaluate(s, a);
    KernelLoss(RobustKernel::huber, 2.0).Evaluate(s, b);
    for (int k = 0; k < 3; ++k) CHECK(a[k] == doctest::Approx(b[k]).epsilon(1e-12));
    cauchy.Evaluate(s, a);
    KernelLoss(RobustKernel::cauchy, 2.0).Evaluate(s, b);
    for (int k = 0; k < 3; ++k) CHECK(a[k] == doctest::Approx(b[k]).epsilon(1e-12));
  }
}

TEST_CASE("sqrt_information: Cholesky, semi-definite fallback, and errors name the edge") {
  const lie::Mat3 omega = (lie::Mat3() << 4, 1, 0, 1, 3, 0.5, 0, 0.5, 2).finished();
  const lie::Mat3 U = sqrt_information(omega, "edge");
  CHECK((U.transpose() * U - omega).norm() < 1e-12);
  CHECK(U(1, 0) == 0.0);  // upper triangular
  const lie::Mat3 psd = lie::Vec3(1.0, 2.0, 0.0).asDiagonal();
  CHECK((sqrt_information(psd, "edge").transpose() * sqrt_information(psd, "edge") - psd).norm() < 1e-12);
  lie::Mat3 bad = lie::Mat3::Identity();
  bad(2, 2) = -1.0;
  CHECK_THROWS_WITH_AS(
      sqrt_information(bad, "edge 3 (line 7 of 'x.txt')"),
      doctest::Contains("edge 3 (line 7 of 'x.txt'): information matrix is not positive semi-definite"),
      std::invalid_argument);
}
