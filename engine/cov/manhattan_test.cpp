// Real-data smoke test: Manhattan3500 (iSAM measurements and square-root information, read by keel::graph) at
// its ground-truth poses. In the doctest suite "datasets" (CTest datasets.cov): without a verified copy of
// the files it fails, naming the file and scripts/fetch-datasets (tests/kit/dataset_files.hpp).
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "graph/isam.hpp"
#include "graph/trajectory.hpp"
#include "kit/dataset_files.hpp"

using namespace keel;
using namespace keel::cov;

TEST_CASE("Manhattan3500 at ground truth: factorization, pair marginals SPD and equal to joint()" *
          doctest::test_suite("datasets")) {
  const PoseGraph2D g =
      graph::read_isam_2d(testkit::dataset_file("manhattan3500", "isam/manhattanOlson3500.txt"));
  const std::vector<SE2> poses = graph::read_poses_2d(
      testkit::dataset_file("manhattan3500", "derived/manhattanOlson3500_groundtruth_poses.txt"));
  REQUIRE(poses.size() == 3500);
  REQUIRE(g.edges.size() == 5598);
  const auto H = information_matrix(g, poses);
  CHECK(H.size == 3 * 3499);
  const MarginalCovariance mc(H);
  const auto& s = mc.summary();
  MESSAGE("Manhattan3500: ordering " << s.ordering << ", supernodal " << s.supernodal << ", extraction "
                                     << s.extraction << ", nnz(H) " << s.nnz_h << ", nnz(L) " << s.nnz_l
                                     << ", supernodes " << s.num_supernodes << ", mean path share of L "
                                     << s.mean_path_fraction);
  CHECK(s.supernodal);
  const std::vector<std::pair<int, int>> pairs = {{1, 6},       {10, 510}, {1000, 1200},
                                                  {2999, 3499}, {0, 100},  {1750, 1800}};
  const auto P = pair_marginals_2d(mc, pairs, 2);
  REQUIRE(P.size() == pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    CAPTURE(k);
    const Mat6& S = P[k];
    CHECK((S - S.transpose()).norm() == 0.0);
    const MatX J = mc.joint({pairs[k].first, pairs[k].second});
    CHECK((MatX(S) - J).norm() <= 1e-12 * J.norm());
    if (pairs[k].first == 0) {  // the gauge pose: zero covariance, the other block positive definite
      CHECK(S.topLeftCorner<3, 3>().norm() == 0.0);
      CHECK(Eigen::LLT<Mat3>(S.bottomRightCorner<3, 3>()).info() == Eigen::Success);
    } else {
      CHECK(Eigen::LLT<Mat6>(S).info() == Eigen::Success);
      CHECK(Eigen::SelfAdjointEigenSolver<Mat6>(S).eigenvalues().minCoeff() > 0.0);
    }
  }
  // The other extraction method (full multi-column solves) and another ordering give the same numbers.
  CovarianceOptions solve, metis;
  solve.extraction = Extraction::solve;
  metis.ordering = Ordering::metis;
  const auto Ps = pair_marginals_2d(MarginalCovariance(H, solve), pairs, 1);
  const auto Pm = pair_marginals_2d(MarginalCovariance(H, metis), pairs, 1);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    CHECK((Ps[k] - P[k]).norm() <= 1e-9 * P[k].norm());
    CHECK((Pm[k] - P[k]).norm() <= 1e-9 * P[k].norm());
  }
  // Uncertainty grows away from the gauge pose.
  CHECK(mc.marginal(3499).trace() > mc.marginal(10).trace());
}
