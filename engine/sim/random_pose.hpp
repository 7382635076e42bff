// Uniform random rotations, shared by the generators of engine/sim.
#pragma once

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

}  // namespace keel::sim::detail
