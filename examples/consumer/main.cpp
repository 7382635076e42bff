// keel_certify FILE [2d|3d]: reads a pose graph (g2o or iSAM text), solves its isotropic (chordal) model with
// keel's certified solver (pgo::solve_certified: the SE-Sync problem, thesis ch. 4's certifiable planar SLAM
// in 2D and 3D) and prints the cost, the lower bound with the proof behind it, and the verdict. A bound is
// printed as proven only when the certificate says a proof succeeded. Exit 0 when certified, 1 when not, 2 on
// a bad command line, 3 on an input keel refuses. Built against an installed keel (CMakeLists.txt).
import keel.core;
import keel.graph;
import keel.pgo;

#include <cstdio>
#include <exception>
#include <string>

namespace {

template <class Graph>
int certify(const Graph& graph) {
  const auto result = keel::pgo::solve_certified(graph);
  const auto& summary = result.summary;
  const auto& certificate = summary.certificate;
  std::printf("poses        %d\n", summary.poses);
  std::printf("edges        %d\n", summary.edges);
  std::printf("cost         %.17g\n", summary.final_cost);
  if (certificate.proven) {
    std::printf("lower bound  %.17g (proven)\n", certificate.bound.lower);
    std::printf("gap          %.3g (relative, rounded up)\n", certificate.bound.relative_gap_up());
  } else {
    std::printf("lower bound  none: %s\n", certificate.message.c_str());
  }
  std::printf("termination  %s\n", std::string(keel::pgo::to_string(summary.termination)).c_str());
  return certificate.certified ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3 || (argc == 3 && std::string(argv[2]) != "2d" && std::string(argv[2]) != "3d")) {
    std::fprintf(stderr,
                 "usage: keel_certify FILE [2d|3d]   (a g2o or iSAM text pose graph; 2d by default)\n");
    return 2;
  }
  try {
    if (argc == 3 && std::string(argv[2]) == "3d") return certify(keel::graph::read_pose_graph_3d(argv[1]));
    return certify(keel::graph::read_pose_graph_2d(argv[1]));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "keel_certify: %s\n", e.what());
    return 3;
  }
}
