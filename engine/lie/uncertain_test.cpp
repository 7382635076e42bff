// First-order Lie-algebra propagation (thesis §§5.4-5.7) against Monte Carlo.
#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "kit/test_kit.hpp"
#include "lie/gaussian.hpp"
#include "lie/metrics.hpp"
#include "lie/uncertain.hpp"

using namespace keel::lie;
namespace testkit = keel::testkit;

namespace {

// Random SPD covariance of size d with entries of order scale^2 and strong correlations.
MatX random_cov(keel::core::Rng& rng, int d, double scale) {
  const MatX A = testkit::random_matrix(rng, d, d, scale);
  return A * A.transpose() + 0.1 * scale * scale * MatX::Identity(d, d);
}

template <class G>
G random_pose(keel::core::Rng& rng, double scale = 1.5) {
  typename G::Tangent xi;
  for (int i = 0; i < G::DoF; ++i) xi(i) = rng.uniform(-scale, scale);
  return G::exp(xi);
}

// Monte-Carlo covariance (eqs. 5.57-5.59) of op(T_1..T_n) about `out_mean`, where
// T_i = exp(xi_i) mean_i and xi_{1:n} ~ N(0, joint).
template <class G>
MatX monte_carlo(const std::vector<G>& means, const MatX& joint,
                 const std::function<G(const std::vector<G>&)>& op, const G& out_mean, int M,
                 keel::core::Rng& rng) {
  constexpr int D = G::DoF;
  const GaussianSampler sampler(joint);
  const G out_inv = out_mean.inverse();
  std::vector<G> s(means.size());
  MatX xi(D, M);
  for (int m = 0; m < M; ++m) {
    const VecX n = sampler(rng);
    for (std::size_t i = 0; i < means.size(); ++i)
      s[i] = G::exp(typename G::Tangent(n.segment<D>(D * static_cast<Eigen::Index>(i)))) * means[i];
    xi.col(m) = (op(s) * out_inv).log();
  }
  return sample_covariance_about_zero(xi);
}

template <class Ex, class F>
bool throws_with(F f, const std::string& needle) {
  try {
    f();
  } catch (const Ex& e) {
    return std::string(e.what()).find(needle) != std::string::npos;
  } catch (...) {
    return false;
  }
  return false;
}

constexpr int kSamples = 100000;

}  // namespace

TEST_CASE_TEMPLATE("compose: joint (eq. 5.39) and independent vs Monte Carlo" *
                       doctest::test_suite("monte_carlo"),
                   G, SO3, SE2, SE3) {
  keel::core::Rng rng(101);
  constexpr int D = G::DoF;
  const std::vector<G> means{random_pose<G>(rng), random_pose<G>(rng)};
  const MatX joint = random_cov(rng, 2 * D, 1e-3);
  const JointPoses<G> jp{means, joint};
  jp.validate();
  const UncertainPose<G> a = jp.marginal(0), b = jp.marginal(1);
  const UncertainPose<G> corr = compose(a, b, jp.cross(0, 1));
  const UncertainPose<G> ind = compose(a, b);
  CHECK(corr.mean.is_approx(means[0] * means[1], 1e-14));  // eq. 5.32
  const MatX mc = monte_carlo<G>(
      means, joint, [](const std::vector<G>& s) { return s[0] * s[1]; }, corr.mean, kSamples, rng);
  const double e_corr = normalized_covariance_error(corr.cov, mc);
  const double e_ind = normalized_covariance_error(ind.cov, mc);
  CAPTURE(e_corr);
  CAPTURE(e_ind);
  CHECK(e_corr < 0.02);
  CHECK(e_ind > 0.1);
  CHECK(e_ind > 5.0 * e_corr);
  // Same through the JointPoses overload.
  CHECK((compose(jp, 0, 1).cov - corr.cov).norm() < 1e-15 * (1.0 + corr.cov.norm()));
  CHECK((compose(jp, 0, 1, false).cov - ind.cov).norm() < 1e-15 * (1.0 + ind.cov.norm()));

  // Independent poses: the Barfoot-Furgale formula matches.
  MatX blockdiag = MatX::Zero(2 * D, 2 * D);
  blockdiag.topLeftCorner(D, D) = a.cov;
  blockdiag.bottomRightCorner(D, D) = b.cov;
  const MatX mc_ind = monte_carlo<G>(
      means, blockdiag, [](const std::vector<G>& s) { return s[0] * s[1]; }, ind.mean, kSamples, rng);
  CHECK(normalized_covariance_error(ind.cov, mc_ind) < 0.02);
}

TEST_CASE_TEMPLATE("inverse (eqs. 5.43-5.45) vs Monte Carlo, also at large noise" *
                       doctest::test_suite("monte_carlo"),
                   G, SO3, SE2, SE3) {
  keel::core::Rng rng(102);
  constexpr int D = G::DoF;
  const G mean = random_pose<G>(rng);
  for (const double scale : {1e-3, 0.1}) {
    const MatX cov = random_cov(rng, D, scale);
    const UncertainPose<G> a(mean, cov);
    const UncertainPose<G> inv = inverse(a);
    CHECK(inv.mean.is_approx(mean.inverse(), 1e-14));
    const MatX mc = monte_carlo<G>(
        {mean}, cov, [](const std::vector<G>& s) { return s[0].inverse(); }, inv.mean, kSamples, rng);
    CHECK(normalized_covariance_error(inv.cov, mc) < 0.02);  // the map of eq. 5.43 is exact
  }
}

TEST_CASE_TEMPLATE("relative pose (eqs. 5.48, 5.51) vs Monte Carlo" * doctest::test_suite("monte_carlo"), G,
                   SO3, SE2, SE3) {
  keel::core::Rng rng(103);
  constexpr int D = G::DoF;
  const std::vector<G> means{random_pose<G>(rng), random_pose<G>(rng)};
  // Strong positive correlation between the two poses (as in a SLAM solution).
  const MatX C = random_cov(rng, D, 1e-3);
  MatX joint(2 * D, 2 * D);
  joint << C, 0.9 * C, 0.9 * C, C + 0.05 * random_cov(rng, D, 1e-3);
  const JointPoses<G> jp{means, joint};
  jp.validate();
  const UncertainPose<G> rel = relative(jp, 0, 1);
  const UncertainPose<G> rel_ind = relative(jp, 0, 1, false);
  CHECK(rel.mean.is_approx(means[0].inverse() * means[1], 1e-14));  // eq. 5.48
  const MatX mc = monte_carlo<G>(
      means, joint, [](const std::vector<G>& s) { return s[0].inverse() * s[1]; }, rel.mean, kSamples, rng);
  const double e = normalized_covariance_error(rel.cov, mc);
  const double e_ind = normalized_covariance_error(rel_ind.cov, mc);
  CAPTURE(e);
  CAPTURE(e_ind);
  CHECK(e < 0.03);
  CHECK(e_ind > 1.0);  // ignoring positive correlation grossly over-estimates (Fig. 5.5)
  CHECK(rel_ind.cov.trace() > rel.cov.trace());
  // Flipping the sign of the cross terms (the garbled typesetting of eq. 5.51) is wrong:
  const UncertainPose<G> wrong_sign =
      relative(jp.marginal(0), jp.marginal(1), typename G::Jacobian(-jp.cross(0, 1)));
  CHECK(normalized_covariance_error(wrong_sign.cov, mc) > 1.0);

  // Independent poses: eq. 5.51 without cross terms matches.
  MatX blockdiag = joint;
  blockdiag.topRightCorner(D, D).setZero();
  blockdiag.bottomLeftCorner(D, D).setZero();
  const MatX mc_ind = monte_carlo<G>(
      means, blockdiag, [](const std::vector<G>& s) { return s[0].inverse() * s[1]; }, rel.mean, kSamples,
      rng);
  CHECK(normalized_covariance_error(rel_ind.cov, mc_ind) < 0.02);
}

TEST_CASE_TEMPLATE("known poses composed with uncertain ones are exact (large noise)", G, SO3, SE2, SE3) {
  keel::core::Rng rng(104);
  constexpr int D = G::DoF;
  const G K = random_pose<G>(rng, 2.0);
  const G mean = random_pose<G>(rng, 2.0);
  const MatX cov = random_cov(rng, D, 0.15);
  const UncertainPose<G> U(mean, cov);
  const int M = 50000;
  struct Case {
    UncertainPose<G> predicted;
    std::function<G(const std::vector<G>&)> op;
  };
  const std::vector<Case> cases{
      {compose(K, U), [&](const std::vector<G>& s) { return K * s[0]; }},
      {compose(U, K), [&](const std::vector<G>& s) { return s[0] * K; }},
      {relative(K, U), [&](const std::vector<G>& s) { return K.inverse() * s[0]; }},
      {relative(U, K), [&](const std::vector<G>& s) { return s[0].inverse() * K; }},
  };
  for (const Case& c : cases) {
    const MatX mc = monte_carlo<G>({mean}, cov, c.op, c.predicted.mean, M, rng);
    CHECK(normalized_covariance_error(c.predicted.cov, mc) < 0.03);
  }
  CHECK(compose(K, U).mean.is_approx(K * mean, 1e-14));
  CHECK((compose(U, K).cov - U.cov).norm() == 0.0);
  // Equivalent to the general formulas with a zero-covariance pose.
  const UncertainPose<G> Kp = UncertainPose<G>::known(K);
  CHECK((compose(Kp, U).cov - compose(K, U).cov).norm() < 1e-14);
  CHECK((compose(U, Kp).cov - compose(U, K).cov).norm() < 1e-14);
  CHECK((relative(Kp, U).cov - relative(K, U).cov).norm() < 1e-14);
  CHECK((relative(U, Kp).cov - relative(U, K).cov).norm() < 1e-14);
}

TEST_CASE_TEMPLATE("chains of correlated poses: compose_chain and append_composition", G, SE2, SE3) {
  keel::core::Rng rng(105);
  constexpr int D = G::DoF;
  const int N = 6;
  std::vector<G> means;
  for (int i = 0; i < N; ++i) means.push_back(random_pose<G>(rng, 1.0));
  // Correlated odometry-like joint covariance: xi_k = rho xi_{k-1} + sqrt(1 - rho^2) w_k.
  const MatX C = random_cov(rng, D, 5e-4);
  const double rho = 0.6;
  MatX joint(D * N, D * N);
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) joint.block(D * i, D * j, D, D) = std::pow(rho, std::abs(i - j)) * C;
  const JointPoses<G> jp{means, joint};
  jp.validate();

  const UncertainPose<G> chain = compose_chain(jp);
  const UncertainPose<G> chain_ind = compose_chain(jp, false);
  G expected_mean = G::identity();
  for (const G& m : means) expected_mean = expected_mean * m;
  CHECK(chain.mean.is_approx(expected_mean, 1e-12));

  // Repeated append_composition gives the same covariance (eq. 5.39 repeated, cross terms carried).
  JointPoses<G> grown = jp;
  std::size_t acc = 0;
  for (std::size_t k = 1; k < static_cast<std::size_t>(N); ++k) acc = append_composition(grown, acc, k);
  grown.validate();
  CHECK(grown.size() == static_cast<std::size_t>(2 * N - 1));
  CHECK((grown.marginal(acc).cov - chain.cov).norm() < 1e-12 * chain.cov.norm());
  CHECK(grown.marginal(acc).mean.is_approx(chain.mean, 1e-12));
  // Two-element chain equals eq. 5.39.
  const JointPoses<G> two{{means[0], means[1]}, joint.topLeftCorner(2 * D, 2 * D)};
  CHECK((compose_chain(two).cov - compose(jp, 0, 1).cov).norm() < 1e-15 + 1e-13 * chain.cov.norm());
  // Independent chain helper equals use_cross = false on a block-diagonal joint.
  std::vector<UncertainPose<G>> parts;
  for (int i = 0; i < N; ++i) parts.push_back(jp.marginal(static_cast<std::size_t>(i)));
  CHECK((compose_chain(parts).cov - chain_ind.cov).norm() < 1e-12 * chain_ind.cov.norm());

  const MatX mc = monte_carlo<G>(
      means, joint,
      [](const std::vector<G>& s) {
        G acc_pose = G::identity();
        for (const G& x : s) acc_pose = acc_pose * x;
        return acc_pose;
      },
      chain.mean, kSamples, rng);
  const double e = normalized_covariance_error(chain.cov, mc);
  const double e_ind = normalized_covariance_error(chain_ind.cov, mc);
  CAPTURE(e);
  CAPTURE(e_ind);
  CHECK(e < 0.02);
  CHECK(e_ind > 5.0 * e);
  CHECK(e_ind > 0.2);
}

TEST_CASE_TEMPLATE("append_inverse / append_relative keep cross-covariances", G, SE2, SE3) {
  keel::core::Rng rng(106);
  constexpr int D = G::DoF;
  const std::vector<G> means{random_pose<G>(rng), random_pose<G>(rng), random_pose<G>(rng)};
  const MatX joint = random_cov(rng, 3 * D, 1e-3);
  JointPoses<G> jp{means, joint};
  const std::size_t r = append_relative(jp, 0, 1);     // T_0^-1 T_1
  const std::size_t i = append_inverse(jp, 2);         // T_2^-1
  const std::size_t c = append_composition(jp, r, i);  // T_0^-1 T_1 T_2^-1
  jp.validate();
  CHECK((jp.marginal(r).cov - relative(JointPoses<G>{means, joint}, 0, 1).cov).norm() < 1e-15);
  CHECK((jp.marginal(i).cov - inverse(JointPoses<G>{means, joint}.marginal(2)).cov).norm() < 1e-15);
  const MatX mc = monte_carlo<G>(
      means, joint, [](const std::vector<G>& s) { return s[0].inverse() * s[1] * s[2].inverse(); },
      jp.means[c], kSamples, rng);
  CHECK(normalized_covariance_error(jp.marginal(c).cov, mc) < 0.03);
}

TEST_CASE("thesis relative-pose example (eqs. 5.52-5.55), alpha = 1") {
  keel::core::Rng rng(107);
  Mat4 M1, M2;
  M1 << 0.707107, -0.707107, 0, 3, 0.707107, 0.707107, 0, 3, -0, 0, 1, 0, 0, 0, 0, 1;
  M2 << 0.707107, -0.707107, 0, 4.5, 0.707107, 0.707107, 0, 4.5, -0, 0, 1, 0, 0, 0, 0, 1;
  const SE3 T1 = SE3::from_matrix(M1), T2 = SE3::from_matrix(M2);
  Vec6 d_marg, d_cross;
  d_marg << 0.005, 0.005, 1e-5, 1e-5, 1e-5, 0.006;
  d_cross << 0.0005, 0.0005, 0, 0, 0, 0.005;
  MatX joint = MatX::Zero(12, 12);
  joint.topLeftCorner(6, 6) = d_marg.asDiagonal();
  joint.bottomRightCorner(6, 6) = d_marg.asDiagonal();
  joint.topRightCorner(6, 6) = d_cross.asDiagonal();
  joint.bottomLeftCorner(6, 6) = d_cross.asDiagonal();
  const JointPoses<SE3> jp{{T1, T2}, joint};
  jp.validate();
  const UncertainPose<SE3> rel = relative(jp, 0, 1);
  const UncertainPose<SE3> rel_ind = relative(jp, 0, 1, false);
  const MatX mc = monte_carlo<SE3>(
      jp.means, joint, [](const std::vector<SE3>& s) { return s[0].inverse() * s[1]; }, rel.mean, kSamples,
      rng);
  const double e = covariance_error(rel.cov, mc);
  const double e_ind = covariance_error(rel_ind.cov, mc);
  MESSAGE("thesis example (alpha=1): eps joint = " << e << ", eps ignoring correlation = " << e_ind);
  CHECK(e < 0.1 * e_ind);
  CHECK(rel.mean.translation().isApprox(Vec3(1.5 * std::sqrt(2.0), 0.0, 0.0), 1e-5));
}

TEST_CASE("bad inputs throw with clear messages") {
  Mat6 asym = Mat6::Identity();
  asym(0, 1) = 0.3;
  CHECK(throws_with<std::invalid_argument>([&] { UncertainPose<SE3>(SE3(), asym); }, "not symmetric"));
  Mat6 neg = Mat6::Identity();
  neg(5, 5) = -0.5;
  CHECK(throws_with<std::invalid_argument>([&] { UncertainPose<SE3>(SE3(), neg); },
                                           "not positive semi-definite"));
  Mat3 nan = Mat3::Identity();
  nan(1, 1) = std::nan("");
  CHECK(throws_with<std::invalid_argument>([&] { UncertainPose<SE2>(SE2(), nan); }, "non-finite"));
  CHECK_NOTHROW(UncertainPose<SE3>(SE3(), Mat6::Zero()));

  const JointPoses<SE3> wrong{{SE3(), SE3(), SE3()}, MatX::Identity(12, 12)};
  CHECK(
      throws_with<std::invalid_argument>([&] { wrong.validate(); }, "joint covariance is 12x12 but 3 poses"));
  CHECK(throws_with<std::invalid_argument>([&] { (void)compose(wrong, 0, 1); }, "need 18x18"));
  CHECK(throws_with<std::invalid_argument>([&] { (void)compose_chain(wrong); }, "need 18x18"));
  const JointPoses<SE2> ok{{SE2(), SE2()}, MatX::Identity(6, 6)};
  CHECK(throws_with<std::invalid_argument>([&] { (void)relative(ok, 0, 2); }, "out of range"));
  MatX notpsd = MatX::Identity(6, 6);
  notpsd(0, 3) = notpsd(3, 0) = 2.0;
  const JointPoses<SE2> bad{{SE2(), SE2()}, notpsd};
  CHECK(throws_with<std::invalid_argument>([&] { bad.validate(); }, "not positive semi-definite"));
  CHECK(throws_with<std::invalid_argument>(
      [&] {
        (void)bad.marginal(0);
        (void)GaussianSampler(bad.cov);
      },
      "not positive semi-definite"));
}
