// chain_joint (the closed form of an odometry chain's joint marginal) against MarginalCovariance::joint (the
// factorization of H) on random chains in 2D and 3D, linearized away from the truth, with reversed and
// parallel edges; bad chains give located errors.
#include <doctest/doctest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "cov/chain.hpp"
#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "cov/test_graphs.hpp"
#include "kit/test_kit.hpp"

using namespace keel;
using namespace keel::cov;
using keel::testkit::contains;
using keel::testkit::message_of;

namespace {

// The graph's consecutive edges only, every third step also measured backwards (a reversed parallel edge).
template <class Graph>
Graph chain_of(const Graph& g) {
  Graph c;
  c.poses = g.poses;
  for (const auto& e : g.edges)
    if (e.j == e.i + 1) {
      c.edges.push_back(e);
      if (e.i % 3 == 0) {
        auto r = e;
        std::swap(r.i, r.j);
        r.measurement = e.measurement.inverse();
        c.edges.push_back(r);
      }
    }
  return c;
}

double chain_rel_err(const lie::MatX& a, const lie::MatX& b) { return (a - b).norm() / b.norm(); }

}  // namespace

TEST_CASE("chain_joint equals the factorized H's joint marginals (2D and 3D, away from the truth)") {
  const std::vector<std::vector<int>> queries = {{1, 9}, {4, 2, 8, 4}, {0, 3, 11}, {11, 5, 0, 1, 2}};
  for (const unsigned seed : {3u, 4u}) {
    const auto g2 = test::small_graph_2d(12, 0, seed, 0.05);
    const auto c2 = chain_of(g2.graph);
    const MarginalCovariance m2(information_matrix(c2, g2.estimate));
    const auto g3 = test::small_graph_3d(12, seed, 0.05);
    const auto c3 = chain_of(g3.graph);
    const MarginalCovariance m3(information_matrix(c3, g3.estimate));
    for (const auto& q : queries) {
      CHECK(chain_rel_err(chain_joint(c2, g2.estimate, q), m2.joint(q)) < 1e-9);
      CHECK(chain_rel_err(chain_joint(c3, g3.estimate, q), m3.joint(q)) < 1e-9);
    }
  }
}

TEST_CASE("chain_joint: a graph that is not a chain is refused by name") {
  const auto g = test::small_graph_2d(8, 0, 5, 0.0);
  auto c = chain_of(g.graph);
  auto loop = c;
  loop.edges.push_back(g.graph.edges.back());  // (0, n/2)
  CHECK(contains(message_of([&] { (void)chain_joint(loop, g.estimate, {1}); }), "not consecutive poses"));
  auto gap = c;
  std::erase_if(gap.edges, [](const graph::Edge2& e) { return std::min(e.i, e.j) == 4; });
  CHECK(
      contains(message_of([&] { (void)chain_joint(gap, g.estimate, {1}); }), "pose 5 has no edge to pose 4"));
  CHECK(contains(message_of([&] { (void)chain_joint(c, g.estimate, {8}); }), "pose id 8 is not in 0 … 7"));
}
