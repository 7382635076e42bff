// Initial estimates (Options::initial_guess, anchor_guess) and the global-pose helpers.
#include <Eigen/Geometry>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/random.hpp"
#include "pgo/internal.hpp"

namespace keel::pgo {

namespace detail {

namespace {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(fmt::format("pgo: {}", what)); }

std::string name_of(const std::string& source) {
  return source.empty() ? std::string("<unnamed graph>") : fmt::format("'{}'", source);
}

lie::SE2 random_pose(core::Rng& rng, double extent, const lie::SE2*) {
  const double x = rng.uniform(-extent, extent);
  const double y = rng.uniform(-extent, extent);
  const double th = rng.uniform(-lie::kPi, lie::kPi);
  return lie::SE2(x, y, th);
}

lie::SE3 random_pose(core::Rng& rng, double extent, const lie::SE3*) {
  lie::Vec3 t;
  for (int k = 0; k < 3; ++k) t(k) = rng.uniform(-extent, extent);
  // Uniform rotation: a normalized 4-vector of independent normals is uniform on S³.
  Eigen::Vector4d q;
  do {
    for (int k = 0; k < 4; ++k) q(k) = rng.normal();
  } while (q.norm() < 1e-12);
  const Eigen::Quaterniond quat(q(3), q(0), q(1), q(2));
  return lie::SE3(lie::SO3::from_matrix_unchecked(quat.normalized().toRotationMatrix()), t);
}

// Odometry chain of one robot from its root pose (the first of Options::constant_poses, pose 0 by default, so
// that the gauge keeps its as-read value): T_root as read (identity if none), then T_k = T_{k−1} z_{k−1,k}
// outward using the first edge between k−1 and k in the file (inverted if it is stored as (k, k−1)). Where
// the chain has a gap (no edge between k−1 and k), the poses beyond it are placed along a spanning tree, as
// g2o's initial guess does: a 0-1 breadth-first search from the root in which those odometry steps cost 0
// and every other edge 1, so each pose is reached through as few non-odometry edges as possible (and a graph
// whose chain is complete gets exactly the chain). A pose that no edge path reaches from the root is an
// error naming it.
template <class D>
std::vector<typename D::Pose> odometry_chain(const typename D::Graph& g, int n, int root) {
  using Pose = typename D::Pose;
  std::vector<Pose> poses(n);
  if (n == 0) return poses;
  // The odometry step of each k−1 → k: the index of the first edge between them in the file.
  std::vector<int> step(n > 0 ? n - 1 : 0, -1);
  for (std::size_t q = 0; q < g.edges.size(); ++q) {
    const auto& e = g.edges[q];
    if (e.j == e.i + 1 && step[e.i] < 0)
      step[e.i] = static_cast<int>(q);
    else if (e.i == e.j + 1 && step[e.j] < 0)
      step[e.j] = static_cast<int>(q);
  }
  std::vector<std::vector<int>> incident(n);
  for (std::size_t q = 0; q < g.edges.size(); ++q) {
    const auto& e = g.edges[q];
    if (e.i < n && e.j < n && e.i != e.j) {
      incident[e.i].push_back(static_cast<int>(q));
      incident[e.j].push_back(static_cast<int>(q));
    }
  }
  auto is_step = [&](int q) {
    const auto& e = g.edges[static_cast<std::size_t>(q)];
    const int lo = std::min(e.i, e.j);
    return std::abs(e.i - e.j) == 1 && step[lo] == q;
  };
  std::vector<int> dist(n, -1);
  std::vector<char> done(n, 0);
  std::deque<int> queue;
  poses[root] = root < static_cast<int>(g.poses.size()) ? g.poses[root] : Pose();
  dist[root] = 0;
  queue.push_back(root);
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop_front();
    if (done[v]) continue;
    done[v] = 1;
    for (const int q : incident[v]) {
      const auto& e = g.edges[static_cast<std::size_t>(q)];
      const int w = e.i == v ? e.j : e.i;
      const int cost = dist[v] + (is_step(q) ? 0 : 1);
      if (done[w] || (dist[w] >= 0 && dist[w] <= cost)) continue;
      dist[w] = cost;
      // z_e = T_i⁻¹ T_j: from v = i, T_j = T_i z; from v = j, T_i = T_j z⁻¹.
      poses[w] = e.i == v ? poses[v] * e.measurement : poses[v] * e.measurement.inverse();
      if (is_step(q)) {
        queue.push_front(w);
      } else {
        queue.push_back(w);
      }
    }
  }
  for (int k = 0; k < n; ++k)
    if (!done[k])
      fail(fmt::format("initial_guess = odometry: pose {} of {} is not connected to pose {} by any edge", k,
                       name_of(g.source), root));
  return poses;
}

template <class D>
typename D::Estimate robot_initial(const typename D::Graph& g, int robot, const Options& o,
                                   const typename D::Estimate* supplied) {
  using Pose = typename D::Pose;
  const int n = pose_count(g);
  typename D::Estimate est;
  switch (o.initial_guess) {
    case InitialGuess::as_read:
      if (static_cast<int>(g.poses.size()) != n)
        fail(
            fmt::format("initial_guess = as_read: {} stores {} poses but its measurements use {} (choose "
                        "initial_guess = odometry?)",
                        name_of(g.source), g.poses.size(), n));
      est.poses = g.poses;
      break;
    case InitialGuess::odometry:
      est.poses = odometry_chain<D>(
          g, n,
          !o.constant_poses.empty() && o.constant_poses.front() >= 0 && o.constant_poses.front() < n
              ? o.constant_poses.front()
              : 0);
      break;
    case InitialGuess::supplied:
      if (!supplied) fail("initial_guess = supplied but no estimate was supplied");
      if (static_cast<int>(supplied->poses.size()) != n)
        fail(fmt::format("initial_guess = supplied: the estimate of robot {} has {} poses, the graph {}",
                         robot, supplied->poses.size(), n));
      est.poses = supplied->poses;
      break;
    case InitialGuess::random: {
      core::Rng rng = core::Rng::stream(o.seed, static_cast<std::uint64_t>(robot));
      est.poses.resize(n);
      for (auto& T : est.poses) T = random_pose(rng, o.random_extent, static_cast<const Pose*>(nullptr));
      for (int k : o.constant_poses)
        if (k >= 0 && k < n) est.poses[k] = k < static_cast<int>(g.poses.size()) ? g.poses[k] : Pose();
      break;
    }
  }
  if constexpr (D::kLandmarks) {
    const int m = landmark_count(g);
    if (o.initial_guess == InitialGuess::as_read && static_cast<int>(g.landmarks.size()) == m) {
      est.landmarks = g.landmarks;
    } else if (o.initial_guess == InitialGuess::supplied &&
               static_cast<int>(supplied->landmarks.size()) == m) {
      est.landmarks = supplied->landmarks;
    } else {
      est.landmarks.assign(m, lie::Vec2::Zero());
      std::vector<char> set(m, 0);
      for (const auto& lm : g.landmark_measurements)
        if (!set[lm.landmark]) {
          est.landmarks[lm.landmark] = est.poses[lm.pose] * lm.position;
          set[lm.landmark] = 1;
        }
    }
  }
  return est;
}

}  // namespace

template <class D>
typename D::MultiEstimate initial_view(const RobotsView<D>& view,
                                       const std::vector<typename D::Pose>& given_anchors, const Options& o,
                                       const typename D::MultiEstimate* supplied) {
  using Pose = typename D::Pose;
  o.validate();
  validate_graph(view);
  const int robots = static_cast<int>(view.robots.size());
  if (o.initial_guess == InitialGuess::supplied) {
    if (!supplied) fail("initial_guess = supplied but no estimate was supplied");
    if (static_cast<int>(supplied->robots.size()) != robots)
      fail(fmt::format("initial_guess = supplied: the estimate has {} robots, the graph {}",
                       supplied->robots.size(), robots));
  }
  typename D::MultiEstimate est;
  for (int r = 0; r < robots; ++r)
    est.robots.push_back(robot_initial<D>(*view.robots[r], r, o, supplied ? &supplied->robots[r] : nullptr));

  if (!view.with_anchors) {
    est.anchors.assign(1, Pose());
    return est;
  }
  if (o.initial_guess == InitialGuess::supplied && static_cast<int>(supplied->anchors.size()) == robots) {
    est.anchors = supplied->anchors;
    return est;
  }
  if (!given_anchors.empty() && static_cast<int>(given_anchors.size()) != robots)
    fail(fmt::format("the graph has {} anchors for {} robots (give one per robot, or none)",
                     given_anchors.size(), robots));
  est.anchors = given_anchors.empty() ? std::vector<Pose>(robots) : given_anchors;
  if (o.anchor_guess == AnchorGuess::inter_robot_edges && view.inter) {
    std::vector<char> placed(robots, 0);
    if (robots > 0) placed[0] = 1;
    for (bool progress = true; progress;) {
      progress = false;
      for (const auto& e : *view.inter) {
        const auto& Ti = est.robots[e.robot_a].poses[e.pose_a];
        const auto& Tj = est.robots[e.robot_b].poses[e.pose_b];
        if (placed[e.robot_a] && !placed[e.robot_b]) {  // z ≈ (Δa Ti)⁻¹ Δb Tj  ⇒  Δb = Δa Ti z Tj⁻¹
          est.anchors[e.robot_b] = est.anchors[e.robot_a] * Ti * e.measurement * Tj.inverse();
          placed[e.robot_b] = progress = true;
        } else if (placed[e.robot_b] && !placed[e.robot_a]) {  // Δa = Δb Tj z⁻¹ Ti⁻¹
          est.anchors[e.robot_a] = est.anchors[e.robot_b] * Tj * e.measurement.inverse() * Ti.inverse();
          placed[e.robot_a] = progress = true;
        }
      }
    }
  }
  return est;
}

template D2::MultiEstimate initial_view<D2>(const RobotsView<D2>&, const std::vector<lie::SE2>&,
                                            const Options&, const D2::MultiEstimate*);
template D3::MultiEstimate initial_view<D3>(const RobotsView<D3>&, const std::vector<lie::SE3>&,
                                            const Options&, const D3::MultiEstimate*);

}  // namespace detail

namespace {

template <class D>
typename D::MultiEstimate wrap_single(const typename D::Estimate* supplied) {
  typename D::MultiEstimate m;
  if (supplied) m.robots.push_back(*supplied);
  return m;
}

}  // namespace

Estimate2D initial_estimate(const graph::PoseGraph2D& graph, const Options& options,
                            const Estimate2D* supplied) {
  const auto m = supplied ? wrap_single<detail::D2>(supplied) : MultiRobotEstimate2D{};
  auto est = detail::initial_view<detail::D2>(detail::view_of(graph), {}, options, supplied ? &m : nullptr);
  return std::move(est.robots[0]);
}

Estimate3D initial_estimate(const graph::PoseGraph3D& graph, const Options& options,
                            const Estimate3D* supplied) {
  const auto m = supplied ? wrap_single<detail::D3>(supplied) : MultiRobotEstimate3D{};
  auto est = detail::initial_view<detail::D3>(detail::view_of(graph), {}, options, supplied ? &m : nullptr);
  return std::move(est.robots[0]);
}

MultiRobotEstimate2D initial_estimate(const MultiRobotGraph2D& graph, const Options& options,
                                      const MultiRobotEstimate2D* supplied) {
  return detail::initial_view<detail::D2>(detail::view_of(graph), graph.anchors, options, supplied);
}

MultiRobotEstimate3D initial_estimate(const MultiRobotGraph3D& graph, const Options& options,
                                      const MultiRobotEstimate3D* supplied) {
  return detail::initial_view<detail::D3>(detail::view_of(graph), graph.anchors, options, supplied);
}

namespace {

template <class E>
auto global_poses_impl(const E& estimate, int robot) {
  if (robot < 0 || robot >= static_cast<int>(estimate.robots.size()) ||
      estimate.anchors.size() != estimate.robots.size())
    throw std::invalid_argument(fmt::format(
        "pgo::global_poses: robot {} out of range, or anchors and robots differ in number", robot));
  auto poses = estimate.robots[robot].poses;
  for (auto& T : poses) T = estimate.anchors[robot] * T;
  return poses;
}

}  // namespace

std::vector<lie::SE2> global_poses(const MultiRobotEstimate2D& estimate, int robot) {
  return global_poses_impl(estimate, robot);
}
std::vector<lie::SE3> global_poses(const MultiRobotEstimate3D& estimate, int robot) {
  return global_poses_impl(estimate, robot);
}
std::vector<lie::Vec2> global_landmarks(const MultiRobotEstimate2D& estimate, int robot) {
  global_poses_impl(estimate, robot);  // range checks
  auto lms = estimate.robots[robot].landmarks;
  for (auto& l : lms) l = estimate.anchors[robot] * l;
  return lms;
}

}  // namespace keel::pgo
