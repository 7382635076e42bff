// Generic property tests for SO2, SO3, SE2, SE3 (thesis §5.2).
#include <doctest/doctest.h>

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

#include "kit/test_kit.hpp"
#include "lie/concepts.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/so2.hpp"
#include "lie/so3.hpp"

using namespace keel::lie;
namespace testkit = keel::testkit;

static_assert(LieGroup<SO2> && LieGroup<SO3> && LieGroup<SE2> && LieGroup<SE3>);

namespace {

template <class G>
typename G::Tangent random_tangent(keel::core::Rng& rng, double scale) {
  typename G::Tangent xi;
  for (int i = 0; i < G::DoF; ++i) xi(i) = rng.uniform(-scale, scale);
  return xi;
}

// Rescales the rotational part of xi to have magnitude `angle` (direction kept).
template <class G>
typename G::Tangent with_rotation_angle(typename G::Tangent xi, double angle) {
  if constexpr (std::is_same_v<G, SO2>) {
    xi(0) = angle;
  } else if constexpr (std::is_same_v<G, SE2>) {
    xi(2) = angle;
  } else if constexpr (std::is_same_v<G, SO3>) {
    xi = xi.normalized() * angle;
  } else {
    xi.template tail<3>() = xi.template tail<3>().normalized() * angle;
  }
  return xi;
}

// Random tangent with rotation angle uniformly in [0, max_angle].
template <class G>
typename G::Tangent random_tangent_bounded(keel::core::Rng& rng, double trans_scale, double max_angle) {
  typename G::Tangent xi = random_tangent<G>(rng, trans_scale);
  double a = rng.uniform(0.0, max_angle);
  if constexpr (std::is_same_v<G, SO2> || std::is_same_v<G, SE2>)
    a *= (rng.uniform(-1.0, 1.0) < 0 ? -1.0 : 1.0);
  if constexpr (std::is_same_v<G, SO3>) xi = random_tangent<G>(rng, 1.0);
  return with_rotation_angle<G>(xi, a);
}

template <class G>
typename G::Point random_point(keel::core::Rng& rng) {
  typename G::Point p;
  for (int i = 0; i < p.size(); ++i) p(i) = rng.uniform(-3.0, 3.0);
  return p;
}

// eq. 5.7 evaluated literally (truncated power series of the matrix exponential).
template <class M>
M matrix_exponential_series(const M& A) {
  M sum = M::Identity();
  M term = M::Identity();
  for (int k = 1; k < 60; ++k) {
    term = (term * A / static_cast<double>(k)).eval();
    sum += term;
  }
  return sum;
}

}  // namespace

TEST_CASE_TEMPLATE("group axioms", G, SO2, SO3, SE2, SE3) {
  keel::core::Rng rng(1);
  for (int trial = 0; trial < 50; ++trial) {
    const G A = G::exp(random_tangent_bounded<G>(rng, 3.0, 3.0));
    const G B = G::exp(random_tangent_bounded<G>(rng, 3.0, 3.0));
    const G C = G::exp(random_tangent_bounded<G>(rng, 3.0, 3.0));
    CHECK(((A * B) * C).is_approx(A * (B * C), 1e-12));
    CHECK((A * G::identity()).is_approx(A, 1e-14));
    CHECK((G::identity() * A).is_approx(A, 1e-14));
    CHECK((A * A.inverse()).is_approx(G::identity(), 1e-13));
    CHECK((A.inverse() * A).is_approx(G::identity(), 1e-13));
    // Group product is the matrix product.
    CHECK(((A * B).matrix() - A.matrix() * B.matrix()).norm() < 1e-12);
    CHECK((A.inverse().matrix() - A.matrix().inverse()).norm() < 1e-12);
  }
  CHECK(G::identity().matrix().isApprox(G::MatrixType::Identity()));
}

TEST_CASE_TEMPLATE("exp matches the matrix power series (eq. 5.7) and hat/vee round trip", G, SO2, SO3, SE2,
                   SE3) {
  keel::core::Rng rng(2);
  for (int trial = 0; trial < 50; ++trial) {
    const typename G::Tangent xi = random_tangent_bounded<G>(rng, 2.0, 3.0);
    const typename G::MatrixType X = G::hat(xi);
    CHECK((G::vee(X) - xi).norm() < 1e-15);
    CHECK((G::exp(xi).matrix() - matrix_exponential_series(X)).norm() < 1e-11);
  }
}

TEST_CASE_TEMPLATE("exp/log round trips (random, near 0, near pi)", G, SO2, SO3, SE2, SE3) {
  keel::core::Rng rng(3);
  for (int trial = 0; trial < 100; ++trial) {
    const typename G::Tangent xi = random_tangent_bounded<G>(rng, 3.0, 3.1);
    CHECK((G::exp(xi).log() - xi).norm() < 1e-12);
    const G T = G::exp(xi);
    CHECK(G::exp(T.log()).is_approx(T, 1e-12));
  }
  for (const double angle : {1e-9, 1e-6, 1e-3, kPi - 1e-3, kPi - 1e-6, kPi - 1e-9}) {
    CAPTURE(angle);
    for (int trial = 0; trial < 20; ++trial) {
      for (const double tscale : {1e-9, 1.0}) {
        const typename G::Tangent xi = with_rotation_angle<G>(random_tangent<G>(rng, tscale), angle);
        const typename G::Tangent back = G::exp(xi).log();
        CHECK((back - xi).norm() <= 1e-12 * xi.norm() + 1e-15);
      }
    }
  }
  // Exactly zero.
  CHECK(G::exp(G::Tangent::Zero()).is_approx(G::identity(), 0.0));
  CHECK(G::identity().log().norm() == 0.0);
}

TEST_CASE_TEMPLATE("Jacobians against central differences of their defining relations", G, SO2, SO3, SE2,
                   SE3) {
  keel::core::Rng rng(4);
  using Tan = typename G::Tangent;
  using Jac = typename G::Jacobian;
  std::vector<Tan> points;
  for (int i = 0; i < 20; ++i) points.push_back(random_tangent_bounded<G>(rng, 2.0, 2.8));
  for (const double angle : {0.0, 1e-9, 1e-6, 1e-3, 0.5, kPi - 1e-2}) {
    points.push_back(with_rotation_angle<G>(random_tangent<G>(rng, 1.0), angle));
  }
  for (const Tan& xi : points) {
    CAPTURE(xi.transpose());
    const G T = G::exp(xi);
    const G Ti = T.inverse();
    // exp(xi + d) ~= exp(J_l d) exp(xi)
    const Jac Jl_num = testkit::numerical_jacobian_tangent<G>(
        [&](const Tan& d) { return (G::exp(Tan(xi + d)) * Ti).log(); });
    CHECK((G::left_jacobian(xi) - Jl_num).norm() < 1e-8);
    // exp(xi + d) ~= exp(xi) exp(J_r d)
    const Jac Jr_num = testkit::numerical_jacobian_tangent<G>(
        [&](const Tan& d) { return (Ti * G::exp(Tan(xi + d))).log(); });
    CHECK((G::right_jacobian(xi) - Jr_num).norm() < 1e-8);
    // log(exp(e) exp(xi)) ~= xi + J_l^-1 e
    const Jac Jli_num =
        testkit::numerical_jacobian_tangent<G>([&](const Tan& e) { return (G::exp(e) * T).log(); });
    CHECK((G::left_jacobian_inverse(xi) - Jli_num).norm() < 1e-8);
    // log(exp(xi) exp(e)) ~= xi + J_r^-1 e
    const Jac Jri_num =
        testkit::numerical_jacobian_tangent<G>([&](const Tan& e) { return (T * G::exp(e)).log(); });
    CHECK((G::right_jacobian_inverse(xi) - Jri_num).norm() < 1e-8);
    // Inverses are inverses.
    CHECK((G::left_jacobian(xi) * G::left_jacobian_inverse(xi) - Jac::Identity()).norm() < 1e-12);
    CHECK((G::right_jacobian(xi) * G::right_jacobian_inverse(xi) - Jac::Identity()).norm() < 1e-12);
    // J_l(xi) = Ad_{exp(xi)} J_r(xi)
    CHECK((G::left_jacobian(xi) - T.adjoint() * G::right_jacobian(xi)).norm() < 1e-12);
  }
}

TEST_CASE_TEMPLATE("optional Jacobian outputs (left perturbations)", G, SO2, SO3, SE2, SE3) {
  keel::core::Rng rng(5);
  using Tan = typename G::Tangent;
  using Jac = typename G::Jacobian;
  using PJ = typename G::PointJacobian;
  for (int trial = 0; trial < 20; ++trial) {
    const Tan xi = random_tangent_bounded<G>(rng, 2.0, 2.8);
    const G A = G::exp(xi);
    const G B = G::exp(random_tangent_bounded<G>(rng, 2.0, 2.8));
    const typename G::Point p = random_point<G>(rng);
    Jac J1, J2;
    // exp
    G::exp(xi, &J1);
    CHECK((J1 - testkit::numerical_jacobian_tangent<G>([&](const Tan& d) {
             return (G::exp(Tan(xi + d)) * A.inverse()).log();
           })).norm() < 1e-8);
    // log
    A.log(&J1);
    CHECK((J1 - testkit::numerical_jacobian_tangent<G>([&](const Tan& e) {
             return (G::exp(e) * A).log();
           })).norm() < 1e-8);
    // inverse: (exp(e) A)^-1 = exp(J e) A^-1
    A.inverse(&J1);
    CHECK((J1 - testkit::numerical_jacobian_tangent<G>([&](const Tan& e) {
             return ((G::exp(e) * A).inverse() * A).log();
           })).norm() < 1e-8);
    // compose
    const G AB = A.compose(B, &J1, &J2);
    CHECK(AB.is_approx(A * B, 1e-15));
    const G ABi = AB.inverse();
    CHECK((J1 - testkit::numerical_jacobian_tangent<G>([&](const Tan& e) {
             return (G::exp(e) * A * B * ABi).log();
           })).norm() < 1e-8);
    CHECK((J2 - testkit::numerical_jacobian_tangent<G>([&](const Tan& e) {
             return (A * G::exp(e) * B * ABi).log();
           })).norm() < 1e-8);
    // act
    PJ Jt;
    Eigen::Matrix<double, G::Point::RowsAtCompileTime, G::Point::RowsAtCompileTime> Jp;
    A.act(p, &Jt, &Jp);
    CHECK((Jt - testkit::numerical_jacobian_tangent<G>([&](const Tan& e) {
             return (G::exp(e) * A).act(p);
           })).norm() < 1e-8);
    const testkit::VecX p0 = p;
    CHECK((Jp - testkit::numerical_jacobian(
                    [&](const testkit::VecX& q) { return A.act(typename G::Point(q)); }, p0))
              .norm() < 1e-8);
  }
}

TEST_CASE_TEMPLATE("adjoint identity T exp(xi) T^-1 = exp(Ad_T xi) (eq. 5.10)", G, SO2, SO3, SE2, SE3) {
  keel::core::Rng rng(6);
  for (int trial = 0; trial < 50; ++trial) {
    const G T = G::exp(random_tangent_bounded<G>(rng, 3.0, 3.0));
    const typename G::Tangent xi = random_tangent_bounded<G>(rng, 1.0, 1.0);
    CHECK((T * G::exp(xi) * T.inverse()).is_approx(G::exp(T.adjoint() * xi), 1e-12));
    CHECK((T * G::exp(xi)).is_approx(G::exp(T.adjoint() * xi) * T, 1e-12));
    // Ad is a homomorphism.
    const G S = G::exp(random_tangent_bounded<G>(rng, 3.0, 3.0));
    CHECK(((T * S).adjoint() - T.adjoint() * S.adjoint()).norm() < 1e-12);
    CHECK((T.inverse().adjoint() - T.adjoint().inverse()).norm() < 1e-11);
  }
}

TEST_CASE_TEMPLATE("action on points", G, SO2, SO3, SE2, SE3) {
  keel::core::Rng rng(7);
  constexpr int P = G::Point::RowsAtCompileTime;
  for (int trial = 0; trial < 50; ++trial) {
    const G A = G::exp(random_tangent_bounded<G>(rng, 3.0, 3.0));
    const G B = G::exp(random_tangent_bounded<G>(rng, 3.0, 3.0));
    const typename G::Point p = random_point<G>(rng);
    typename G::Point expected;
    if constexpr (G::Dim == P) {
      expected = A.matrix() * p;  // rotation groups
    } else {
      Eigen::Matrix<double, P + 1, 1> h;
      h << p, 1.0;
      expected = (A.matrix() * h).template head<P>();
    }
    CHECK((A.act(p) - expected).norm() < 1e-12);
    CHECK((A * p - expected).norm() < 1e-12);
    CHECK(((A * B) * p - A * (B * p)).norm() < 1e-12);
    CHECK((A.inverse() * (A * p) - p).norm() < 1e-12);
    // Rigid: distances preserved.
    const typename G::Point q = random_point<G>(rng);
    CHECK(std::abs((A * p - A * q).norm() - (p - q).norm()) < 1e-12);
  }
}

TEST_CASE_TEMPLATE("from_matrix validates and round-trips", G, SO2, SO3, SE2, SE3) {
  keel::core::Rng rng(8);
  for (int trial = 0; trial < 20; ++trial) {
    const G A = G::exp(random_tangent_bounded<G>(rng, 3.0, 3.0));
    CHECK(G::from_matrix(A.matrix()).is_approx(A, 1e-14));
  }
  constexpr int R = G::Point::RowsAtCompileTime;
  const G A = G::exp(random_tangent_bounded<G>(rng, 3.0, 3.0));
  // Scaled rotation block: not orthonormal.
  typename G::MatrixType M = A.matrix();
  M.template topLeftCorner<R, R>() *= 1.1;
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)G::from_matrix(M); }, "not orthonormal"));
  // Reflection.
  M = A.matrix();
  M.template topLeftCorner<R, R>().col(0) *= -1.0;
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)G::from_matrix(M); }, "det(R) <= 0"));
  // Non-finite.
  M = A.matrix();
  M(0, 0) = std::nan("");
  CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)G::from_matrix(M); }, "non-finite"));
  if constexpr (G::Dim != R) {
    M = A.matrix();
    M(G::Dim - 1, 0) = 0.5;
    CHECK(testkit::throws_with<std::invalid_argument>([&] { (void)G::from_matrix(M); }, "bottom row"));
  }
  // Slightly perturbed (6 printed digits) matrices are accepted and projected onto the group.
  M = A.matrix();
  M(0, 0) += 3e-7;
  const G P = G::from_matrix(M);
  const typename G::MatrixType PM = P.matrix();
  const Eigen::Matrix<double, R, R> Rp = PM.template topLeftCorner<R, R>();
  CHECK((Rp.transpose() * Rp - Eigen::Matrix<double, R, R>::Identity()).norm() < 1e-14);
  CHECK(P.is_approx(A, 1e-6));
}

TEST_CASE("SO3 log near pi picks the axis from the symmetric part") {
  // Rotation by exactly pi about a generic axis, and just below pi: log must return an angle
  // in [0, pi] about the right axis (up to the sign ambiguity at exactly pi).
  const Vec3 axis = Vec3(1.0, -2.0, 0.5).normalized();
  const SO3 R = SO3::exp(kPi * axis);
  const Vec3 phi = R.log();
  CHECK(std::abs(phi.norm() - kPi) < 1e-14);
  CHECK(std::abs(std::abs(phi.normalized().dot(axis)) - 1.0) < 1e-14);
  CHECK(SO3::exp(phi).is_approx(R, 1e-14));
  for (const double eps : {1e-4, 1e-8, 1e-12}) {
    const Vec3 xi = (kPi - eps) * axis;
    CHECK((SO3::exp(xi).log() - xi).norm() < 1e-13);
    CHECK((SO3::exp(-xi).log() + xi).norm() < 1e-13);
  }
}

TEST_CASE("SE3 adjoint and left Jacobian block structure") {
  const Vec3 t(1.0, -2.0, 0.3);
  const SE3 T(SO3::exp(Vec3(0.1, 0.2, -0.3)), t);
  const Mat6 Ad = T.adjoint();
  CHECK(Ad.topLeftCorner<3, 3>().isApprox(T.rotation()));
  CHECK(Ad.bottomLeftCorner<3, 3>().isZero());
  CHECK(Ad.topRightCorner<3, 3>().isApprox(SO3::hat(t) * T.rotation()));
  // Q block at small phi tends to rho^/2.
  const Vec3 rho(0.3, -0.1, 0.7);
  CHECK((SE3::q_block(rho, Vec3::Zero()) - 0.5 * SO3::hat(rho)).norm() < 1e-15);
  // curly hat: Ad_{exp(xi)} = exp(curly_hat(xi)).
  Vec6 xi;
  xi << 0.2, -0.4, 0.1, 0.3, -0.2, 0.5;
  CHECK((SE3::exp(xi).adjoint() - matrix_exponential_series(SE3::curly_hat(xi))).norm() < 1e-12);
}
