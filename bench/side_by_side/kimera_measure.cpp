// Kimera-RPGO's measurement driver for bench/side_by_side/robust.sh: the inputs of `keel robust` (one g2o
// graph per robot, optionally an inter-robot candidate file with global ids), Kimera-RPGO's RobustSolver with
// its Mahalanobis PCM (PCM2D / PCM3D: an odometry check of each loop closure and the pairwise check, both
// against the same threshold) and, unless --no-gnc, GNC (truncated least squares) over GTSAM; one thread.
// Prints key=value lines:
//
//   rpgo_s         RobustSolver::update on the whole graph: PCM, the maximum clique, GNC and the
//                  Levenberg–Marquardt solves (not the file reading or the building of the factor graph)
//   process_s      from the start of main to the end of the solve
//   loop_closures  loop closures Kimera-RPGO saw; kept: those in its final graph with a GNC weight ≥ 0.5
//   kept_edges     the kept closures as "i-j" in global ids (robot r's pose k is k plus the poses before it)
//
// With --poses FILE it also writes Kimera-RPGO's estimate there, one line "id x y [z]" per pose in global ids
// (the positions, for the ATE against a reference), after the timed part.
//
// keel's own file; it includes only Kimera-RPGO's and GTSAM's public headers and is built outside the
// repository against externally built copies (docs/PEERS.md has the commands).
//
//   kimera_measure [--threshold T] [--no-gnc] [--gnc-probability P] [--poses FILE] GRAPH... [--candidates
//   FILE]
//
// T is the Mahalanobis NORM Kimera-RPGO compares (not its square): √γ of keel's γ(p) for the same test, which
// robust.sh passes. Robots get GTSAM symbols 'a', 'b', … so that Kimera-RPGO groups their closures as keel
// does.
#include <gtsam/inference/Symbol.h>
#include <gtsam/slam/BetweenFactor.h>
#include <gtsam/slam/PriorFactor.h>
#include <gtsam/slam/dataset.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "KimeraRPGO/RobustSolver.h"
#include "KimeraRPGO/SolverParams.h"

namespace {

using Clock = std::chrono::steady_clock;

bool is_3d(const std::string& file) {
  std::ifstream in(file);
  std::string tag;
  while (in >> tag) {
    if (tag.rfind("VERTEX_SE3", 0) == 0 || tag.rfind("EDGE_SE3", 0) == 0) return true;
    if (tag.rfind("VERTEX_SE2", 0) == 0 || tag.rfind("EDGE_SE2", 0) == 0) return false;
    std::string rest;
    std::getline(in, rest);
  }
  return false;
}

template <class Pose>
int run(const std::vector<std::string>& graphs, const std::string& candidates, double threshold, bool gnc,
        double gnc_probability, const std::string& poses_file, Clock::time_point start) {
  constexpr bool k3d = std::is_same_v<Pose, gtsam::Pose3>;
  gtsam::NonlinearFactorGraph nfg;
  gtsam::Values values;
  std::vector<std::size_t> offsets;
  std::size_t total = 0;
  auto key = [](std::size_t robot, std::size_t k) {
    return gtsam::Symbol(static_cast<unsigned char>('a' + robot), k).key();
  };
  auto add_between = [&](const gtsam::NonlinearFactor::shared_ptr& f, auto map_key) {
    auto b = std::dynamic_pointer_cast<gtsam::BetweenFactor<Pose>>(f);
    if (!b) return;
    nfg.add(
        gtsam::BetweenFactor<Pose>(map_key(b->key1()), map_key(b->key2()), b->measured(), b->noiseModel()));
  };
  for (std::size_t r = 0; r < graphs.size(); ++r) {
    const auto gv = gtsam::readG2o(graphs[r], k3d);
    offsets.push_back(total);
    for (const auto& kv : *gv.second) values.insert(key(r, kv.key), kv.value);
    total += gv.second->size();
    for (const auto& f : *gv.first) add_between(f, [&](gtsam::Key k) { return key(r, k); });
  }
  if (!candidates.empty()) {
    const auto gv = gtsam::readG2o(candidates, k3d);
    auto global = [&](gtsam::Key id) {
      std::size_t r = offsets.size() - 1;
      while (r > 0 && offsets[r] > id) --r;
      return key(r, id - offsets[r]);
    };
    for (const auto& f : *gv.first) add_between(f, global);
  }
  // The gauge: robot a's first pose, as Kimera-RPGO's own g2o example fixes it.
  const gtsam::Key first = key(0, 0);
  nfg.add(gtsam::PriorFactor<Pose>(first, values.at<Pose>(first),
                                   gtsam::noiseModel::Isotropic::Sigma(k3d ? 6 : 3, 1e-6)));

  KimeraRPGO::RobustSolverParams params;
  if (k3d)
    params.setPcm3DParams(threshold, threshold, KimeraRPGO::Verbosity::QUIET);
  else
    params.setPcm2DParams(threshold, threshold, KimeraRPGO::Verbosity::QUIET);
  if (gnc) params.setGncInlierCostThresholdsAtProbability(gnc_probability);
  if (graphs.size() > 1) params.setMultiRobotAlignMethod(KimeraRPGO::MultiRobotAlignMethod::L2);
  const auto t0 = Clock::now();
  KimeraRPGO::RobustSolver solver(params);
  solver.update(nfg, values);
  const double rpgo_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const double process_s = std::chrono::duration<double>(Clock::now() - start).count();

  const gtsam::NonlinearFactorGraph out = solver.getFactorsUnsafe();
  const gtsam::Vector w = solver.getGncWeights();
  // A factor can appear more than once in Kimera-RPGO's final graph; each kept pair is printed once.
  std::set<std::pair<std::size_t, std::size_t>> seen;
  std::ostringstream kept;
  std::size_t n_kept = 0;
  for (std::size_t k = 0; k < out.size(); ++k) {
    auto b = std::dynamic_pointer_cast<gtsam::BetweenFactor<Pose>>(out[k]);
    if (!b) continue;
    const gtsam::Symbol s1(b->key1()), s2(b->key2());
    const bool odometry =
        s1.chr() == s2.chr() && (s2.index() == s1.index() + 1 || s1.index() == s2.index() + 1);
    if (odometry) continue;
    if (gnc && k < static_cast<std::size_t>(w.size()) && w(static_cast<Eigen::Index>(k)) < 0.5) continue;
    const std::size_t i = offsets[static_cast<std::size_t>(s1.chr() - 'a')] + s1.index();
    const std::size_t j = offsets[static_cast<std::size_t>(s2.chr() - 'a')] + s2.index();
    if (!seen.insert({i, j}).second) continue;
    kept << (n_kept++ ? " " : "") << i << "-" << j;
  }
  if (!poses_file.empty()) {
    const gtsam::Values estimate = solver.calculateEstimate();
    std::FILE* f = std::fopen(poses_file.c_str(), "w");
    if (f == nullptr) {
      std::fprintf(stderr, "kimera_measure: cannot write %s\n", poses_file.c_str());
      return 1;
    }
    for (std::size_t r = 0; r < graphs.size(); ++r) {
      const std::size_t n = (r + 1 < offsets.size() ? offsets[r + 1] : total) - offsets[r];
      for (std::size_t k = 0; k < n; ++k) {
        const auto t = estimate.at<Pose>(key(r, k)).translation();
        if constexpr (k3d)
          std::fprintf(f, "%zu %.17g %.17g %.17g\n", offsets[r] + k, t.x(), t.y(), t.z());
        else
          std::fprintf(f, "%zu %.17g %.17g\n", offsets[r] + k, t.x(), t.y());
      }
    }
    std::fclose(f);
  }
  std::printf("rpgo_s=%.6f\nprocess_s=%.6f\nposes=%zu\nloop_closures=%zu\nkept=%zu\nkept_edges=%s\n", rpgo_s,
              process_s, total, solver.getNumLC(), n_kept, kept.str().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const auto start = Clock::now();
  double threshold = 0.0, gnc_probability = 0.99;
  bool gnc = true;
  std::vector<std::string> graphs;
  std::string candidates, poses_file;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--threshold" && k + 1 < argc)
      threshold = std::atof(argv[++k]);
    else if (a == "--no-gnc")
      gnc = false;
    else if (a == "--gnc-probability" && k + 1 < argc)
      gnc_probability = std::atof(argv[++k]);
    else if (a == "--candidates" && k + 1 < argc)
      candidates = argv[++k];
    else if (a == "--poses" && k + 1 < argc)
      poses_file = argv[++k];
    else
      graphs.push_back(a);
  }
  if (graphs.empty() || !(threshold > 0.0)) {
    std::fprintf(
        stderr,
        "usage: kimera_measure --threshold T [--no-gnc] [--gnc-probability P] [--poses FILE] GRAPH... "
        "[--candidates F]\n");
    return 2;
  }
  return is_3d(graphs[0])
             ? run<gtsam::Pose3>(graphs, candidates, threshold, gnc, gnc_probability, poses_file, start)
             : run<gtsam::Pose2>(graphs, candidates, threshold, gnc, gnc_probability, poses_file, start);
}
