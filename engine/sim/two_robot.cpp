// Two-robot map-merging scenarios (thesis §2.7.2 and a 3D substitute for §2.7.3); see scenario.hpp.
#include "sim/two_robot.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "core/random.hpp"
#include "sim/random_pose.hpp"

namespace keel::sim {

using namespace keel::pcm;  // measurement types and the left-perturbation covariance

namespace {

// Throws std::invalid_argument with the formatted message, prefixed "pcm::".
template <class... A>
[[noreturn]] void fail(fmt::format_string<A...> format, A&&... args) {
  throw std::invalid_argument(fmt::format("pcm::{}", fmt::format(format, std::forward<A>(args)...)));
}

template <class M>
bool all_finite(const M& m) {
  return m.allFinite();
}

bool finite_pose(const lie::SE2& T) { return T.translation().allFinite() && std::isfinite(T.angle()); }
bool finite_pose(const lie::SE3& T) { return T.translation().allFinite() && T.rotation().allFinite(); }

using detail::from_residual;
using detail::normal_sample;
using detail::random_rotation;
using detail::redraw;

// A unit vector uniform on the circle / sphere (a normalized standard normal vector).
template <int N>
Eigen::Matrix<double, N, 1> random_direction(core::Rng& rng) {
  Eigen::Matrix<double, N, 1> v;
  do {
    for (int d = 0; d < N; ++d) v(d) = rng.normal();
  } while (v.norm() < 1e-12);
  return v.normalized();
}

// The offset δ of a near-miss alignment (CandidateOptions): translation length and rotation angle uniform in
// their ranges, directions uniform.
lie::SE2 near_miss_offset(core::Rng& rng, const CandidateOptions& o, const lie::SE2*) {
  const lie::Vec2 t =
      rng.uniform(o.near_miss_translation_min, o.near_miss_translation_max) * random_direction<2>(rng);
  const double angle = rng.uniform(o.near_miss_rotation_min, o.near_miss_rotation_max);
  return lie::SE2(lie::SO2(rng.uniform(0.0, 1.0) < 0.5 ? -angle : angle), t);
}
lie::SE3 near_miss_offset(core::Rng& rng, const CandidateOptions& o, const lie::SE3*) {
  const lie::Vec3 t =
      rng.uniform(o.near_miss_translation_min, o.near_miss_translation_max) * random_direction<3>(rng);
  const lie::Vec3 axis = random_direction<3>(rng);
  const double angle = rng.uniform(o.near_miss_rotation_min, o.near_miss_rotation_max);
  return lie::SE3(lie::SO3::exp(angle * axis), t);
}

lie::SE2 make_pose(const lie::SO2& R, const lie::Vec2& t) { return lie::SE2(R, t); }
lie::SE3 make_pose(const lie::SO3& R, const lie::Vec3& t) { return lie::SE3(R, t); }

int uniform_index(core::Rng& rng, int n) {
  const int k = static_cast<int>(rng.uniform() * n);
  return std::min(k, n - 1);
}

template <class G>
typename G::Jacobian left_cov_of_inverse(const G& z, const typename G::Jacobian& cov) {
  // z = exp(n) z̄  ⇒  z⁻¹ = z̄⁻¹ exp(−n) = exp(−Ad(z̄⁻¹) n) z̄⁻¹.
  const typename G::Jacobian Ad = z.inverse().adjoint();
  return (Ad * cov * Ad.transpose()).eval();
}

// Union–find connectivity of a local graph: the first pose not connected to pose 0, or −1.
template <class Graph>
int first_unreachable(const Graph& g, int n) {
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& e : g.edges) parent[find(e.i)] = find(e.j);
  const int root = find(0);
  for (int v = 1; v < n; ++v)
    if (find(v) != root) return v;
  return -1;
}

template <class G>
TwoRobotScenario<G> split_impl(const graph::PoseGraphOf<G>& graph, const std::vector<G>& gt,
                               const SplitOptions& o) {
  using J = typename G::Jacobian;
  const int n = static_cast<int>(gt.size());
  if (!graph.poses.empty() && static_cast<int>(graph.poses.size()) != n)
    fail("split_two_robots: the ground truth has {} poses, the graph {}", n, graph.poses.size());
  o.validate(n);
  for (int v = o.first; v < o.last; ++v)
    if (!finite_pose(gt[v])) fail("split_two_robots: ground-truth pose {} is not finite", v);

  TwoRobotScenario<G> s;
  s.split = o;
  const G Ga_inv = gt[o.first].inverse(), Gb_inv = gt[o.split].inverse();
  s.true_anchor = Ga_inv * gt[o.split];
  const int na = o.split - o.first, nb = o.last - o.split;
  for (int v = o.first; v < o.split; ++v) s.truth_a.push_back(Ga_inv * gt[v]);
  for (int v = o.split; v < o.last; ++v) s.truth_b.push_back(Gb_inv * gt[v]);
  s.truth_a[0] = G();
  s.truth_b[0] = G();

  // Local graphs: the graph's own initial poses (if any), re-expressed with the robot's first pose at the
  // identity.
  auto init_local = [&](graph::PoseGraphOf<G>& g, int begin, int end) {
    g.source = graph.source;
    g.has_initial_poses = graph.has_initial_poses;
    if (graph.poses.empty()) return;
    const G inv = graph.poses[begin].inverse();
    for (int v = begin; v < end; ++v) g.poses.push_back(inv * graph.poses[v]);
    g.poses[0] = G();
  };
  init_local(s.robot_a, o.first, o.split);
  init_local(s.robot_b, o.split, o.last);

  auto side = [&](int v) { return v < o.first || v >= o.last ? -1 : (v < o.split ? 0 : 1); };
  for (const auto& e : graph.edges) {
    const int si = side(e.i), sj = side(e.j);
    if (si < 0 || sj < 0) continue;
    if (si == sj) {
      auto le = e;
      const int base = si == 0 ? o.first : o.split;
      le.i -= base;
      le.j -= base;
      (si == 0 ? s.robot_a : s.robot_b).edges.push_back(le);
      continue;
    }
    if (std::abs(e.i - e.j) ==
        1) {  // the odometry edge that joined the trajectories: removed, not a loop closure
      ++s.dropped_odometry;
      continue;
    }
    InterRobotMeasurement<G> m;
    const J cov = left_covariance_from_information(e.measurement, e.information);
    if (si == 0) {
      m.pose_a = e.i - o.first;
      m.pose_b = e.j - o.split;
      m.z = e.measurement;
      m.covariance = cov;
      s.pool_information.push_back(e.information);
    } else {  // stored b → a: invert
      m.pose_a = e.j - o.first;
      m.pose_b = e.i - o.split;
      m.z = e.measurement.inverse();
      m.covariance = left_cov_of_inverse(e.measurement, cov);
      s.pool_information.push_back(pcm::information_from_left_covariance(m.z, m.covariance));
    }
    s.pool.push_back(m);
    s.pool_lines.push_back(e.line);
  }
  if (const int v = first_unreachable(s.robot_a, na); v >= 0)
    fail(
        "split_two_robots: robot a's local graph is not connected (its pose {} = pose {} of the "
        "dataset is not linked to its pose 0)",
        v, o.first + v);
  if (const int v = first_unreachable(s.robot_b, nb); v >= 0)
    fail(
        "split_two_robots: robot b's local graph is not connected (its pose {} = pose {} of the "
        "dataset is not linked to its pose 0)",
        v, o.split + v);

  s.extent_min = s.truth_a[0].translation();
  s.extent_max = s.extent_min;
  auto grow = [&](const typename G::Point& p) {
    s.extent_min = s.extent_min.cwiseMin(p);
    s.extent_max = s.extent_max.cwiseMax(p);
  };
  for (const auto& T : s.truth_a) grow(T.translation());
  for (const auto& T : s.truth_b) grow((s.true_anchor * T).translation());
  return s;
}

template <class G>
CandidateSet<G> generate_impl(const TwoRobotScenario<G>& s, const CandidateOptions& o, std::uint64_t seed,
                              std::uint64_t index) {
  using J = typename G::Jacobian;
  using T = typename G::Tangent;
  using P = typename G::Point;
  constexpr int kT = P::RowsAtCompileTime;  // translation dimensions (2 or 3)
  constexpr int kR = G::DoF - kT;           // rotation dimensions (1 or 3)
  o.validate();
  const int pool = static_cast<int>(s.pool.size());
  if (o.num_inliers > pool)
    fail("generate_candidates: num_inliers ({}) exceeds the pool of true inter-robot loop closures ({})",
         o.num_inliers, pool);
  if ((o.aliased_groups > 0 && o.aliased_group_size > 0) && pool == 0)
    fail("generate_candidates: aliased outliers take their noise from the pool, which is empty");
  const int na = static_cast<int>(s.truth_a.size()), nb = static_cast<int>(s.truth_b.size());
  if (na < 1 || nb < 1) fail("generate_candidates: the scenario has a robot without poses");

  core::Rng rng = core::Rng::stream(seed, index);
  CandidateSet<G> out;

  // Inliers: a partial Fisher–Yates shuffle of the pool indices.
  std::vector<int> idx(static_cast<std::size_t>(pool));
  std::iota(idx.begin(), idx.end(), 0);
  for (int k = 0; k < o.num_inliers; ++k) {
    const int r = k + uniform_index(rng, pool - k);
    std::swap(idx[k], idx[r]);
    const int u = idx[k];
    out.candidates.push_back(s.pool[u]);
    out.information.push_back(s.pool_information[u]);
    out.labels.push_back({MeasurementLabel::inlier, -1, u});
  }

  const P extent = s.extent_max - s.extent_min;
  auto uniform_point = [&](const P& lo, const P& hi) {
    P p;
    for (int d = 0; d < kT; ++d) p(d) = rng.uniform(lo(d), hi(d));
    return p;
  };

  // Perceptually aliased groups.
  for (int g = 0; g < o.aliased_groups; ++g) {
    G A;
    if (o.near_miss_translation_max > 0.0) {
      A = s.true_anchor * near_miss_offset(rng, o, static_cast<const G*>(nullptr));
    } else {
      const auto R = random_rotation(rng, static_cast<const G*>(nullptr));
      A = make_pose(R, uniform_point(s.extent_min, s.extent_max));
    }
    out.false_anchors.push_back(A);
    for (int m = 0; m < o.aliased_group_size; ++m) {
      const int i = uniform_index(rng, na), k = uniform_index(rng, nb);
      const J info = s.pool_information[uniform_index(rng, pool)];
      const J residual_cov = info.ldlt().solve(J::Identity());
      const J L = Eigen::LLT<J>(0.5 * (residual_cov + residual_cov.transpose())).matrixL();
      const T r = o.aliased_noise_scale * normal_sample(rng, L);
      const G z_bar = s.truth_a[i].inverse() * A * s.truth_b[k];
      InterRobotMeasurement<G> c;
      c.pose_a = i;
      c.pose_b = k;
      c.z = z_bar * from_residual(r).inverse();  // z⁻¹ z̄ = ρ⁻¹(r): the residual at the false alignment is r
      c.covariance = left_covariance_from_information(c.z, info);
      out.candidates.push_back(c);
      out.information.push_back(info);
      out.labels.push_back({MeasurementLabel::aliased, g, -1});
    }
  }

  // Random outliers.
  for (int m = 0; m < o.random_outliers; ++m) {
    const int i = uniform_index(rng, na), k = uniform_index(rng, nb);
    const auto R = random_rotation(rng, static_cast<const G*>(nullptr));
    const P t = uniform_point(P(-extent), P(extent));
    // log-uniform scales: σ = exp(U[log min, log max])
    const double st = std::exp(
        rng.uniform(std::log(o.random_sigma_translation_min), std::log(o.random_sigma_translation_max)));
    const double sr =
        std::exp(rng.uniform(std::log(o.random_sigma_rotation_min), std::log(o.random_sigma_rotation_max)));
    J info = J::Zero();
    info.template topLeftCorner<kT, kT>().diagonal().setConstant(1.0 / (st * st));
    info.template bottomRightCorner<kR, kR>().diagonal().setConstant(1.0 / (sr * sr));
    InterRobotMeasurement<G> c;
    c.pose_a = i;
    c.pose_b = k;
    c.z = make_pose(R, t);
    c.covariance = left_covariance_from_information(c.z, info);
    out.candidates.push_back(c);
    out.information.push_back(info);
    out.labels.push_back({MeasurementLabel::random, -1, -1});
  }

  if (o.shuffle) {
    const int n = static_cast<int>(out.candidates.size());
    for (int k = n - 1; k > 0; --k) {
      const int r = uniform_index(rng, k + 1);
      std::swap(out.candidates[k], out.candidates[r]);
      std::swap(out.information[k], out.information[r]);
      std::swap(out.labels[k], out.labels[r]);
    }
  }
  return out;
}

template <class G, class Graph>
void resample_graph(Graph& g, const std::vector<G>& truth, double scale, core::Rng rng) {
  for (auto& e : g.edges)
    e.measurement = redraw(rng, G(truth[e.i].inverse() * truth[e.j]), e.information, scale);
}

template <class G>
void resample_impl(TwoRobotScenario<G>& s, double scale, std::uint64_t seed) {
  if (!(std::isfinite(scale) && scale > 0.0))
    fail("resample_measurements: noise_scale must be > 0 and finite (got {:g})", scale);
  if constexpr (std::is_same_v<G, lie::SE2>) {
    if (!s.robot_a.landmark_measurements.empty() || !s.robot_b.landmark_measurements.empty())
      fail("resample_measurements: graphs with landmark measurements are not supported");
  }
  resample_graph<G>(s.robot_a, s.truth_a, scale, core::Rng::stream(seed, 0));
  resample_graph<G>(s.robot_b, s.truth_b, scale, core::Rng::stream(seed, 1));
  core::Rng rng = core::Rng::stream(seed, 2);
  for (std::size_t u = 0; u < s.pool.size(); ++u) {
    auto& c = s.pool[u];
    const G X = s.truth_a[c.pose_a].inverse() * s.true_anchor * s.truth_b[c.pose_b];
    c.z = redraw(rng, X, s.pool_information[u], scale);
    c.covariance = left_covariance_from_information(c.z, s.pool_information[u]);
  }
}

}  // namespace

void SplitOptions::validate(int num_poses) const {
  auto check = [&](bool ok, const char* what) {
    if (!ok)
      fail("SplitOptions: {} (first {}, split {}, last {}, dataset poses {})", what, first, split, last,
           num_poses);
  };
  check(first >= 0, "first must be >= 0");
  check(split - first >= 2, "robot a = [first, split) needs at least 2 poses");
  check(last - split >= 2, "robot b = [split, last) needs at least 2 poses");
  check(last <= num_poses, "last must be <= the number of poses");
}

TwoRobotScenario2 split_two_robots(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& ground_truth,
                                   const SplitOptions& options) {
  return split_impl<lie::SE2>(graph, ground_truth, options);
}
TwoRobotScenario3 split_two_robots(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& ground_truth,
                                   const SplitOptions& options) {
  return split_impl<lie::SE3>(graph, ground_truth, options);
}

void CandidateOptions::validate() const {
  auto count = [](const char* name, int v) {
    if (v < 0) fail("CandidateOptions: {} must be >= 0 (got {})", name, v);
  };
  count("num_inliers", num_inliers);
  count("aliased_groups", aliased_groups);
  count("random_outliers", random_outliers);
  if (aliased_groups > 0 && aliased_group_size < 1)
    fail("CandidateOptions: aliased_group_size must be >= 1 when aliased_groups > 0 (got {})",
         aliased_group_size);
  auto range = [](const char* name, double lo, double hi) {
    if (!(std::isfinite(lo) && std::isfinite(hi) && lo > 0.0 && lo <= hi))
      fail("CandidateOptions: {} range must satisfy 0 < min <= max, finite (got [{:g}, {:g}])", name, lo, hi);
  };
  range("random_sigma_translation", random_sigma_translation_min, random_sigma_translation_max);
  range("random_sigma_rotation", random_sigma_rotation_min, random_sigma_rotation_max);
  if (near_miss_translation_max > 0.0 || near_miss_rotation_max > 0.0) {
    auto offsets = [](const char* name, double lo, double hi) {
      if (!(std::isfinite(lo) && std::isfinite(hi) && lo >= 0.0 && lo <= hi))
        fail("CandidateOptions: {} range must satisfy 0 <= min <= max, finite (got [{:g}, {:g}])", name, lo,
             hi);
    };
    offsets("near_miss_translation", near_miss_translation_min, near_miss_translation_max);
    offsets("near_miss_rotation", near_miss_rotation_min, near_miss_rotation_max);
    if (!(near_miss_translation_max > 0.0))
      fail("CandidateOptions: near-miss groups need near_miss_translation max > 0 (got {:g})",
           near_miss_translation_max);
  }
  if (!(std::isfinite(aliased_noise_scale) && aliased_noise_scale > 0.0))
    fail("CandidateOptions: aliased_noise_scale must be > 0 and finite (got {:g})", aliased_noise_scale);
  if (total() < 1) fail("CandidateOptions: no candidates requested (all counts are 0)");
}

void resample_measurements(TwoRobotScenario2& scenario, double noise_scale, std::uint64_t seed) {
  resample_impl(scenario, noise_scale, seed);
}
void resample_measurements(TwoRobotScenario3& scenario, double noise_scale, std::uint64_t seed) {
  resample_impl(scenario, noise_scale, seed);
}

CandidateSet2 generate_candidates(const TwoRobotScenario2& scenario, const CandidateOptions& options,
                                  std::uint64_t seed, std::uint64_t index) {
  return generate_impl<lie::SE2>(scenario, options, seed, index);
}
CandidateSet3 generate_candidates(const TwoRobotScenario3& scenario, const CandidateOptions& options,
                                  std::uint64_t seed, std::uint64_t index) {
  return generate_impl<lie::SE3>(scenario, options, seed, index);
}

}  // namespace keel::sim
