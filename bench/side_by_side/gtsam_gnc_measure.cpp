// GTSAM's GncOptimizer (graduated non-convexity, truncated least squares) as a measurement driver for
// bench/side_by_side/robust.sh: one g2o graph (2D or 3D), its edges between consecutive poses (i → i + 1)
// known inliers as in keel robust, every other edge a candidate loop closure; a prior on pose 0 (a known
// inlier); GncOptimizer<GncParams<LevenbergMarquardtParams>> with TLS, μ step 1.4 and the inlier cost
// threshold at probability P (default 0.99: the χ² quantile keel's --gnc-p 0.01 uses), from the file's
// vertices; one thread (GTSAM built without TBB). Prints key=value lines:
//
//   gnc_s          GncOptimizer::optimize (not the file reading or the building of the factor graph)
//   process_s      from the start of main to the end of the solve
//   loop_closures  loop closures in the file; kept: those with a GNC weight ≥ 0.5
//   kept_edges     the kept closures as "i-j"
//
// keel's own file; it includes only GTSAM's public headers and is built outside the repository against an
// externally built GTSAM (docs/PEERS.md):
//
//   c++ -std=c++17 -O2 -I$GTSAM/include -I/usr/include/eigen3 gtsam_gnc_measure.cpp -L$GTSAM/lib -lgtsam
//   -lcephes-gtsam
//       -Wl,-rpath,$GTSAM/lib -o gtsam_gnc_measure
//
//   gtsam_gnc_measure [--probability P] GRAPH
#include <gtsam/geometry/Pose2.h>
#include <gtsam/geometry/Pose3.h>
#include <gtsam/nonlinear/GncOptimizer.h>
#include <gtsam/nonlinear/LevenbergMarquardtParams.h>
#include <gtsam/slam/BetweenFactor.h>
#include <gtsam/slam/PriorFactor.h>
#include <gtsam/slam/dataset.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

bool is_3d(const std::string& file) {
  std::ifstream in(file);
  std::string tag;
  while (in >> tag) {
    if (tag.rfind("EDGE_SE3", 0) == 0 || tag.rfind("VERTEX_SE3", 0) == 0) return true;
    if (tag.rfind("EDGE_SE2", 0) == 0 || tag.rfind("VERTEX_SE2", 0) == 0) return false;
    std::getline(in, tag);
  }
  return false;
}

template <class Pose>
int run(const std::string& file, double probability, Clock::time_point start) {
  constexpr bool three_d = std::is_same_v<Pose, gtsam::Pose3>;
  auto [graph, initial] = gtsam::readG2o(file, three_d);
  gtsam::NonlinearFactorGraph factors = *graph;
  gtsam::GncParams<gtsam::LevenbergMarquardtParams>::IndexVector known;
  std::vector<std::pair<std::size_t, std::size_t>> closures;  // factor index, (i, j) in `ends`
  std::vector<std::pair<gtsam::Key, gtsam::Key>> ends;
  for (std::size_t k = 0; k < factors.size(); ++k) {
    const auto between = std::dynamic_pointer_cast<gtsam::BetweenFactor<Pose>>(factors[k]);
    if (!between) continue;
    const gtsam::Key i = between->key1(), j = between->key2();
    if (j == i + 1 || i == j + 1) {
      known.push_back(k);
    } else {
      closures.emplace_back(k, ends.size());
      ends.emplace_back(i, j);
    }
  }
  const auto sigmas = gtsam::noiseModel::Isotropic::Sigma(three_d ? 6 : 3, 1e-6);
  factors.addPrior(0, initial->at<Pose>(0), sigmas);
  known.push_back(factors.size() - 1);
  gtsam::LevenbergMarquardtParams lm;
  lm.setVerbosityLM("SILENT");
  gtsam::GncParams<gtsam::LevenbergMarquardtParams> params(lm);
  params.setLossType(gtsam::GncLossType::TLS);
  params.setKnownInliers(known);
  gtsam::GncOptimizer<gtsam::GncParams<gtsam::LevenbergMarquardtParams>> gnc(factors, *initial, params);
  gnc.setInlierCostThresholdsAtProbability(probability);
  const auto t0 = Clock::now();
  (void)gnc.optimize();
  const double gnc_s = seconds(t0);
  const gtsam::Vector& w = gnc.getWeights();
  std::string kept;
  int count = 0;
  for (const auto& [k, e] : closures)
    if (w(static_cast<Eigen::Index>(k)) >= 0.5) {
      kept += (count++ ? " " : "") + std::to_string(ends[e].first) + "-" + std::to_string(ends[e].second);
    }
  std::printf("gnc_s=%.6f\nprocess_s=%.6f\nloop_closures=%zu\nkept=%d\nkept_edges=%s\n", gnc_s,
              seconds(start), closures.size(), count, kept.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const auto start = Clock::now();
  double probability = 0.99;
  std::string file;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--probability" && k + 1 < argc)
      probability = std::atof(argv[++k]);
    else
      file = a;
  }
  if (file.empty() || !(probability > 0.0 && probability < 1.0)) {
    std::fprintf(stderr, "usage: gtsam_gnc_measure [--probability P] GRAPH\n");
    return 2;
  }
  try {
    return is_3d(file) ? run<gtsam::Pose3>(file, probability, start)
                       : run<gtsam::Pose2>(file, probability, start);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gtsam_gnc_measure: %s: %s\n", file.c_str(), e.what());
    return 1;
  }
}
