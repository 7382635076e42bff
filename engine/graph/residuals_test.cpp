// The one edge residual per dimension (graph/residuals.hpp) against the group operations it stands for:
// ρ(z⁻¹ T_i⁻¹ T_j) composed with lie's SE2/SE3 and its SO3 logarithm, at random poses (E far from the
// identity), next to the angle π and next to the identity; its 2D parameter Jacobians against central
// differences.
#include <doctest/doctest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>

#include "graph/residuals.hpp"
#include "kit/test_kit.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/so3.hpp"

using namespace keel;
using graph::SE2;
using graph::SE3;

namespace {

// Angle difference in (−π, π]: two angles that both represent π may differ by 2π.
double angle_gap(double a, double b) { return std::abs(lie::wrap_angle(a - b)); }

}  // namespace

TEST_CASE("2D edge residual is ρ(z⁻¹ T_i⁻¹ T_j) of the group operations") {
  core::Rng rng(31);
  for (int trial = 0; trial < 500; ++trial) {
    const SE2 Ti = testkit::random_pose<SE2>(rng, 3.0, 50.0), Tj = testkit::random_pose<SE2>(rng, 3.0, 50.0);
    const SE2 z = testkit::random_pose<SE2>(rng, 3.0, 20.0);
    const SE2 E = z.inverse() * (Ti.inverse() * Tj);
    const lie::Vec3 r = graph::edge_residual(z, Ti, Tj);
    CHECK((r.head<2>() - E.translation()).norm() < 1e-11);
    CHECK(angle_gap(r(2), E.angle()) < 1e-12);
    CHECK(r(2) > -lie::kPi);
    CHECK(r(2) <= lie::kPi);
  }
}

TEST_CASE("2D edge residual: parameter Jacobians match central differences") {
  core::Rng rng(32);
  constexpr double h = 1e-6;
  for (int trial = 0; trial < 200; ++trial) {
    const SE2 z = testkit::random_pose<SE2>(rng, 3.0, 20.0);
    const graph::EdgeMeasurement2 m(z);
    std::array<double, 3> p_i = graph::pose_parameters(testkit::random_pose<SE2>(rng, 3.0, 50.0));
    std::array<double, 3> p_j = graph::pose_parameters(testkit::random_pose<SE2>(rng, 3.0, 50.0));
    lie::Vec3 r;
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> J_i, J_j;
    graph::edge_residual(m, p_i.data(), p_j.data(), r.data(), J_i.data(), J_j.data());
    if (std::abs(r(2)) > 3.0) continue;  // a step across ±π would wrap the angle
    for (int side = 0; side < 2; ++side) {
      auto& p = side == 0 ? p_i : p_j;
      const auto& J = side == 0 ? J_i : J_j;
      for (int k = 0; k < 3; ++k) {
        const double keep = p[static_cast<std::size_t>(k)];
        lie::Vec3 plus, minus;
        p[static_cast<std::size_t>(k)] = keep + h;
        graph::edge_residual(m, p_i.data(), p_j.data(), plus.data());
        p[static_cast<std::size_t>(k)] = keep - h;
        graph::edge_residual(m, p_i.data(), p_j.data(), minus.data());
        p[static_cast<std::size_t>(k)] = keep;
        const lie::Vec3 numeric = (plus - minus) / (2 * h);
        CHECK((J.col(k) - numeric).norm() < 1e-6 * std::max(1.0, numeric.norm()));
      }
    }
  }
}

TEST_CASE("3D edge residual is (t_E, Log R_E) of the group operations") {
  core::Rng rng(33);
  for (int trial = 0; trial < 500; ++trial) {
    const SE3 Ti = testkit::random_pose<SE3>(rng, 2.5, 30.0), Tj = testkit::random_pose<SE3>(rng, 2.5, 30.0);
    const SE3 z = testkit::random_pose<SE3>(rng, 2.5, 10.0);
    const SE3 E = z.inverse() * (Ti.inverse() * Tj);
    const lie::Vec6 r = graph::edge_residual(z, Ti, Tj);
    CHECK((r.head<3>() - E.translation()).norm() < 1e-10);
    const lie::Vec3 phi = E.so3().log();
    if (phi.norm() < lie::kPi - 1e-6)
      CHECK((r.tail<3>() - phi).norm() < 1e-10);  // at π, φ and −φ are both logs
    CHECK(r.tail<3>().norm() <= lie::kPi + 1e-15);
    CHECK((lie::SO3::exp(r.tail<3>()).matrix() - E.rotation()).norm() < 1e-10);
  }
}

TEST_CASE("3D edge residual next to the angle π and next to the identity") {
  core::Rng rng(34);
  for (const double angle : {lie::kPi - 1e-9, lie::kPi - 1e-4, 1e-3, 1e-9, 0.0}) {
    for (int trial = 0; trial < 50; ++trial) {
      const lie::Vec3 axis = testkit::random_tangent<lie::SO3>(rng, 1.0, 1.0).normalized();
      const SE3 Ti = testkit::random_pose<SE3>(rng, 2.5, 30.0);
      const SE3 z = testkit::random_pose<SE3>(rng, 2.5, 10.0);
      const SE3 E(lie::SO3::exp(angle * axis), lie::Vec3(1.0, -2.0, 3.0));
      const SE3 Tj = Ti * z * E;  // so that z⁻¹ T_i⁻¹ T_j = E
      const lie::Vec6 r = graph::edge_residual(z, Ti, Tj);
      CHECK((r.head<3>() - E.translation()).norm() < 1e-10);
      const lie::Vec3 phi = r.tail<3>();
      CHECK(std::abs(phi.norm() - angle) < 1e-7);
      if (angle > 0.0 && angle < 3.0) CHECK((phi - angle * axis).norm() < 1e-9);
      if (angle > 3.0) CHECK(std::min((phi - angle * axis).norm(), (phi + angle * axis).norm()) < 1e-6);
    }
  }
}

TEST_CASE("A quaternion and its negative give the same rotation vector, and 2v at v → 0") {
  core::Rng rng(35);
  for (int trial = 0; trial < 200; ++trial) {
    const lie::Vec3 w = testkit::random_tangent<lie::SO3>(rng, 1.0, 1.0);
    const Eigen::Quaterniond q(lie::SO3::exp(w).matrix());
    const Eigen::Quaterniond minus_q(-q.w(), -q.x(), -q.y(), -q.z());
    lie::Vec3 a, b;
    graph::quaternion_to_rotation_vector(q, a.data());
    graph::quaternion_to_rotation_vector(minus_q, b.data());
    CHECK((a - b).norm() < 1e-12);
    CHECK(a.norm() <= lie::kPi + 1e-15);
    CHECK((lie::SO3::exp(a).matrix() - lie::SO3::exp(w).matrix()).norm() < 1e-10);
  }
  const Eigen::Quaterniond tiny(1.0, 1e-200, -2e-200, 0.0);
  lie::Vec3 phi;
  graph::quaternion_to_rotation_vector(tiny, phi.data());
  CHECK(phi(0) == 2e-200);
  CHECK(phi(1) == -4e-200);
  lie::Vec3 zero;
  graph::quaternion_to_rotation_vector(Eigen::Quaterniond::Identity(), zero.data());
  CHECK(zero.norm() == 0.0);
}
