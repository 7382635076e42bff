// Densest-subgraph selector (pcm/densest.hpp): planted cliques above the √n barrier are recovered, the
// repaired selection is always a maximal clique no larger than the maximum, weighted and binary affinities
// agree when the weights are 1, the dense products are those of Eigen's dense product bit for bit, and bad
// inputs give clear errors.
#include <doctest/doctest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "kit/test_kit.hpp"
#include "pcm/clique.hpp"
#include "pcm/densest.hpp"
#include "pcm/densest_detail.hpp"
#include "pcm/consistency.hpp"
#include "sim/random_graph.hpp"
#include "sim/world1d.hpp"

using namespace keel::pcm;
using keel::sim::random_graph;
using keel::testkit::contains;
using keel::testkit::message_of;

namespace {

bool maximal(const ConsistencyGraph& g, const std::vector<int>& s) {
  for (int v = 0; v < g.size(); ++v) {
    if (std::binary_search(s.begin(), s.end(), v)) continue;
    bool all = true;
    for (int w : s) all = all && g.adjacent(v, w);
    if (all) return false;
  }
  return true;
}

// bench_clique's world1d_m100_w<w>: the consistency graph at γ(11 %) of a 1D world of the Fig. 2.3 generator.
ConsistencyGraph bench_world(int w) {
  const auto o = keel::sim::world1d_options_with_total(keel::sim::World1DOptions{}, 100, 0.5, 0.25);
  const auto Q = keel::sim::world1d_consistency_matrix(keel::sim::generate_world1d(o, 20180522, w));
  return ConsistencyGraph::from_threshold(Q.n, Q.q, consistency_threshold(0.11, 1));
}

}  // namespace

TEST_CASE("densest subgraph: a planted clique well above √n is recovered exactly") {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const auto [g, planted] = keel::sim::planted_clique_graph(300, 60, 0.1, seed);
    const auto r = densest_subgraph(g);
    INFO("seed " << seed);
    CHECK(r.converged);
    CHECK(r.violations == 0);
    CHECK(r.raw == planted);
    CHECK(r.selection == planted);
    CHECK(r.objective == doctest::Approx(60.0).epsilon(1e-3));
  }
}

TEST_CASE("densest subgraph: the repaired selection is a maximal clique, never above the maximum") {
  auto rng = keel::core::Rng::stream(17, 0);
  for (int trial = 0; trial < 150; ++trial) {
    const int n = 3 + static_cast<int>(rng.uniform(0.0, 38.0));
    const double p = rng.uniform(0.05, 0.95);
    const auto g = random_graph(n, p, 1000 + static_cast<std::uint64_t>(trial));
    const auto r = densest_subgraph(g);
    INFO("trial " << trial << ": n " << n << ", p " << p);
    REQUIRE(!r.selection.empty());
    CHECK(g.is_clique(r.selection));
    CHECK(maximal(g, r.selection));
    CHECK(static_cast<int>(r.selection.size()) <= static_cast<int>(maximum_clique_exact(g).clique.size()));
    CHECK(std::is_sorted(r.raw.begin(), r.raw.end()));
    long long v = 0;
    for (std::size_t a = 0; a < r.raw.size(); ++a)
      for (std::size_t b = a + 1; b < r.raw.size(); ++b) v += g.adjacent(r.raw[a], r.raw[b]) ? 0 : 1;
    CHECK(v == r.violations);
  }
}

TEST_CASE("densest subgraph: complete and empty graphs, determinism") {
  ConsistencyGraph k(12);
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j) k.add_edge(i, j);
  const auto all = densest_subgraph(k);
  CHECK(all.selection.size() == 12);
  CHECK(all.violations == 0);
  CHECK(all.objective == doctest::Approx(12.0));
  const auto none = densest_subgraph(ConsistencyGraph(9));
  CHECK(none.selection.size() == 1);
  CHECK(densest_subgraph(ConsistencyGraph(0)).selection.empty());
  const auto g = random_graph(120, 0.4, 5);
  const auto a = densest_subgraph(g), b = densest_subgraph(g);
  CHECK(a.selection == b.selection);
  CHECK(a.raw == b.raw);
  CHECK(a.objective == b.objective);
}

TEST_CASE("densest subgraph: unit weights equal the binary problem; weights steer the choice") {
  const auto g = keel::sim::planted_clique_graph(150, 35, 0.1, 9).graph;
  const int n = g.size();
  std::vector<double> ones(static_cast<std::size_t>(n) * n, 1.0);
  const auto w = densest_subgraph(g, ones), b = densest_subgraph(g);
  CHECK(w.selection == b.selection);
  CHECK(w.objective == doctest::Approx(b.objective));
  // Two disjoint triangles: the one with the heavier edges wins.
  ConsistencyGraph t(6, {{0, 1}, {1, 2}, {0, 2}, {3, 4}, {4, 5}, {3, 5}});
  std::vector<double> aff(36, 0.0);
  auto set = [&](int i, int j, double x) { aff[i * 6 + j] = aff[j * 6 + i] = x; };
  set(0, 1, 0.3), set(1, 2, 0.3), set(0, 2, 0.3), set(3, 4, 0.9), set(4, 5, 0.9), set(3, 5, 0.9);
  CHECK(densest_subgraph(t, aff).selection == std::vector<int>{3, 4, 5});
  set(0, 1, 1.0), set(1, 2, 1.0), set(0, 2, 1.0);
  CHECK(densest_subgraph(t, aff).selection == std::vector<int>{0, 1, 2});
}

TEST_CASE("densest subgraph: bad inputs give clear errors") {
  ConsistencyGraph g(3, {{0, 1}});
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, std::vector<double>(8, 0.5)); }),
                 "affinity has 8 entries, expected n² = 9"));
  std::vector<double> a(9, 0.5);
  a[1] = 1.5;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, a); }), "affinity(0, 1) = 1.5 is not in [0, 1]"));
  a[1] = 0.4;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, a); }), "not symmetric"));
  DensestOptions o;
  o.beta = 1.0;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, o); }), "beta must be in (0, 1)"));
  o = {};
  o.max_outer = 0;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, o); }), "max_outer must be >= 1"));
  o = {};
  o.max_stalled_outer = -1;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, o); }), "max_stalled_outer must be >= 0"));
}

TEST_CASE("densest subgraph: sparse rows and dense matrices give the same answers") {
  // The two storages differ only in the order of floating-point sums. On graphs with a planted cluster at
  // densities up to 0.5 (the selector's use) and on 1D-world consistency graphs, binary and weighted, the
  // answers agree (on the planted graphs always, on the 1D worlds in all but a few runs), the objective
  // agrees to rounding and the iteration counts within 10 %. The paths part at near-ties of the backtracking
  // test F⁺ >= F − eps (measured on bench_clique's family: the same selections on all 49 planted and 1D
  // graphs, inner iteration counts apart by up to 6 % on 1D worlds of m = 1000 … 2000); where the homotopy
  // has to raise the penalty by orders of magnitude (a 1D world here, dense random graphs at p > 0.8) the
  // paths can end at different local maxima, each a maximal clique.
  auto rng = keel::core::Rng::stream(29, 0);
  int world_runs = 0, world_same = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const bool planted = trial < 18;
    keel::pcm::ConsistencyGraph g;
    if (planted) {
      const int n = 20 + static_cast<int>(rng.uniform(0.0, 180.0));
      g = keel::sim::planted_clique_graph(n, n / 8 + 2, rng.uniform(0.02, 0.5), 500 + trial).graph;
    } else {
      const int m = 20 + static_cast<int>(rng.uniform(0.0, 180.0));
      const auto o = keel::sim::world1d_options_with_total(keel::sim::World1DOptions{}, m, 0.5, 0.25);
      const auto Q = keel::sim::world1d_consistency_matrix(keel::sim::generate_world1d(o, 31, trial));
      g = ConsistencyGraph::from_threshold(Q.n, Q.q, consistency_threshold(0.11, 1));
    }
    const int n = g.size();
    std::vector<double> affinity(static_cast<std::size_t>(n) * n, 0.0);
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const double a = rng.uniform(0.2, 1.0);
        affinity[static_cast<std::size_t>(i) * n + j] = affinity[static_cast<std::size_t>(j) * n + i] = a;
      }
    for (const bool weighted : {false, true}) {
      DensestOptions dense, sparse;
      dense.storage = DensestOptions::Storage::dense;
      sparse.storage = DensestOptions::Storage::sparse;
      const auto a = weighted ? densest_subgraph(g, affinity, dense) : densest_subgraph(g, dense);
      const auto b = weighted ? densest_subgraph(g, affinity, sparse) : densest_subgraph(g, sparse);
      INFO("trial " << trial << ": n " << n << (planted ? ", planted" : ", 1D world")
                    << (weighted ? ", weighted" : ", binary"));
      CHECK(!a.sparse);
      CHECK(b.sparse);
      CHECK(g.is_clique(b.selection));
      CHECK(maximal(g, b.selection));
      const bool same = a.raw == b.raw && a.selection == b.selection && a.violations == b.violations &&
                        a.converged == b.converged &&
                        std::abs(a.objective - b.objective) <= 1e-6 * a.objective &&
                        std::abs(a.inner_iterations - b.inner_iterations) <= a.inner_iterations / 10;
      if (planted) {
        CHECK(same);
      } else {
        ++world_runs;
        world_same += same ? 1 : 0;
      }
    }
  }
  CHECK(world_same >= world_runs - 2);
}

TEST_CASE("densest subgraph: a stalled homotopy stops early with the answer of max_outer") {
  // 1D-world consistency graphs of the Fig. 2.3 generator (bench_clique's world1d_m100_w*; w = 3 stalls: its
  // support keeps an inconsistent pair while d grows to ~1e11 over 1,000 outer iterations). Stopping after
  // three outer iterations that do not move u gives the same raw and repaired selections; graphs that
  // converge take exactly the same iterations either way.
  int stalls = 0;
  for (int w = 0; w < 5; ++w) {
    const auto g = bench_world(w);
    // The options before the crawl cut, which removes this stall before it starts (see the crawl-cut case).
    const auto before = DensestOptions::before_acceptance_rule();
    DensestOptions never = before;
    never.max_stalled_outer = 0;
    const auto full = densest_subgraph(g, never);
    const auto early = densest_subgraph(g, before);
    INFO("world " << w << ": " << full.outer_iterations << " outer iterations, " << early.outer_iterations
                  << " with the stall stop");
    CHECK_FALSE(full.stalled);
    CHECK(early.raw == full.raw);
    CHECK(early.selection == full.selection);
    CHECK(early.violations == full.violations);
    if (early.stalled) {
      ++stalls;
      CHECK_FALSE(early.converged);
      CHECK_FALSE(full.converged);
      CHECK(full.outer_iterations == never.max_outer);
      CHECK(early.outer_iterations < 50);
    } else {
      CHECK(early.converged == full.converged);
      CHECK(early.outer_iterations == full.outer_iterations);
      CHECK(early.inner_iterations == full.inner_iterations);
    }
  }
  CHECK(stalls >= 1);
}

TEST_CASE("densest subgraph: automatic storage is sparse below kSparseDensity and dense above") {
  CHECK(densest_subgraph(random_graph(400, 0.05, 3)).sparse);
  CHECK(!densest_subgraph(random_graph(400, 0.6, 3)).sparse);
}

TEST_CASE("densest subgraph: the byte-column product sums exactly as Eigen's dense product did") {
  // The dense storage's Au (detail::ByteAdjacency) must reproduce, bit for bit, the two products of a dense
  // 0/1 matrix of doubles that the selector used before: Eigen's matrix-vector product (all columns, summed
  // in Eigen's column blocks: n < 128 one block, 16 below n = 4000, 4 from there) and the column-by-column
  // sum over a small support. Every kernel this CPU has is checked, on u >= 0 with exact zeros.
  using keel::pcm::detail::ByteAdjacency;
  CHECK(ByteAdjacency::eigen_block(100) == 100);
  CHECK(ByteAdjacency::eigen_block(128) == 16);
  CHECK(ByteAdjacency::eigen_block(3999) == 16);
  CHECK(ByteAdjacency::eigen_block(4000) == 4);
  keel::core::Rng rng(77);
  int kernels_checked = 0;
  for (const int n : {1, 2, 9, 64, 100, 127, 128, 203, 1000, 4000}) {
    const auto g = random_graph(n, n > 1000 ? 0.5 : 0.3, static_cast<std::uint64_t>(n));
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
    for (int v = 0; v < n; ++v)
      for (int w : g.neighbors(v)) A(v, w) = 1.0;
    const ByteAdjacency bytes(g);
    for (const double keep : {1.0, 0.6, 0.2}) {  // share of non-zero entries: full product, then support sums
      Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
      std::vector<int> support;
      for (int j = 0; j < n; ++j)
        if (rng.uniform(0.0, 1.0) < keep) {
          u(j) = rng.uniform(0.0, 1.0) * std::pow(10.0, rng.uniform(-8.0, 0.0));
          support.push_back(j);
        }
      Eigen::VectorXd expected(n);
      int block = n;
      if (static_cast<int>(support.size()) * 4 > n) {
        expected.noalias() = A * u;
        block = ByteAdjacency::eigen_block(n);
      } else {
        expected.setZero();
        for (const int j : support) expected.noalias() += u(j) * A.col(j);
      }
      for (const auto kernel : {ByteAdjacency::Kernel::automatic, ByteAdjacency::Kernel::generic,
                                ByteAdjacency::Kernel::avx2, ByteAdjacency::Kernel::avx512}) {
        if (!ByteAdjacency::available(kernel)) continue;
        ++kernels_checked;
        Eigen::VectorXd out = Eigen::VectorXd::Constant(n, -1.0);
        bytes.product(u.data(), support, block, out.data(), kernel);
        INFO("n " << n << ", support " << support.size() << ", kernel " << static_cast<int>(kernel));
        CHECK(std::memcmp(out.data(), expected.data(), sizeof(double) * static_cast<std::size_t>(n)) == 0);
      }
    }
  }
  // With one block over all columns: the sums of the sparse storage's rows (each row over its neighbours in
  // ascending order, from zero; zero entries of u add exact zeros).
  for (const int n : {1, 37, 300}) {
    const auto g = random_graph(n, 0.1, 900 + static_cast<std::uint64_t>(n));
    const ByteAdjacency bytes(g);
    std::vector<double> u(static_cast<std::size_t>(n)), out(static_cast<std::size_t>(n)), rows(u.size());
    std::vector<int> support;
    for (int j = 0; j < n; ++j) {
      u[static_cast<std::size_t>(j)] = j % 3 == 0 ? 0.0 : rng.uniform(0.0, 1.0);
      if (u[static_cast<std::size_t>(j)] != 0.0) support.push_back(j);
    }
    for (int i = 0; i < n; ++i) {
      double sum = 0.0;
      for (const int j : g.neighbors(i)) sum += u[static_cast<std::size_t>(j)];
      rows[static_cast<std::size_t>(i)] = sum;
    }
    bytes.product(u.data(), support, n, out.data());
    CHECK(std::memcmp(out.data(), rows.data(), sizeof(double) * u.size()) == 0);
  }
  CHECK(kernels_checked >= 60);  // automatic and generic everywhere
  const ByteAdjacency bytes(random_graph(10, 0.5, 1));
  std::vector<double> u(10, 1.0), out(10);
  const std::vector<int> all{0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  CHECK(contains(message_of([&] { bytes.product(u.data(), all, 0, out.data()); }), "block 0 < 1"));
}

TEST_CASE("densest subgraph: CLIPPER's line search steps") {
  // Both without the crawl cut, so that only the steps differ.
  const auto long_step = DensestOptions::before_acceptance_rule();
  DensestOptions clipper = long_step;
  clipper.line_search = DensestOptions::LineSearch::clipper;
  // A planted clique well above √n: recovered exactly, in far fewer products than with the long step (the
  // first try, a power step, is accepted at almost every iteration).
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const auto [g, planted] = keel::sim::planted_clique_graph(300, 60, 0.1, seed);
    const auto fast = densest_subgraph(g, clipper);
    const auto slow = densest_subgraph(g, long_step);
    INFO("seed " << seed << ": " << fast.products << " products against " << slow.products);
    CHECK(fast.converged);
    CHECK(fast.selection == planted);
    CHECK(fast.raw == planted);
    CHECK(fast.products * 3 < slow.products);
    CHECK(fast.products <= fast.inner_iterations + fast.outer_iterations);
  }
  // bench_clique's 1D worlds of m = 100: maximal cliques of the size the long step selects (on the family's
  // 143 graphs the size was never smaller; w = 4 selects another set of that size).
  for (int w = 0; w < 5; ++w) {
    const auto g = bench_world(w);
    const auto fast = densest_subgraph(g, clipper);
    const auto slow = densest_subgraph(g, long_step);
    INFO("world " << w);
    CHECK(g.is_clique(fast.selection));
    CHECK(maximal(g, fast.selection));
    CHECK(fast.selection.size() == slow.selection.size());
  }
}

TEST_CASE("densest subgraph: the sparse storage gives the same bits with and without byte columns") {
  // Planted cliques in G(n, p) below the dense threshold, where the sparse storage takes some of its products
  // from byte columns (byte_columns_pay). Objective and penalty as hexadecimal doubles, with the iteration
  // and product counts, recorded from the compressed rows alone (0a3eeb5): any change in the order of a sum
  // would show in their last bits.
  struct Golden {
    int n, k;
    double p;
    std::uint64_t seed;
    double objective, penalty;
    int outer;
    long long inner, products;
    std::size_t selection;
  };
  for (const Golden& c :
       {Golden{1000, 100, 0.2, 7, 0x1.8fffffffffc63p+6, 0x1.899ccd65eddc2p-1, 3, 41, 216, 100},
        Golden{600, 12, 0.1, 8, 0x1.7ffffffd35024p+3, 0x1.4f8c60a97b2fbp+0, 5, 101, 441, 12},
        Golden{400, 40, 0.25, 9, 0x1.3fffffffd2c6ap+5, 0x1.f34ba057e8c98p-1, 3, 45, 223, 40}}) {
    auto o = DensestOptions::before_acceptance_rule();  // the options the golden values were recorded with
    o.storage = DensestOptions::Storage::sparse;
    const auto r = densest_subgraph(keel::sim::planted_clique_graph(c.n, c.k, c.p, c.seed).graph, o);
    INFO("G(" << c.n << ", " << c.p << ") + planted " << c.k);
    CHECK(r.sparse);
    CHECK(r.objective == c.objective);
    CHECK(r.penalty == c.penalty);
    CHECK(r.outer_iterations == c.outer);
    CHECK(r.inner_iterations == c.inner);
    CHECK(r.products == c.products);
    CHECK(r.selection.size() == c.selection);
  }
}

TEST_CASE("densest subgraph: the crawl cut ends a symmetric pair's 1/(d + F) decay with the same answer") {
  // A clique K of 10 vertices, and two vertices a and b adjacent to all of K and to nothing else, in a sparse
  // G(60, 0.05): a and b sit at u_a = u_b = (Mu)_a / (d + F) for every d, so without the cut the
  // homotopy doubles d some 25 times before they fall below eps. The cut zeroes them once u (d + F) has
  // settled; the repair then adds one of them, as it does after the long decay.
  const int n = 60;
  const auto noise = random_graph(n, 0.05, 11);
  const int a = 40, b = 41;
  std::vector<std::pair<int, int>> edges;
  for (int v = 0; v < n; ++v)
    for (int w : noise.neighbors(v))
      if (v < w && v != a && v != b && w != a && w != b) edges.emplace_back(v, w);
  std::vector<int> K;
  for (int v = 0; v < 10; ++v) K.push_back(3 * v + 1);
  for (int v : K) {
    for (int w : K)
      if (v < w) edges.emplace_back(v, w);
    edges.emplace_back(v, a);
    edges.emplace_back(v, b);
  }
  const ConsistencyGraph g(n, edges);  // duplicate edges are idempotent
  REQUIRE_FALSE(g.adjacent(a, b));
  REQUIRE(g.is_clique(K));

  DensestOptions off;
  off.crawl_tolerance = 0.0;
  const auto slow = densest_subgraph(g, off);
  const auto fast = densest_subgraph(g);
  INFO(slow.outer_iterations << " outer iterations and " << slow.products << " products without the cut, "
                             << fast.outer_iterations << " and " << fast.products << " with it");
  CHECK(slow.crawl_cuts == 0);
  CHECK(slow.outer_iterations >= 20);
  CHECK(fast.crawl_cuts == 1);
  CHECK(fast.converged);
  CHECK(fast.outer_iterations <= 8);
  CHECK(fast.products * 5 < slow.products);
  CHECK(fast.raw == K);
  CHECK(fast.raw == slow.raw);
  CHECK(fast.selection == slow.selection);
  CHECK(fast.selection.size() == K.size() + 1);
  CHECK(g.is_clique(fast.selection));

  // bench_clique's 1D worlds of m = 100 and planted cliques: the same raw and repaired selections with and
  // without the cut (on the family's 143 graphs: all 143).
  for (int w = 0; w < 5; ++w) {
    const auto world = bench_world(w);
    INFO("world " << w);
    const auto x = densest_subgraph(world, off), y = densest_subgraph(world);
    CHECK(x.raw == y.raw);
    CHECK(x.selection == y.selection);
    CHECK(y.products <= x.products);
  }
  for (std::uint64_t seed : {4u, 5u, 6u}) {
    const auto [pg, planted] = keel::sim::planted_clique_graph(200, 8, 0.2, seed);
    INFO("planted seed " << seed);
    const auto x = densest_subgraph(pg, off), y = densest_subgraph(pg);
    CHECK(x.selection == y.selection);
    CHECK(y.products <= x.products);
  }
  off.crawl_tolerance = -0.1;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, off); }), "crawl_tolerance must be in [0, 1)"));
  off.crawl_tolerance = 1.0;
  CHECK(contains(message_of([&] { (void)densest_subgraph(g, off); }), "crawl_tolerance must be in [0, 1)"));
}
