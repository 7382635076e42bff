// app::solve and app::marginals on small synthetic graphs, 2D and 3D: the app's solve is pgo::optimize with
// SolveOptions' fields, bit for bit; its marginals are the cov queries at the given poses, bit for bit
// (pairs: 6 × 6 in 2D, 12 × 12 in 3D; ids: one joint); read_graph reads a written file back in its dimension;
// bad options and requests name what is wrong.
#include <doctest/doctest.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/marginals.hpp"
#include "app/solve.hpp"
#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "graph/io.hpp"
#include "kit/test_kit.hpp"
#include "pgo/optimize.hpp"
#include "sim/two_robot_test_graphs.hpp"

using namespace keel;
using keel::testkit::contains;
using keel::testkit::message_of;
namespace fs = std::filesystem;

TEST_CASE("app::solve is pgo::optimize with the options' fields, bit for bit, in 2D and 3D") {
  app::SolveOptions o;
  o.robust = "cauchy";
  o.robust_parameter = 2.0;
  o.max_iterations = 30;
  const pgo::Options po = o.pgo_options();
  CHECK(po.robust_kernel == pgo::RobustKernel::cauchy);
  CHECK(po.initial_guess == pgo::InitialGuess::odometry);
  CHECK(po.max_iterations == 30);

  const auto g2 = sim::testing::square_laps<lie::SE2>(2, 4, 51).graph;
  const auto s2 = app::solve(g2, o);
  const auto r2 = pgo::optimize(g2, po);
  REQUIRE(s2.graph.poses.size() == r2.estimate.poses.size());
  for (std::size_t k = 0; k < r2.estimate.poses.size(); ++k)
    CHECK(s2.graph.poses[k].matrix() == r2.estimate.poses[k].matrix());
  CHECK(s2.summary.final_cost == r2.summary.final_cost);
  CHECK(s2.edges.size() == g2.edges.size());
  CHECK(s2.graph.edges.size() == g2.edges.size());

  const auto g3 = sim::testing::square_laps<lie::SE3>(2, 4, 53).graph;
  const auto s3 = app::solve(g3, o);
  const auto r3 = pgo::optimize(g3, po);
  for (std::size_t k = 0; k < r3.estimate.poses.size(); ++k)
    CHECK(s3.graph.poses[k].matrix() == r3.estimate.poses[k].matrix());
  CHECK(s3.summary.final_cost == r3.summary.final_cost);

  // A supplied initial guess: starting at the solution, the solve stays there.
  app::SolveOptions supplied = o;
  supplied.init = "supplied";
  pgo::Estimate2D at{s2.graph.poses, {}};
  const auto again = app::solve(g2, supplied, &at);
  CHECK(again.summary.final_cost <= s2.summary.final_cost * (1 + 1e-9));
  // '-' stands for '_' in the initial guess's name.
  app::SolveOptions as_read;
  as_read.init = "as-read";
  CHECK(as_read.pgo_options().initial_guess == pgo::InitialGuess::as_read);
}

TEST_CASE("bad solve options name the field and the valid values") {
  app::SolveOptions o;
  o.init = "chained";
  CHECK(contains(message_of([&] { (void)o.pgo_options(); }), "chained"));
  o.init = "odometry";
  o.robust = "tukey";
  CHECK(contains(message_of([&] { (void)o.pgo_options(); }), "tukey"));
  o.robust = "huber";
  o.robust_parameter = -1.0;
  CHECK_THROWS_AS((void)o.pgo_options(), std::invalid_argument);
}

TEST_CASE("app::marginals are the cov queries at the given poses, 2D and 3D") {
  const auto g2 = sim::testing::square_laps<lie::SE2>(2, 4, 55).graph;
  const auto s2 = app::solve(g2);
  const pgo::Estimate2D at2{s2.graph.poses, {}};
  app::MarginalsRequest pairs;
  pairs.pairs = {{1, 40}, {5, 6}, {79, 0}};
  pairs.threads = 2;
  const auto m2 = app::marginals(g2, at2, pairs);
  CHECK(m2.dimension == 2);
  const cov::MarginalCovariance mc2(cov::information_matrix(g2, at2.poses));
  const auto ref2 = cov::pair_marginals_2d(mc2, pairs.pairs, 1);
  REQUIRE(m2.pairs.size() == 3);
  for (std::size_t k = 0; k < 3; ++k) {
    CHECK(m2.pairs[k].rows() == 6);
    CHECK(m2.pairs[k] == lie::MatX(ref2[k]));
  }
  CHECK(m2.joint.size() == 0);
  CHECK(m2.factor.size == mc2.summary().size);

  const auto g3 = sim::testing::square_laps<lie::SE3>(2, 4, 57).graph;
  const auto s3 = app::solve(g3);
  const pgo::Estimate3D at3{s3.graph.poses};
  const auto m3 = app::marginals(g3, at3, pairs);
  CHECK(m3.dimension == 3);
  const cov::MarginalCovariance mc3(cov::information_matrix(g3, at3.poses));
  const auto ref3 = mc3.joint_many({{1, 40}, {5, 6}, {79, 0}}, 1);
  for (std::size_t k = 0; k < 3; ++k) {
    CHECK(m3.pairs[k].rows() == 12);
    CHECK(m3.pairs[k] == ref3[k]);
  }
  app::MarginalsRequest ids;
  ids.ids = {3, 3, 70};
  const auto j3 = app::marginals(g3, at3, ids);
  CHECK(j3.pairs.empty());
  CHECK(j3.joint == mc3.joint({3, 3, 70}));
}

TEST_CASE("a marginals request with neither or both queries, or an unknown id, is refused") {
  const auto g = sim::testing::square_laps<lie::SE2>(1, 4, 59).graph;
  const pgo::Estimate2D at{app::solve(g).graph.poses, {}};
  app::MarginalsRequest r;
  CHECK(contains(message_of([&] { (void)app::marginals(g, at, r); }), "give exactly one of pairs and ids"));
  r.pairs = {{0, 1}};
  r.ids = {2};
  CHECK(contains(message_of([&] { (void)app::marginals(g, at, r); }), "give exactly one of pairs and ids"));
  r.ids.clear();
  r.pairs = {{0, 400}};
  CHECK(contains(message_of([&] { (void)app::marginals(g, at, r); }), "400 is not a pose id"));
  r.pairs.clear();
  r.ids = {400};
  CHECK_THROWS_AS((void)app::marginals(g, at, r), std::out_of_range);
}

TEST_CASE("read_graph reads a file in the dimension of its first record") {
  const fs::path dir = fs::temp_directory_path() / "keel_app_test_read_graph";
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto s2 = sim::testing::square_laps<lie::SE2>(1, 4, 61);
  auto s3 = sim::testing::square_laps<lie::SE3>(1, 4, 63);
  auto g2 = s2.graph;
  auto g3 = s3.graph;
  g2.poses = s2.truth;
  g3.poses = s3.truth;
  graph::write_pose_graph(g2, dir / "a.g2o");
  graph::write_pose_graph(g3, dir / "b.g2o");
  const auto r2 = app::read_graph(dir / "a.g2o");
  const auto r3 = app::read_graph(dir / "b.g2o");
  REQUIRE(std::holds_alternative<graph::PoseGraph2D>(r2));
  REQUIRE(std::holds_alternative<graph::PoseGraph3D>(r3));
  CHECK(std::get<graph::PoseGraph2D>(r2).edges.size() == g2.edges.size());
  CHECK(std::get<graph::PoseGraph3D>(r3).edges.size() == g3.edges.size());
  fs::remove_all(dir);
}
