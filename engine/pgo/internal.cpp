// Shared internals: graph checks, square-root information, residuals (double only), evaluation and reports.
#include "pgo/internal.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <fmt/format.h>
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace keel::pgo::detail {

namespace {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(fmt::format("pgo: {}", what)); }

std::string source_of(const std::string& s) {
  return s.empty() ? std::string("<unnamed graph>") : fmt::format("'{}'", s);
}

template <int N>
Eigen::Matrix<double, N, N> sqrt_info_impl(const Eigen::Matrix<double, N, N>& omega,
                                           const std::string& what) {
  using M = Eigen::Matrix<double, N, N>;
  if (!omega.allFinite()) fail(fmt::format("{}: information matrix has a non-finite entry", what));
  const M sym = 0.5 * (omega + omega.transpose());
  Eigen::LLT<M> llt(sym);
  if (llt.info() == Eigen::Success) return llt.matrixU();
  // Positive semi-definite (or slightly indefinite from rounding): symmetric square root of the clamped
  // spectrum.
  Eigen::SelfAdjointEigenSolver<M> es(sym);
  const auto& lambda = es.eigenvalues();
  const double scale = std::max(1.0, lambda.cwiseAbs().maxCoeff());
  if (lambda.minCoeff() < -1e-9 * scale)
    fail(fmt::format("{}: information matrix is not positive semi-definite (smallest eigenvalue {})", what,
                     lambda.minCoeff()));
  const Eigen::Matrix<double, N, 1> root = lambda.cwiseMax(0.0).cwiseSqrt();
  return root.asDiagonal() * es.eigenvectors().transpose();  // UᵀU = V Λ Vᵀ
}

template <class G>
int max_pose_index(const G& g) {
  int m = -1;
  for (const auto& e : g.edges) m = std::max({m, e.i, e.j});
  if constexpr (requires { g.landmark_measurements; })
    for (const auto& lm : g.landmark_measurements) m = std::max(m, lm.pose);
  return m;
}

}  // namespace

int pose_count(const graph::PoseGraph2D& g) {
  return std::max<int>(static_cast<int>(g.poses.size()), max_pose_index(g) + 1);
}
int pose_count(const graph::PoseGraph3D& g) {
  return std::max<int>(static_cast<int>(g.poses.size()), max_pose_index(g) + 1);
}
int landmark_count(const graph::PoseGraph2D& g) {
  int m = -1;
  for (const auto& lm : g.landmark_measurements) m = std::max(m, lm.landmark);
  return std::max<int>(static_cast<int>(g.landmarks.size()), m + 1);
}

std::string edge_label(const char* kind, std::size_t index, int line, const std::string& source) {
  if (line > 0) return fmt::format("{} {} (line {} of {})", kind, index, line, source_of(source));
  if (!source.empty()) return fmt::format("{} {} of {}", kind, index, source_of(source));
  return fmt::format("{} {}", kind, index);
}

template <class D>
void validate_graph(const RobotsView<D>& view) {
  const int robots = static_cast<int>(view.robots.size());
  for (int r = 0; r < robots; ++r) {
    const auto& g = *view.robots[r];
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      const auto& e = g.edges[k];
      if (e.i < 0 || e.j < 0)
        fail(fmt::format("{}: negative pose index", edge_label("edge", k, e.line, g.source)));
      if (e.i == e.j)
        fail(fmt::format("{}: connects pose {} to itself", edge_label("edge", k, e.line, g.source), e.i));
    }
    if constexpr (D::kLandmarks) {
      for (std::size_t k = 0; k < g.landmark_measurements.size(); ++k) {
        const auto& m = g.landmark_measurements[k];
        if (m.pose < 0 || m.landmark < 0)
          fail(fmt::format("{}: negative pose or landmark index",
                           edge_label("landmark measurement", k, m.line, g.source)));
      }
    }
  }
  if (!view.inter) return;
  for (std::size_t k = 0; k < view.inter->size(); ++k) {
    const auto& e = (*view.inter)[k];
    const std::string label = edge_label("inter-robot edge", k, e.line, "");
    if (e.robot_a < 0 || e.robot_a >= robots || e.robot_b < 0 || e.robot_b >= robots)
      fail(fmt::format("{}: robot index out of range ({} robots)", label, robots));
    if (e.robot_a == e.robot_b)
      fail(fmt::format("{}: robot_a == robot_b (use an edge of that robot's own graph)", label));
    if (e.pose_a < 0 || e.pose_a >= pose_count(*view.robots[e.robot_a]) || e.pose_b < 0 ||
        e.pose_b >= pose_count(*view.robots[e.robot_b]))
      fail(fmt::format("{}: pose index out of range of its robot's graph", label));
  }
}

template void validate_graph<D2>(const RobotsView<D2>&);
template void validate_graph<D3>(const RobotsView<D3>&);

lie::Mat2 sqrt_information(const lie::Mat2& omega, const std::string& what) {
  return sqrt_info_impl<2>(omega, what);
}
lie::Mat3 sqrt_information(const lie::Mat3& omega, const std::string& what) {
  return sqrt_info_impl<3>(omega, what);
}
lie::Mat6 sqrt_information(const lie::Mat6& omega, const std::string& what) {
  return sqrt_info_impl<6>(omega, what);
}

bool robust_edge(const Options& o, int i, int j) {
  if (o.robust_kernel == RobustKernel::none) return false;
  if (o.robust_scope == RobustScope::all_edges) return true;
  if (o.robust_scope == RobustScope::loop_closures) return std::abs(i - j) != 1;
  return false;
}

bool robust_landmark(const Options& o) {
  return o.robust_kernel != RobustKernel::none && o.robust_scope != RobustScope::inter_robot;
}

bool robust_inter_robot(const Options& o) { return o.robust_kernel != RobustKernel::none; }

EdgeReport edge_report(const Options& o, bool robust, double chi2) {
  EdgeReport rep;
  rep.chi2 = chi2;
  rep.robust = robust;
  if (robust) {
    rep.weight = robust_rho(o.robust_kernel, o.robust_parameter, chi2).d1;
    rep.scale = std::sqrt(rep.weight);
  }
  return rep;
}

double normalized_chi2(double cost, int residual_dimension, int free_dimension) {
  const int dof = residual_dimension - free_dimension;
  return dof > 0 ? 2.0 * cost / dof : std::numeric_limits<double>::quiet_NaN();
}

namespace {

// Cost contribution ½ ρ(χ²) of a measurement.
double half_rho(const Options& o, bool robust, double chi2) {
  return 0.5 * (robust ? robust_rho(o.robust_kernel, o.robust_parameter, chi2).rho : chi2);
}

void check_constant_poses(const Options& o, int robot, int n, const std::string& source) {
  for (int k : o.constant_poses)
    if (k < 0 || k >= n)
      fail(fmt::format("constant_poses: pose {} is out of range (robot {}, {}, has {} poses)", k, robot,
                       source_of(source), n));
}

}  // namespace

template <class D>
typename D::MultiEvaluation evaluate_view(const RobotsView<D>& view, const typename D::MultiEstimate& at,
                                          const Options& o) {
  o.validate();
  validate_graph(view);
  const int robots = static_cast<int>(view.robots.size());
  if (static_cast<int>(at.robots.size()) != robots)
    fail(fmt::format("evaluate: the estimate has {} robots, the graph {}", at.robots.size(), robots));
  if (view.with_anchors && static_cast<int>(at.anchors.size()) != robots)
    fail(fmt::format("evaluate: the estimate has {} anchors for {} robots", at.anchors.size(), robots));

  typename D::MultiEvaluation out;
  out.robots.resize(robots);
  std::vector<std::vector<char>> pose_used(robots);
  for (int r = 0; r < robots; ++r) {
    const auto& g = *view.robots[r];
    const auto& est = at.robots[r];
    auto& ev = out.robots[r];
    const int n = pose_count(g);
    if (static_cast<int>(est.poses.size()) < n)
      fail(fmt::format("evaluate: robot {} ({}) has {} poses but the estimate {}", r, source_of(g.source), n,
                       est.poses.size()));
    check_constant_poses(o, r, n, g.source);
    pose_used[r].assign(n, 0);
    ev.residuals.resize(g.edges.size());
    ev.edges.resize(g.edges.size());
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      const auto& e = g.edges[k];
      const auto U = sqrt_information(e.information, edge_label("edge", k, e.line, g.source));
      const auto res = edge_residual(e.measurement, est.poses[e.i], est.poses[e.j]);
      const double chi2 = (U * res).squaredNorm();
      const bool robust = robust_edge(o, e.i, e.j);
      ev.residuals[k] = res;
      ev.edges[k] = edge_report(o, robust, chi2);
      ev.cost += half_rho(o, robust, chi2);
      ev.chi2 += chi2;
      pose_used[r][e.i] = pose_used[r][e.j] = 1;
    }
    ev.residual_dimension = D::kPoseDof * static_cast<int>(g.edges.size());
    if constexpr (D::kLandmarks) {
      const int m = landmark_count(g);
      if (static_cast<int>(est.landmarks.size()) < m)
        fail(fmt::format("evaluate: robot {} ({}) has {} landmarks but the estimate {}", r,
                         source_of(g.source), m, est.landmarks.size()));
      std::vector<char> lm_used(m, 0);
      ev.landmark_residuals.resize(g.landmark_measurements.size());
      ev.landmark_edges.resize(g.landmark_measurements.size());
      const bool robust = robust_landmark(o);
      for (std::size_t k = 0; k < g.landmark_measurements.size(); ++k) {
        const auto& lm = g.landmark_measurements[k];
        const auto U =
            sqrt_information(lm.information, edge_label("landmark measurement", k, lm.line, g.source));
        const lie::Vec2 res = landmark_residual(lm.position, est.poses[lm.pose], est.landmarks[lm.landmark]);
        const double chi2 = (U * res).squaredNorm();
        ev.landmark_residuals[k] = res;
        ev.landmark_edges[k] = edge_report(o, robust, chi2);
        ev.cost += half_rho(o, robust, chi2);
        ev.chi2 += chi2;
        pose_used[r][lm.pose] = 1;
        lm_used[lm.landmark] = 1;
      }
      ev.residual_dimension += 2 * static_cast<int>(g.landmark_measurements.size());
      ev.free_parameter_dimension += 2 * static_cast<int>(std::count(lm_used.begin(), lm_used.end(), 1));
    }
  }

  std::vector<char> anchor_used(robots, 0);
  if (view.inter) {
    const auto& inter = *view.inter;
    out.inter_robot_residuals.resize(inter.size());
    out.inter_robot_edges.resize(inter.size());
    const bool robust = robust_inter_robot(o);
    for (std::size_t k = 0; k < inter.size(); ++k) {
      const auto& e = inter[k];
      const auto U = sqrt_information(e.information, edge_label("inter-robot edge", k, e.line, ""));
      const auto Gi = at.anchors[e.robot_a] * at.robots[e.robot_a].poses[e.pose_a];
      const auto Gj = at.anchors[e.robot_b] * at.robots[e.robot_b].poses[e.pose_b];
      const auto res = edge_residual(e.measurement, Gi, Gj);
      const double chi2 = (U * res).squaredNorm();
      out.inter_robot_residuals[k] = res;
      out.inter_robot_edges[k] = edge_report(o, robust, chi2);
      out.cost += half_rho(o, robust, chi2);
      out.chi2 += chi2;
      pose_used[e.robot_a][e.pose_a] = pose_used[e.robot_b][e.pose_b] = 1;
      anchor_used[e.robot_a] = anchor_used[e.robot_b] = 1;
    }
    out.residual_dimension += D::kPoseDof * static_cast<int>(inter.size());
  }
  if (view.with_anchors)
    for (int r = 1; r < robots; ++r) out.free_parameter_dimension += anchor_used[r] ? D::kPoseDof : 0;

  for (int r = 0; r < robots; ++r) {
    auto& ev = out.robots[r];
    std::vector<char> free = pose_used[r];
    for (int k : o.constant_poses) free[k] = 0;
    ev.free_parameter_dimension += D::kPoseDof * static_cast<int>(std::count(free.begin(), free.end(), 1));
    ev.normalized_chi2 = normalized_chi2(ev.cost, ev.residual_dimension, ev.free_parameter_dimension);
    out.cost += ev.cost;
    out.chi2 += ev.chi2;
    out.residual_dimension += ev.residual_dimension;
    out.free_parameter_dimension += ev.free_parameter_dimension;
  }
  out.normalized_chi2 = normalized_chi2(out.cost, out.residual_dimension, out.free_parameter_dimension);
  return out;
}

template D2::MultiEvaluation evaluate_view<D2>(const RobotsView<D2>&, const D2::MultiEstimate&,
                                               const Options&);
template D3::MultiEvaluation evaluate_view<D3>(const RobotsView<D3>&, const D3::MultiEstimate&,
                                               const Options&);

RobotsView<D2> view_of(const graph::PoseGraph2D& g) { return {{&g}, nullptr, false}; }
RobotsView<D3> view_of(const graph::PoseGraph3D& g) { return {{&g}, nullptr, false}; }

RobotsView<D2> view_of(const MultiRobotGraph2D& g) {
  RobotsView<D2> v;
  for (const auto& r : g.robots) v.robots.push_back(&r);
  v.inter = &g.inter_robot_edges;
  v.with_anchors = true;
  return v;
}

RobotsView<D3> view_of(const MultiRobotGraph3D& g) {
  RobotsView<D3> v;
  for (const auto& r : g.robots) v.robots.push_back(&r);
  v.inter = &g.inter_robot_edges;
  v.with_anchors = true;
  return v;
}

}  // namespace keel::pgo::detail
