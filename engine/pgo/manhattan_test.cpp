// Manhattan3500 (Olson et al. 2006; iSAM text file, 3500 poses, 5598 edges): the optimizer on real benchmark
// data.
//  * noise-free ground-truth edges, started from the noisy odometry chain → the ground-truth poses to ~1e-6;
//  * the noisy file from the odometry chain → the optimum reached from ground truth, normalized χ² ≈ 1.
// The files are found through the dataset manifest (keel::datasets::resolve_dataset_file) and read by
// keel::graph. In the doctest suite "datasets" (CTest datasets.pgo): without a verified copy of the files it
// fails, naming the file and scripts/fetch-datasets (tests/kit/dataset_files.hpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "graph/isam.hpp"
#include "kit/dataset_files.hpp"
#include "lie/euler.hpp"
#include "pgo/optimize.hpp"

using namespace keel;
using namespace keel::pgo;

namespace {

double max_error(const std::vector<lie::SE2>& a, const std::vector<lie::SE2>& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    worst = std::max({worst, (a[k].translation() - b[k].translation()).norm(),
                      std::abs(lie::wrap_angle(a[k].angle() - b[k].angle()))});
  return worst;
}

}  // namespace

TEST_CASE(
    "Manhattan3500: noise-free edges from the noisy odometry guess recover ground truth; real data optimum" *
    doctest::test_suite("datasets")) {
  const auto noisy =
      graph::read_isam_2d(testkit::dataset_file("manhattan3500", "isam/manhattanOlson3500.txt"));
  // Noise-free edges printed with 6 digits: snapped to the grid (0.5 m, π/2) they chain to the exact ground
  // truth.
  const auto gt = graph::read_isam_ground_truth_2d(
      testkit::dataset_file("manhattan3500", "isam/groundtruth/manhattanOlson3500_groundtruth.txt"),
      graph::GroundTruthOptions{0.5, lie::kPi / 2, 1e-5});
  REQUIRE(noisy.poses.size() == 3500);
  REQUIRE(noisy.edges.size() == 5598);
  REQUIRE(gt.poses.size() == 3500);
  CHECK(gt.max_edge_translation_error < 1e-12);
  CHECK(gt.max_edge_rotation_error < 1e-12);
  const std::vector<lie::SE2>& truth = gt.poses;

  // Ground-truth measurements on the noisy file's edges and information (the files have the same (i, j)
  // sequence).
  graph::PoseGraph2D exact = noisy;
  for (auto& e : exact.edges) e.measurement = truth[e.i].inverse() * truth[e.j];
  Options o;
  o.initial_guess = InitialGuess::odometry;
  const Estimate2D odometry_guess = initial_estimate(noisy, o);  // the noisy odometry chain
  CHECK(max_error(odometry_guess.poses, truth) > 1.0);

  SUBCASE("noise-free") {
    Options t;
    t.initial_guess = InitialGuess::supplied;
    t.function_tolerance = 1e-16;
    t.gradient_tolerance = 1e-16;
    t.parameter_tolerance = 1e-14;
    t.max_iterations = 200;
    const Result2D r = optimize(exact, t, &odometry_guess);
    MESSAGE("noise-free Manhattan3500: " << r.summary.report << "; max pose error "
                                         << max_error(r.estimate.poses, truth));
    CHECK(r.summary.termination == Termination::converged);
    CHECK(max_error(r.estimate.poses, truth) < 1e-6);
  }

  SUBCASE("real data from the odometry chain reaches the optimum found from ground truth") {
    const Result2D r = optimize(noisy, o);
    Options from_truth;
    from_truth.initial_guess = InitialGuess::supplied;
    const Estimate2D truth_guess{truth, {}};
    const Result2D best = optimize(noisy, from_truth, &truth_guess);
    MESSAGE("Manhattan3500 from odometry: initial cost "
            << r.summary.initial_cost << ", final cost " << r.summary.final_cost << ", iterations "
            << r.summary.iterations << ", normalized chi2 " << r.summary.normalized_chi2 << ", time "
            << r.summary.total_time_s << " s, max pose error vs truth " << max_error(r.estimate.poses, truth)
            << "; from ground truth: final cost " << best.summary.final_cost);
    CHECK(r.summary.termination == Termination::converged);
    CHECK(r.summary.final_cost < 1e-3 * r.summary.initial_cost);
    CHECK(r.summary.final_cost == doctest::Approx(best.summary.final_cost).epsilon(1e-5));
    CHECK(r.summary.residual_dimension == 3 * 5598);
    CHECK(r.summary.free_parameter_dimension == 3 * 3499);
    CHECK(r.summary.normalized_chi2 > 0.8);
    CHECK(r.summary.normalized_chi2 < 1.3);
  }
}
