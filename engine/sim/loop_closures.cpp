#include "sim/loop_closures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "sim/random_pose.hpp"

namespace keel::sim {

void LoopClosureCorruption::validate() const {
  if (first_poses < 0)
    throw std::invalid_argument(
        fmt::format("LoopClosureCorruption.first_poses = {}: must be >= 0 (0: every pose)", first_poses));
  if (!(rotation_noise >= 0) || !std::isfinite(rotation_noise))
    throw std::invalid_argument(fmt::format(
        "LoopClosureCorruption.rotation_noise = {}: must be a finite angle >= 0 (rad)", rotation_noise));
  if (!(outlier_fraction >= 0 && outlier_fraction <= 1))
    throw std::invalid_argument(
        fmt::format("LoopClosureCorruption.outlier_fraction = {}: must be in [0, 1]", outlier_fraction));
}

namespace {

lie::SE2 noisy(const lie::SE2& z, double sigma, core::Rng& rng) {
  const double n = rng.normal();
  return lie::SE2(lie::SO2(z.angle() + sigma * n), z.translation());
}
lie::SE3 noisy(const lie::SE3& z, double sigma, core::Rng& rng) {
  lie::Vec3 n;
  for (int k = 0; k < 3; ++k) n(k) = rng.normal();
  return lie::SE3(z.so3() * lie::SO3::exp(sigma * n), z.translation());
}

template <class Graph>
CorruptedGraph<Graph> corrupt(const Graph& g, const LoopClosureCorruption& o, const core::Streams& streams,
                              std::uint64_t index) {
  o.validate();
  using Pose = std::remove_cvref_t<decltype(g.poses[0])>;
  constexpr int kDim = std::is_same_v<Pose, lie::SE2> ? 2 : 3;
  if constexpr (kDim == 2) {
    if (!g.landmarks.empty() || !g.landmark_measurements.empty())
      throw std::invalid_argument(fmt::format(
          "corrupt_loop_closures: {} has landmarks (pose graphs without landmarks only)", g.source));
  }
  const int n = static_cast<int>(g.poses.size());
  if (o.first_poses > n)
    throw std::invalid_argument(fmt::format("corrupt_loop_closures: first_poses = {} but {} has {} poses",
                                            o.first_poses, g.source, n));
  const int keep = o.first_poses == 0 ? n : o.first_poses;
  CorruptedGraph<Graph> out;
  Graph& h = out.graph;
  h.poses.assign(g.poses.begin(), g.poses.begin() + keep);
  h.has_initial_poses = g.has_initial_poses;
  h.indefinite_information = g.indefinite_information;  // the source's count (a bound for a subset)
  h.gauge_pose = g.gauge_pose < keep ? g.gauge_pose : 0;
  h.source = g.source;
  for (const auto& e : g.edges) {
    if (e.i >= keep || e.j >= keep) continue;
    if (std::abs(e.i - e.j) != 1) out.loop_closures.push_back(static_cast<int>(h.edges.size()));
    h.edges.push_back(e);
  }
  // The outliers: a uniformly random ordering of the loop closures (Fisher–Yates), its first round(f·L).
  const auto L = out.loop_closures.size();
  std::vector<int> order = out.loop_closures;
  core::Rng order_rng = streams.child("order").stream(index);
  for (std::size_t k = L; k > 1; --k) {
    const auto r =
        std::min<std::size_t>(static_cast<std::size_t>(order_rng.uniform() * static_cast<double>(k)), k - 1);
    std::swap(order[k - 1], order[r]);
  }
  const auto outliers = static_cast<std::size_t>(std::llround(o.outlier_fraction * static_cast<double>(L)));
  out.outliers.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(outliers));
  std::sort(out.outliers.begin(), out.outliers.end());
  std::vector<char> is_outlier(h.edges.size(), 0);
  for (int e : out.outliers) is_outlier[static_cast<std::size_t>(e)] = 1;
  double span = 0;
  for (int e : out.loop_closures)
    span =
        std::max(span, h.edges[static_cast<std::size_t>(e)].measurement.translation().cwiseAbs().maxCoeff());
  if (!(span > 0)) span = 1;
  // Every loop closure draws its noise direction and its outlier pose, in edge order, whatever it becomes.
  core::Rng noise_rng = streams.child("noise").stream(index);
  core::Rng outlier_rng = streams.child("outlier").stream(index);
  for (int e : out.loop_closures) {
    auto& edge = h.edges[static_cast<std::size_t>(e)];
    const Pose with_noise = noisy(edge.measurement, o.rotation_noise, noise_rng);
    const auto R = detail::random_rotation(outlier_rng, static_cast<const Pose*>(nullptr));
    typename Pose::Point t;
    for (int d = 0; d < kDim; ++d) t(d) = outlier_rng.uniform(-span, span);
    edge.measurement = is_outlier[static_cast<std::size_t>(e)] ? Pose(R, t) : with_noise;
  }
  return out;
}

}  // namespace

CorruptedGraph2 corrupt_loop_closures(const graph::PoseGraph2D& g, const LoopClosureCorruption& o,
                                      const core::Streams& streams, std::uint64_t index) {
  return corrupt(g, o, streams, index);
}
CorruptedGraph3 corrupt_loop_closures(const graph::PoseGraph3D& g, const LoopClosureCorruption& o,
                                      const core::Streams& streams, std::uint64_t index) {
  return corrupt(g, o, streams, index);
}

}  // namespace keel::sim
