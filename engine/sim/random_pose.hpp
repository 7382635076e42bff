// Uniform random rotations and measurement noise, shared by the generators of engine/sim.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>

#include "core/random.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"

namespace keel::sim::detail {

// Rotation uniform on SO(2) / SO(3) (3D: the unit quaternion of four standard normals, which is uniform on
// S³). The pointer argument only selects the group.
inline lie::SO2 random_rotation(core::Rng& rng, const lie::SE2*) {
  return lie::SO2(rng.uniform(-lie::kPi, lie::kPi));
}
inline lie::SO3 random_rotation(core::Rng& rng, const lie::SE3*) {
  double w, x, y, z, n;
  do {
    w = rng.normal();
    x = rng.normal();
    y = rng.normal();
    z = rng.normal();
    n = std::sqrt(w * w + x * x + y * y + z * z);
  } while (n < 1e-12);
  w /= n;
  x /= n;
  y /= n;
  z /= n;
  lie::Mat3 R;
  R << 1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),  //
      2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),   //
      2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y);
  return lie::SO3::from_matrix_unchecked(R);
}

// ρ⁻¹: the pose whose residual parameterization (graph/pose_graph.hpp) is r.
inline lie::SE2 from_residual(const lie::Vec3& r) { return lie::SE2(r(0), r(1), r(2)); }
inline lie::SE3 from_residual(const lie::Vec6& r) {
  return lie::SE3(lie::SO3::exp(r.tail<3>()), r.head<3>());
}

// A draw of N(0, C) from the lower Cholesky factor of C.
template <class Mat>
auto normal_sample(core::Rng& rng, const Mat& lower) {
  typename Eigen::Matrix<double, Mat::RowsAtCompileTime, 1> n;
  for (int k = 0; k < n.size(); ++k) n(k) = rng.normal();
  return (lower * n).eval();
}

// A residual draw r ~ N(0, s² Ω⁻¹) and the measurement X ρ⁻¹(r)⁻¹ whose residual at the true relative pose X
// is r.
template <class G>
G redraw(core::Rng& rng, const G& X, const typename G::Jacobian& info, double scale) {
  using J = typename G::Jacobian;
  const J cov = info.ldlt().solve(J::Identity());
  const J L = Eigen::LLT<J>(0.5 * (cov + cov.transpose())).matrixL();
  const typename G::Tangent r = scale * normal_sample(rng, L);
  return X * from_residual(r).inverse();
}

}  // namespace keel::sim::detail
