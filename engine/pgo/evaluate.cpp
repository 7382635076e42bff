// evaluate(): residuals, χ² and cost of a graph at a given estimate (no solve, no Ceres).
#include <utility>

#include "pgo/internal.hpp"

namespace keel::pgo {

namespace {

template <class Single, class Multi>
Single single_of(Multi&& m) {
  Single s = std::move(m.robots[0]);
  // One robot, no anchors: the totals are that robot's numbers; keep the totals' definitions anyway.
  static_cast<Evaluation&>(s) = static_cast<const Evaluation&>(m);
  return s;
}

}  // namespace

Evaluation2D evaluate(const graph::PoseGraph2D& graph, const Estimate2D& at, const Options& options) {
  MultiRobotEstimate2D m;
  m.robots.push_back(at);
  return single_of<Evaluation2D>(detail::evaluate_view<detail::D2>(detail::view_of(graph), m, options));
}

Evaluation3D evaluate(const graph::PoseGraph3D& graph, const Estimate3D& at, const Options& options) {
  MultiRobotEstimate3D m;
  m.robots.push_back(at);
  return single_of<Evaluation3D>(detail::evaluate_view<detail::D3>(detail::view_of(graph), m, options));
}

MultiRobotEvaluation2D evaluate(const MultiRobotGraph2D& graph, const MultiRobotEstimate2D& at,
                                const Options& options) {
  return detail::evaluate_view<detail::D2>(detail::view_of(graph), at, options);
}

MultiRobotEvaluation3D evaluate(const MultiRobotGraph3D& graph, const MultiRobotEstimate3D& at,
                                const Options& options) {
  return detail::evaluate_view<detail::D3>(detail::view_of(graph), at, options);
}

}  // namespace keel::pgo
