// MarginalCovariance against a dense inverse of H; batched queries against single ones; thread independence.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <stdexcept>
#include <string>
#include <vector>

#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "cov/test_graphs.hpp"
#include "kit/test_kit.hpp"

using namespace keel;
using namespace keel::cov;

namespace {

// Σ of every variable (fixed pose: zero rows/columns), as a dense matrix in variable order.
MatX dense_covariance(const SparseInformation& H) {
  const MatX Sr = H.dense().inverse();
  std::vector<int> start(static_cast<std::size_t>(H.num_variables()) + 1, 0);
  for (int v = 0; v < H.num_variables(); ++v) start[v + 1] = start[v] + H.variable_dim(v);
  MatX S = MatX::Zero(start.back(), start.back());
  for (int a = 0; a < H.num_variables(); ++a)
    for (int b = 0; b < H.num_variables(); ++b) {
      if (H.offset[a] < 0 || H.offset[b] < 0) continue;
      S.block(start[a], start[b], H.variable_dim(a), H.variable_dim(b)) =
          Sr.block(H.offset[a], H.offset[b], H.variable_dim(a), H.variable_dim(b));
    }
  return S;
}

MatX dense_joint(const SparseInformation& H, const MatX& S, const std::vector<int>& vars) {
  std::vector<int> start(static_cast<std::size_t>(H.num_variables()) + 1, 0);
  for (int v = 0; v < H.num_variables(); ++v) start[v + 1] = start[v] + H.variable_dim(v);
  int total = 0;
  for (int v : vars) total += H.variable_dim(v);
  MatX J(total, total);
  int ra = 0;
  for (int a : vars) {
    int cb = 0;
    for (int b : vars) {
      J.block(ra, cb, H.variable_dim(a), H.variable_dim(b)) =
          S.block(start[a], start[b], H.variable_dim(a), H.variable_dim(b));
      cb += H.variable_dim(b);
    }
    ra += H.variable_dim(a);
  }
  return J;
}

double rel_err(const MatX& a, const MatX& b) { return (a - b).norm() / b.norm(); }

}  // namespace

TEST_CASE("joint marginals equal the dense inverse of H (2D with landmarks, every ordering, both gauges)") {
  // Near the origin so that H is well conditioned (cond ≈ 1e6): the dense inverse is then a 1e-10 reference.
  // (Far from the origin, the lever arms of the Lie-algebra perturbation make cond(H) ≈ 1e9 and both inverses
  // lose digits.)
  const auto tg = test::small_graph_2d(14, 4, /*seed=*/21, /*noise=*/0.05, lie::SE2(-5.0, 3.0, 0.3));
  const std::vector<std::vector<int>> queries = {{3, 7, 1}, {0, 5},      {13, 14, 2, 17},
                                                 {6},       {15, 15, 9}, {16, 0, 12}};
  for (const Gauge kind : {Gauge::fix_pose, Gauge::prior}) {
    GaugeOptions gauge;
    gauge.kind = kind;
    if (kind == Gauge::prior) gauge.prior_information = Mat3::Identity() * 50.0;
    const auto H = information_matrix(tg.graph, tg.estimate, tg.landmarks, gauge);
    const MatX S = dense_covariance(H);
    const VecX eig = Eigen::SelfAdjointEigenSolver<MatX>(H.dense()).eigenvalues();
    REQUIRE(eig.maxCoeff() / eig.minCoeff() < 1e7);
    for (const Ordering o :
         {Ordering::automatic, Ordering::amd, Ordering::metis, Ordering::nesdis, Ordering::natural})
      for (const Extraction x : {Extraction::forward, Extraction::solve, Extraction::automatic})
        for (const bool supernodal : {true, false}) {
          if (x == Extraction::forward && !supernodal) continue;
          CAPTURE(to_string(o));
          CAPTURE(to_string(x));
          CAPTURE(supernodal);
          CovarianceOptions opt;
          opt.ordering = o;
          opt.supernodal = supernodal;
          opt.extraction = x;
          opt.block_columns = 4;  // several chunks even on a small graph
          const MarginalCovariance mc(H, opt);
          CHECK(mc.summary().supernodal == supernodal);
          CHECK(
              mc.summary().extraction ==
              (x == Extraction::solve || (x == Extraction::automatic && !supernodal) ? "solve" : "forward"));
          if (o != Ordering::automatic)
            CHECK(mc.summary().ordering == (o == Ordering::natural ? "natural" : to_string(o)));
          for (const auto& q : queries) {
            const MatX J = mc.joint(q);
            CHECK(J.rows() == dense_joint(H, S, q).rows());
            CHECK(rel_err(J, dense_joint(H, S, q)) < 1e-10);
            CHECK((J - J.transpose()).norm() == 0.0);
          }
          const auto many = mc.joint_many(queries, 2);
          for (std::size_t k = 0; k < queries.size(); ++k)
            CHECK(rel_err(many[k], dense_joint(H, S, queries[k])) < 1e-10);
        }
    const MarginalCovariance mc(H);
    if (kind == Gauge::fix_pose) {
      CHECK(mc.marginal(0).norm() == 0.0);
      CHECK(mc.joint({0, 4}).block(0, 3, 3, 3).norm() == 0.0);
    } else {
      CHECK(mc.marginal(0).norm() > 0.0);
    }
    CHECK(mc.variable_dim(15) == 2);
    CHECK(mc.num_variables() == 18);
  }
}

TEST_CASE("joint marginals equal the dense inverse of H (3D)") {
  const auto tg = test::small_graph_3d(10, /*seed=*/22, /*noise=*/0.05);
  const auto H = information_matrix(tg.graph, tg.estimate);
  const MatX S = dense_covariance(H);
  const MarginalCovariance mc(H);
  for (const std::vector<int>& q : std::vector<std::vector<int>>{{1, 9}, {4, 2, 8}, {0, 3}}) {
    CHECK(rel_err(mc.joint(q), dense_joint(H, S, q)) < 1e-10);
  }
  CHECK_THROWS_AS((void)pair_marginals_2d(mc, {{1, 2}}, 1), std::invalid_argument);
}

TEST_CASE(
    "3D pair marginals equal the pair queries of joint_many and the dense inverse, with either extraction") {
  const auto tg = test::small_graph_3d(40, /*seed=*/25, /*noise=*/0.05);
  const auto H = information_matrix(tg.graph, tg.estimate);
  const MatX S = dense_covariance(H);
  const std::vector<std::pair<int, int>> pairs = {{1, 39}, {4, 2}, {0, 3}, {7, 7}, {20, 21}, {38, 5}};
  std::vector<std::vector<int>> queries;
  for (const auto& [i, j] : pairs) queries.push_back({i, j});
  for (const Extraction x : {Extraction::forward, Extraction::solve}) {
    CAPTURE(to_string(x));
    CovarianceOptions opt;
    opt.extraction = x;
    opt.block_columns = 8;
    const MarginalCovariance mc(H, opt);
    const auto p1 = pair_marginals_3d(mc, pairs, 1);
    const auto p2 = pair_marginals_3d(mc, pairs, 2);
    const auto any = pair_marginals(mc, pairs, 2);
    const auto q = mc.joint_many(queries, 1);
    REQUIRE(p1.size() == pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      CHECK(p1[k] == p2[k]);         // bitwise across thread counts
      CHECK(MatX(p1[k]) == q[k]);    // the same blocks as joint_many's
      CHECK(any[k] == MatX(p1[k]));  // the dispatching query picks the 3D one
      // the dense inverse of the 240 × 240 H is itself accurate to about cond(H)·ε ≈ 1e-10 here
      CHECK(rel_err(MatX(p1[k]), dense_joint(H, S, queries[k])) < 1e-8);
      CHECK(p1[k] == p1[k].transpose());
    }
    CHECK_THROWS_AS((void)pair_marginals_3d(mc, {{0, 40}}, 1), std::invalid_argument);
  }
  // a 2D graph is refused by the 3D query and answered 6×6 by the dispatching one
  const auto t2 = test::small_graph_2d(12, 0, /*seed=*/26, /*noise=*/0.02);
  const MarginalCovariance m2(information_matrix(t2.graph, t2.estimate));
  CHECK_THROWS_AS((void)pair_marginals_3d(m2, {{1, 2}}, 1), std::invalid_argument);
  const auto b2 = pair_marginals(m2, {{1, 2}}, 1);
  CHECK(b2.front() == MatX(pair_marginals_2d(m2, {{1, 2}}, 1).front()));
}

TEST_CASE("batched queries equal single queries; 1 and 2 threads give identical results") {
  const auto tg = test::small_graph_2d(300, 0, /*seed=*/23, /*noise=*/0.02);
  const auto H = information_matrix(tg.graph, tg.estimate);
  for (const Extraction x : {Extraction::forward, Extraction::solve}) {
    CAPTURE(to_string(x));
    CovarianceOptions opt;
    opt.block_columns = 16;
    opt.extraction = x;
    const MarginalCovariance mc(H, opt);
    std::vector<std::pair<int, int>> pairs;
    std::vector<std::vector<int>> queries;
    for (int k : {1, 5, 50, 200})
      for (int i = 0; i + k < 300; i += 7) {
        pairs.emplace_back(i, i + k);
        queries.push_back({i, i + k});
      }
    const auto p1 = pair_marginals_2d(mc, pairs, 1);
    const auto p2 = pair_marginals_2d(mc, pairs, 2);
    const auto q2 = mc.joint_many(queries, 2);
    REQUIRE(p1.size() == pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      CHECK(p1[k] == p2[k]);        // bitwise: the chunks do not depend on the thread count
      CHECK(MatX(p1[k]) == q2[k]);  // same plan → same numbers
      if (k % 10 == 0) CHECK(rel_err(mc.joint(queries[k]), MatX(p1[k])) < 1e-12);
    }
    CHECK_THROWS_AS((void)pair_marginals_2d(mc, {{0, 300}}, 1), std::invalid_argument);
    CHECK_THROWS_AS((void)mc.joint({-1}), std::out_of_range);
  }
  // the two methods agree
  CovarianceOptions fwd, sol;
  fwd.extraction = Extraction::forward;
  sol.extraction = Extraction::solve;
  const MarginalCovariance mf(H, fwd), ms(H, sol);
  const std::vector<std::vector<int>> q = {{1, 299, 150}, {7, 8}, {250}};
  const auto rf = mf.joint_many(q, 2), rs = ms.joint_many(q, 2);
  for (std::size_t k = 0; k < q.size(); ++k) CHECK(rel_err(rf[k], rs[k]) < 1e-10);
}

TEST_CASE(
    "linear map covariances K_u Σ K_vᵀ equal the dense inverse, with either extraction and any threads") {
  // 2D with landmarks and 3D: maps over one, two and three variables (a repeat, the gauge pose, a landmark),
  // with rows other than the variables' dimensions; every asked pair against K_u S K_vᵀ from the dense S.
  const auto t2 = test::small_graph_2d(30, 3, /*seed=*/31, /*noise=*/0.05, lie::SE2(-2.0, 1.0, 0.2));
  const auto t3 = test::small_graph_3d(25, /*seed=*/32, /*noise=*/0.05);
  const SparseInformation H2 = information_matrix(t2.graph, t2.estimate, t2.landmarks, GaugeOptions{});
  const SparseInformation H3 = information_matrix(t3.graph, t3.estimate);
  core::Rng rng(33);
  for (const SparseInformation* H : {&H2, &H3}) {
    const int d = H->variable_dim(0);
    CAPTURE(d);
    std::vector<int> start(static_cast<std::size_t>(H->num_variables()) + 1, 0);
    for (int v = 0; v < H->num_variables(); ++v) start[v + 1] = start[v] + H->variable_dim(v);
    // K as a dense row block over every variable
    auto dense_k = [&](const LinearMap& m) {
      MatX K = MatX::Zero(m.coefficients.front().rows(), start.back());
      for (std::size_t t = 0; t < m.vars.size(); ++t)
        K.middleCols(start[m.vars[t]], H->variable_dim(m.vars[t])) += m.coefficients[t];
      return K;
    };
    auto random_map = [&](int rows, const std::vector<int>& vars) {
      LinearMap m;
      m.vars = vars;
      for (const int v : vars)
        m.coefficients.push_back(testkit::random_matrix(rng, rows, H->variable_dim(v)));
      return m;
    };
    const int last = H->num_variables() - 1;  // a landmark in 2D
    std::vector<LinearMap> maps = {
        random_map(d, {3, 9}),     random_map(2, {0, 5}),  // the gauge pose: no term
        random_map(d, {7, 7, 12}), random_map(1, {last}),
        random_map(d, {20, 1}),    random_map(d + 1, {24, 2, 13})};
    maps.push_back(random_map(d, {0}));  // only the gauge pose: zero covariance
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t u = 0; u < maps.size(); ++u)
      for (std::size_t v = 0; v < maps.size(); ++v) pairs.emplace_back(u, v);
    const MatX S = dense_covariance(*H);
    for (const Extraction x : {Extraction::forward, Extraction::solve}) {
      CAPTURE(to_string(x));
      CovarianceOptions opt;
      opt.extraction = x;
      opt.block_columns = 5;  // several chunks
      const MarginalCovariance mc(*H, opt);
      const auto c1 = linear_map_covariances(mc, maps, pairs, 1);
      const auto c2 = linear_map_covariances(mc, maps, pairs, 2);
      REQUIRE(c1.size() == pairs.size());
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        const auto [u, v] = pairs[k];
        CAPTURE(u);
        CAPTURE(v);
        CHECK(c1[k] == c2[k]);  // bitwise across thread counts
        const MatX ref = dense_k(maps[u]) * S * dense_k(maps[v]).transpose();
        CHECK(c1[k].rows() == ref.rows());
        CHECK(c1[k].cols() == ref.cols());
        if (u == maps.size() - 1 || v == maps.size() - 1)
          CHECK(c1[k].norm() == 0.0);
        else
          CHECK(rel_err(c1[k], ref) < 1e-9);
        if (u == v) CHECK((c1[k] - c1[k].transpose()).norm() == 0.0);
      }
      // J Σ Jᵀ of an edge's residual map equals J P Jᵀ from the pair marginal
      const std::pair<int, int> edge{4, 11};
      const MatX P = pair_marginals(mc, {edge}, 1).front();
      const LinearMap m = random_map(d, {edge.first, edge.second});
      MatX J(d, 2 * d);
      J << m.coefficients[0], m.coefficients[1];
      CHECK(rel_err(linear_map_covariances(mc, {m}, {{0, 0}}).front(), J * P * J.transpose()) < 1e-12);
      // malformed input: a clear error
      CHECK_THROWS_AS((void)linear_map_covariances(mc, maps, {{0, maps.size()}}), std::out_of_range);
      CHECK_THROWS_AS((void)linear_map_covariances(mc, {random_map(d, {H->num_variables()})}, {{0, 0}}),
                      std::out_of_range);
      LinearMap wrong = random_map(d, {1, 2});
      wrong.coefficients[1] = MatX::Ones(d, d + 1);
      CHECK_THROWS_WITH_AS((void)linear_map_covariances(mc, {wrong}, {{0, 0}}),
                           doctest::Contains("term 1 (pose 2)"), std::invalid_argument);
      CHECK_THROWS_AS((void)linear_map_covariances(mc, {LinearMap{}}, {{0, 0}}), std::invalid_argument);
      LinearMap unpaired;
      unpaired.vars = {1, 2};
      unpaired.coefficients = {MatX::Ones(d, d)};
      CHECK_THROWS_AS((void)linear_map_covariances(mc, {unpaired}, {{0, 0}}), std::invalid_argument);
    }
  }
}

TEST_CASE("a variable without information is reported by name") {
  auto tg = test::small_graph_2d(6, 0, /*seed=*/24, /*noise=*/0.0);
  tg.graph.poses.push_back(lie::SE2(1.0, 2.0, 0.0));
  tg.estimate.push_back(lie::SE2(1.0, 2.0, 0.0));  // pose 6: no edge touches it
  const auto H = information_matrix(tg.graph, tg.estimate);
  CHECK(testkit::throws_with<std::runtime_error>([&] { const MarginalCovariance mc(H); },
                                                 "not positive definite"));
  CHECK(testkit::throws_with<std::runtime_error>([&] { const MarginalCovariance mc(H); }, "pose 6"));
  CovarianceOptions bad;
  bad.block_columns = 0;
  CHECK_THROWS_AS(bad.validate(), std::invalid_argument);
  bad.block_columns = 8;
  bad.supernodal = false;
  bad.extraction = Extraction::forward;
  CHECK_THROWS_AS(bad.validate(), std::invalid_argument);
  CHECK(testkit::throws_with<std::invalid_argument>([&] { bad.validate(); }, "CovarianceOptions"));
}

TEST_CASE("Ordering and Extraction names round-trip; an unknown name is an error naming the valid ones") {
  for (Ordering o :
       {Ordering::automatic, Ordering::amd, Ordering::metis, Ordering::nesdis, Ordering::natural})
    CHECK(ordering_from_string(to_string(o)) == o);
  for (Extraction x : {Extraction::automatic, Extraction::forward, Extraction::solve})
    CHECK(extraction_from_string(to_string(x)) == x);
  CHECK(to_string(Ordering::automatic) == "auto");
  CHECK(extraction_from_string("solve") == Extraction::solve);
  CHECK(testkit::throws_with<std::invalid_argument>(
      [] { (void)ordering_from_string("colamd"); },
      "unknown linalg::Ordering 'colamd' (valid: auto, amd, metis, nesdis, natural)"));
  CHECK(testkit::throws_with<std::invalid_argument>(
      [] { (void)extraction_from_string("automatic"); },
      "unknown cov::Extraction 'automatic' (valid: auto, forward, solve)"));
}
