// app::solve and app::marginals on small synthetic graphs, 2D and 3D: the app's solve is pgo::optimize with
// the back end's options, bit for bit; its marginals are the cov queries at the given poses, bit for bit
// (pairs: 6 × 6 in 2D, 12 × 12 in 3D; ids: one joint); read_graph reads a written file back in its dimension;
// bad options and requests name what is wrong.
#include <doctest/doctest.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "app/marginals.hpp"
#include "app/solve.hpp"
#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "graph/io.hpp"
#include "kit/test_kit.hpp"
#include "pgo/certified.hpp"
#include "pgo/optimize.hpp"
#include "sim/two_robot_test_graphs.hpp"

using namespace keel;
using keel::testkit::contains;
using keel::testkit::message_of;
namespace fs = std::filesystem;

TEST_CASE("app::solve is pgo::optimize with the back end's options, bit for bit, in 2D and 3D") {
  app::MaximumLikelihood o;
  CHECK(o.options.initial_guess == pgo::InitialGuess::odometry);  // keel solve's default
  o.options.robust_kernel = pgo::RobustKernel::cauchy;
  o.options.robust_parameter = 2.0;
  o.options.max_iterations = 30;
  const pgo::Options po = o.options;  // constant_poses {0}: the graphs' gauge pose
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
  app::MaximumLikelihood supplied = o;
  supplied.options.initial_guess = pgo::InitialGuess::supplied;
  pgo::Estimate2D at{s2.graph.poses, {}};
  const auto again = app::solve(g2, supplied, &at);
  CHECK(again.summary.final_cost <= s2.summary.final_cost * (1 + 1e-9));
  // '-' stands for '_' in the initial guess's name.
  CHECK(app::initial_guess_from_name("as-read") == pgo::InitialGuess::as_read);
}

TEST_CASE("bad solve options name the field and the valid values") {
  CHECK(contains(message_of([] { (void)app::initial_guess_from_name("chained"); }), "chained"));
  CHECK(contains(message_of([] { (void)pgo::robust_kernel_from_string("tukey"); }), "tukey"));
  const auto g = sim::testing::square_laps<lie::SE2>(2, 4, 51).graph;
  app::MaximumLikelihood o;
  o.options.robust_kernel = pgo::RobustKernel::huber;
  o.options.robust_parameter = -1.0;
  CHECK(contains(message_of([&] { (void)app::solve(g, o); }), "robust_parameter"));
  app::Certified c;
  c.options.max_rank = 1;
  CHECK(contains(message_of([&] { (void)app::solve_certified(g, c); }), "max_rank must be >= 2"));
  c.options.max_rank = 10;
  c.options.gap_tolerance = 0.0;
  CHECK(contains(message_of([&] { (void)app::solve_certified(g, c); }), "gap_tolerance"));
  // The information a back end reads.
  CHECK(app::information_check(app::SolveBackend{app::Certified{}}) ==
        graph::InformationCheck::diagonal_blocks);
  CHECK(app::information_check(app::SolveBackend{}) == graph::InformationCheck::positive_definite);
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

// The gauge pose k (g2o's FIX k): every solve holds pose k at its as-read value, and the optimum is the same
// up to a rigid motion. Relative poses and costs do not depend on k.
template <class G>
void check_gauge_solves(std::uint64_t seed) {
  auto g0 = sim::testing::square_laps<G>(2, 4, seed, true, true).graph;
  // Move the as-read poses off the truth, so that holding pose 2 is not holding it where the optimum has it.
  for (std::size_t v = 0; v < g0.poses.size(); ++v)
    g0.poses[v] = g0.poses[v] * G::exp(G::Tangent::Constant(0.01 * static_cast<double>(v % 5)));
  auto gk = g0;
  gk.gauge_pose = 2;
  for (const char* init : {"odometry", "as-read"}) {
    CAPTURE(init);
    app::MaximumLikelihood o;
    o.options.initial_guess = app::initial_guess_from_name(init);
    const auto s0 = app::solve(g0, o);
    const auto sk = app::solve(gk, o);
    CHECK(s0.graph.poses[0].matrix() == g0.poses[0].matrix());
    // Held, to the rounding of Ceres's parameterization of the block ((x, y, θ) in 2D, a quaternion in 3D;
    // the same holds for pose 0 in the default gauge).
    CHECK((sk.graph.poses[2].matrix() - g0.poses[2].matrix()).cwiseAbs().maxCoeff() <= 1e-15);
    CHECK_FALSE(sk.graph.poses[0].is_approx(g0.poses[0], 1e-6));
    // The same optimum up to the solver's stopping rule (|Δcost|/cost ≤ 1e-6 per step: the two runs stop
    // within ~1e-8 of each other here).
    CHECK(sk.summary.final_cost == doctest::Approx(s0.summary.final_cost).epsilon(1e-7));
    for (const auto& [i, j] : std::vector<std::pair<int, int>>{{0, 1}, {5, 60}, {79, 2}})
      CHECK((s0.graph.poses[i].inverse() * s0.graph.poses[j])
                .is_approx(sk.graph.poses[i].inverse() * sk.graph.poses[j], 1e-3));
  }
  // The certified solve: the same F and lower bound (gauge invariant), the returned estimate moved rigidly so
  // that pose 2 keeps its as-read value.
  const auto c0 = app::solve_certified(g0);
  const auto ck = app::solve_certified(gk);
  REQUIRE(c0.summary.certificate.certified);
  REQUIRE(ck.summary.certificate.certified);
  CHECK(ck.summary.final_cost == c0.summary.final_cost);
  CHECK(ck.summary.certificate.bound.lower == c0.summary.certificate.bound.lower);
  CHECK(ck.summary.certificate.bound.upper == c0.summary.certificate.bound.upper);
  CHECK(ck.graph.poses[2].matrix() == g0.poses[2].matrix());
  CHECK(pgo::isotropic_cost(gk, ck.graph.poses) == doctest::Approx(c0.summary.final_cost).epsilon(1e-10));
  CHECK(ck.anisotropic_cost == doctest::Approx(c0.anisotropic_cost).epsilon(1e-10));
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{0, 1}, {5, 60}, {79, 2}})
    CHECK((c0.graph.poses[i].inverse() * c0.graph.poses[j])
              .is_approx(ck.graph.poses[i].inverse() * ck.graph.poses[j], 1e-9));
}

TEST_CASE("the graph's gauge pose is held by solve and the certified solve; costs and bounds do not change") {
  check_gauge_solves<lie::SE2>(61);
  check_gauge_solves<lie::SE3>(63);
}

// Marginals in the gauge at pose k. A left perturbation T = exp(ξ^) T̄ is in the world frame, and a common
// motion exp(γ^) of every pose leaves every residual unchanged exactly, so the gauge-k perturbation is ξ_v −
// ξ_k of the gauge-0 one: Σ^k_ij = Σ_ij − Σ_ik − Σ_kj + Σ_kk (exact for the linearized problem), the
// reference here.
template <class G, class Estimate>
void check_gauge_marginals(std::uint64_t seed) {
  constexpr int d = G::DoF;
  const auto g0 = sim::testing::square_laps<G>(2, 4, seed, true, true).graph;
  auto gk = g0;
  gk.gauge_pose = 2;
  Estimate at;
  at.poses = app::solve(g0).graph.poses;
  app::MarginalsRequest r;
  r.ids = {2, 4, 7, 0};  // block 0 is the gauge pose k = 2
  const auto m0 = app::marginals(g0, at, r);
  const auto mk = app::marginals(gk, at, r);
  const auto block = [&](const lie::MatX& S, int a, int b) { return lie::MatX(S.block(a * d, b * d, d, d)); };
  CHECK(block(mk.joint, 0, 0).cwiseAbs().maxCoeff() == 0.0);  // pose k's own marginal
  CHECK(block(mk.joint, 0, 2).cwiseAbs().maxCoeff() == 0.0);
  const double scale = m0.joint.cwiseAbs().maxCoeff();
  for (int a = 1; a < 4; ++a)
    for (int b = 1; b < 4; ++b) {
      const lie::MatX ref =
          block(m0.joint, a, b) - block(m0.joint, a, 0) - block(m0.joint, 0, b) + block(m0.joint, 0, 0);
      CHECK((block(mk.joint, a, b) - ref).cwiseAbs().maxCoeff() <= 1e-9 * scale);
    }
  // Pose 0 is no longer fixed; the covariance of ξ_7 − ξ_4 (the relative pose's, up to its adjoint) is the
  // same in both gauges.
  CHECK(block(mk.joint, 3, 3).cwiseAbs().maxCoeff() > 1e-6 * scale);
  const auto rel = [&](const lie::MatX& S) {
    return lie::MatX(block(S, 1, 1) + block(S, 2, 2) - block(S, 1, 2) - block(S, 2, 1));
  };
  CHECK((rel(mk.joint) - rel(m0.joint)).cwiseAbs().maxCoeff() <= 1e-9 * rel(m0.joint).cwiseAbs().maxCoeff());
}

TEST_CASE("marginals are reported in the graph's gauge: pose k's block is zero, relative covariances agree") {
  check_gauge_marginals<lie::SE2, pgo::Estimate2D>(65);
  check_gauge_marginals<lie::SE3, pgo::Estimate3D>(67);
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
