#include "app/robust.hpp"

#include "app/files.hpp"

namespace keel::app {

namespace {

// Every robot's poses and edges and the inter-robot candidates in one graph (ids as merge::robust numbers
// them), for the numeric check of all the inputs at once.
template <class Graph, class Edge>
Graph everything(const std::vector<Graph>& robots, const std::vector<Edge>& inter) {
  Graph all;
  for (const auto& g : robots) {
    const int off = static_cast<int>(all.poses.size());
    all.poses.insert(all.poses.end(), g.poses.begin(), g.poses.end());
    for (auto e : g.edges) {
      e.i += off;
      e.j += off;
      all.edges.push_back(e);
    }
  }
  all.edges.insert(all.edges.end(), inter.begin(), inter.end());
  if (robots.size() == 1) all.source = robots[0].source;
  return all;
}

}  // namespace

RobustRun2 robust(const std::vector<graph::PoseGraph2D>& robots, const std::vector<graph::Edge2>& inter_robot,
                  const RobustOptions& options, const Progress& progress) {
  check_numeric_range(everything(robots, inter_robot));
  return merge::robust(robots, inter_robot, options, progress);
}

RobustRun3 robust(const std::vector<graph::PoseGraph3D>& robots, const std::vector<graph::Edge3>& inter_robot,
                  const RobustOptions& options, const Progress& progress) {
  check_numeric_range(everything(robots, inter_robot));
  return merge::robust(robots, inter_robot, options, progress);
}

}  // namespace keel::app
