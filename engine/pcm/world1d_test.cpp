// The 1D world of §2.7.1: deterministic generation, the distributions it draws from, Q, the combinatorial solution of
// eq. 2.5 (exhaustive = pruned = brute-force / exact maximum clique on random worlds), and inconsistent-pair counts.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "pcm/clique.hpp"
#include "pcm/selection.hpp"
#include "pcm/world1d.hpp"
#include "pcm/test_support.hpp"

using namespace keel::pcm;

using keel::pcm::testing::contains;
using keel::pcm::testing::message_of;

namespace {

}  // namespace

TEST_CASE("world generation is deterministic per (seed, index) and respects the counts") {
  World1DOptions o;
  const auto a = generate_world1d(o, 42, 7), b = generate_world1d(o, 42, 7), c = generate_world1d(o, 42, 8);
  CHECK(a.z == b.z);
  CHECK(a.sigma == b.sigma);
  CHECK(a.labels == b.labels);
  CHECK(a.z != c.z);
  for (int i = 0; i < 500; ++i) {
    const auto w = generate_world1d(o, 1, i);
    const int ni = w.count(MeasurementLabel::inlier), na = w.count(MeasurementLabel::aliased),
              nr = w.count(MeasurementLabel::random);
    REQUIRE(w.size() == ni + na + nr);
    CHECK(ni >= o.inliers_min);
    CHECK(ni <= o.inliers_max);
    CHECK(na >= o.aliased_min);
    CHECK(na <= o.aliased_max);
    CHECK(nr >= o.random_min);
    CHECK(nr <= o.random_max);
    CHECK(w.sigma.size() == w.z.size());
    for (int u = 0; u < w.size(); ++u) {
      if (w.labels[u] == MeasurementLabel::inlier) CHECK(w.sigma[u] == o.sigma_inlier);
      if (w.labels[u] == MeasurementLabel::aliased) CHECK(w.sigma[u] == w.aliased_sigma);
      if (w.labels[u] != MeasurementLabel::inlier) {
        CHECK(w.sigma[u] >= o.outlier_sigma_min);
        CHECK(w.sigma[u] <= o.outlier_sigma_max);
      }
    }
    CHECK(std::fabs(w.aliased_mean - o.x) <= o.outlier_mean_range);
  }
  // Without shuffling the groups come in order.
  o.shuffle = false;
  const auto w = generate_world1d(o, 3, 3);
  CHECK(std::is_sorted(w.labels.begin(), w.labels.end()));
}

TEST_CASE("inliers are N(x, σ_in²); an aliased group shares one Gaussian") {
  World1DOptions o;
  o.x = 3.5;
  o.sigma_inlier = 0.7;
  double s = 0, ss = 0, al = 0, al2 = 0;
  long long n = 0, m = 0;
  for (int i = 0; i < 4000; ++i) {
    const auto w = generate_world1d(o, 99, i);
    for (int u = 0; u < w.size(); ++u) {
      if (w.labels[u] == MeasurementLabel::inlier) {
        s += w.z[u] - o.x;
        ss += (w.z[u] - o.x) * (w.z[u] - o.x);
        ++n;
      } else if (w.labels[u] == MeasurementLabel::aliased) {
        const double t = (w.z[u] - w.aliased_mean) / w.aliased_sigma;  // standardised within its group
        al += t;
        al2 += t * t;
        ++m;
      }
    }
  }
  CHECK(std::fabs(s / n) < 4.0 * o.sigma_inlier / std::sqrt(static_cast<double>(n)));
  CHECK(std::sqrt(ss / n) == doctest::Approx(o.sigma_inlier).epsilon(0.02));
  CHECK(std::fabs(al / m) < 4.0 / std::sqrt(static_cast<double>(m)));
  CHECK(al2 / m == doctest::Approx(1.0).epsilon(0.03));
}

TEST_CASE("Q of a world: q_uv = (z_u − z_v)² / (σ_u² + σ_v²), dof 1") {
  World1D w;
  w.z = {0.0, 1.0, 4.0};
  w.sigma = {1.0, 2.0, 0.5};
  w.labels.assign(3, MeasurementLabel::random);
  const auto Q = world1d_consistency_matrix(w);
  CHECK(Q.n == 3);
  CHECK(Q.dof == 1);
  CHECK(Q.at(0, 1) == doctest::Approx(1.0 / 5.0));
  CHECK(Q.at(1, 2) == doctest::Approx(9.0 / 4.25));
  CHECK(Q.at(2, 0) == doctest::Approx(16.0 / 1.25));
  for (int u = 0; u < 3; ++u) {
    CHECK(Q.at(u, u) == 0.0);
    for (int v = 0; v < 3; ++v) CHECK(Q.at(u, v) == Q.at(v, u));
  }
  World1D bad = w;
  bad.sigma[1] = 0.0;
  CHECK(contains(message_of([&] { (void)world1d_consistency_matrix(bad); }), "standard deviation"));
  bad = w;
  bad.sigma.pop_back();
  CHECK(contains(message_of([&] { (void)world1d_consistency_matrix(bad); }), "3 measurements but 2"));
  CHECK(contains(message_of([&] { (void)world1d_consistency_matrix(World1D{}); }), "no measurements"));
}

TEST_CASE("inlier pairs follow χ²(1): the share consistent at γ(p) is 1 − p") {
  World1DOptions o;
  const double p = 0.11, gamma = consistency_threshold(p, 1);
  long long pairs = 0, consistent = 0;
  for (int i = 0; i < 3000; ++i) {
    const auto w = generate_world1d(o, 5, i);
    const auto Q = world1d_consistency_matrix(w);
    for (int u = 0; u < w.size(); ++u)
      for (int v = u + 1; v < w.size(); ++v)
        if (w.labels[u] == MeasurementLabel::inlier && w.labels[v] == MeasurementLabel::inlier) {
          ++pairs;
          consistent += Q.at(u, v) <= gamma;
        }
  }
  CHECK(static_cast<double>(consistent) / pairs == doctest::Approx(1.0 - p).epsilon(0.01));
}

TEST_CASE("combinatorial eq. 2.5 = brute-force and exact maximum clique on random worlds (m <= 20)") {
  World1DOptions o;  // 8..22 measurements by default; keep m <= 20 here
  o.inliers_max = 8;
  const double gammas[] = {consistency_threshold(0.11, 1), consistency_threshold(0.01, 1), 0.5};
  long long tied_worlds = 0;
  for (int i = 0; i < 1500; ++i) {
    const auto w = generate_world1d(o, 2018, i);
    REQUIRE(w.size() <= 20);
    const auto Q = world1d_consistency_matrix(w);
    const double gamma = gammas[i % 3];
    const auto ex = max_consistent_set_combinatorial(Q, gamma, CombinatorialMethod::exhaustive);
    const auto pr = max_consistent_set_combinatorial(Q, gamma, CombinatorialMethod::pruned);
    const auto g = ConsistencyGraph::from_threshold(Q.n, Q.q, gamma);
    CliqueOptions ties;
    ties.report_ties = true;
    ties.max_ties = 100000;
    const auto bf = maximum_clique_brute_force(g, ties);
    const auto exact = maximum_clique_exact(g);
    CAPTURE(i);
    REQUIRE(ex.selected.size() == pr.selected.size());
    CHECK(ex.selected.size() == bf.clique.size());
    CHECK(ex.selected.size() == exact.clique.size());
    CHECK(ex.optimal_sets == pr.optimal_sets);
    CHECK(ex.optimal_sets == static_cast<long long>(bf.ties.size()) + 1);
    CHECK(ex.subsets_visited == (1LL << w.size()));
    CHECK(pr.subsets_visited < ex.subsets_visited);
    CHECK(count_inconsistent_pairs(Q, ex.selected, gamma) == 0);
    CHECK(count_inconsistent_pairs(Q, pr.selected, gamma) == 0);
    CHECK(g.is_clique(pr.selected));
    tied_worlds += ex.optimal_sets > 1;
  }
  MESSAGE(tied_worlds << " of 1500 worlds have more than one maximum consistent set");
}

TEST_CASE("combinatorial: small hand cases and limits") {
  // Chain 0-1-2 (0 and 2 inconsistent): two maximum sets of size 2.
  ConsistencyMatrix Q;
  Q.n = 3;
  Q.q = {0, 1, 9, 1, 0, 1, 9, 1, 0};
  for (auto m : {CombinatorialMethod::exhaustive, CombinatorialMethod::pruned}) {
    const auto r = max_consistent_set_combinatorial(Q, 2.0, m);
    CHECK(r.selected.size() == 2);
    CHECK(r.optimal_sets == 2);
    CHECK(combinatorial_method_from_string(to_string(m)) == m);
  }
  CHECK(max_consistent_set_combinatorial(Q, 2.0, CombinatorialMethod::exhaustive).selected == std::vector<int>{0, 1});

  ConsistencyMatrix big;
  big.n = kCombinatorialExhaustiveMax + 1;
  big.q.assign(static_cast<std::size_t>(big.n) * big.n, 0.0);
  CHECK(contains(message_of([&] { (void)max_consistent_set_combinatorial(big, 1.0, CombinatorialMethod::exhaustive); }),
                 "exceeds the limit 30"));
  // The pruned search handles it (all consistent: one set of everything).
  const auto all = max_consistent_set_combinatorial(big, 1.0, CombinatorialMethod::pruned);
  CHECK(all.selected.size() == static_cast<std::size_t>(big.n));
  CHECK(all.optimal_sets == 1);
  CHECK(contains(message_of([&] { (void)max_consistent_set_combinatorial(Q, 0.0); }), "gamma"));
  CHECK(contains(message_of([] { (void)combinatorial_method_from_string("greedy"); }), "greedy"));
}

TEST_CASE("count_inconsistent_pairs") {
  ConsistencyMatrix Q;
  Q.n = 4;
  Q.q = {0, 1, 5, 1,  //
         1, 0, 1, 1,  //
         5, 1, 0, 7,  //
         1, 1, 2, 0};  // asymmetric (2, 3): 7 vs 2
  CHECK(count_inconsistent_pairs(Q, {}, 3.0) == 0);
  CHECK(count_inconsistent_pairs(Q, {1}, 3.0) == 0);
  CHECK(count_inconsistent_pairs(Q, {0, 1, 3}, 3.0) == 0);
  CHECK(count_inconsistent_pairs(Q, {0, 2}, 3.0) == 1);
  CHECK(count_inconsistent_pairs(Q, {3, 2}, 3.0) == 1);  // one direction is enough
  CHECK(count_inconsistent_pairs(Q, {0, 1, 2, 3}, 3.0) == 2);
  CHECK(count_inconsistent_pairs(Q, {0, 1, 2, 3}, 10.0) == 0);
  CHECK(contains(message_of([&] { (void)count_inconsistent_pairs(Q, {0, 4}, 3.0); }), "out of range"));
  CHECK(contains(message_of([&] { (void)count_inconsistent_pairs(Q, {1, 1}, 3.0); }), "repeated"));
}

TEST_CASE("World1DOptions validation and fixed-size options") {
  World1DOptions o;
  CHECK_NOTHROW(o.validate());
  o.sigma_inlier = 0.0;
  CHECK(contains(message_of([&] { o.validate(); }), "sigma_inlier"));
  o = {};
  o.aliased_min = 5;
  o.aliased_max = 4;
  CHECK(contains(message_of([&] { o.validate(); }), "aliased_min/_max"));
  o = {};
  o.inliers_min = o.inliers_max = o.aliased_min = o.aliased_max = o.random_min = o.random_max = 0;
  CHECK(contains(message_of([&] { o.validate(); }), "at least one measurement"));
  o = {};
  o.outlier_sigma_min = 2.0;
  o.outlier_sigma_max = 1.0;
  CHECK(contains(message_of([&] { o.validate(); }), "outlier_sigma"));
  o = {};
  o.outlier_mean_range = -1.0;
  CHECK(contains(message_of([&] { o.validate(); }), "outlier_mean_range"));

  const auto f = world1d_options_with_total(World1DOptions{}, 37, 0.5, 0.25);
  CHECK(f.inliers_min == 19);  // lround(18.5)
  CHECK(f.inliers_max == 19);
  CHECK(f.aliased_min == 9);
  CHECK(f.random_min == 9);
  for (int i = 0; i < 20; ++i) CHECK(generate_world1d(f, 1, i).size() == 37);
  CHECK(contains(message_of([] { (void)world1d_options_with_total(World1DOptions{}, 0, 0.5, 0.2); }), "total"));
  CHECK(contains(message_of([] { (void)world1d_options_with_total(World1DOptions{}, 10, 0.8, 0.3); }), "fractions"));
  CHECK(to_string(MeasurementLabel::aliased) == "aliased");
}

TEST_CASE("the Monte-Carlo study is independent of the thread count and consistent with its parts") {
  World1DStudyOptions o;
  o.pcm_gamma = consistency_threshold(0.11, 1);
  o.ransac_gamma = consistency_threshold(0.01, 1);
  o.seed = 77;
  o.worlds = 300;
  o.threads = 1;
  const auto a = run_world1d_study(o);
  o.threads = 2;
  const auto b = run_world1d_study(o);
  REQUIRE(a.selectors.size() == 5);
  CHECK(a.measurements == b.measurements);
  CHECK(a.inliers == b.inliers);
  for (std::size_t s = 0; s < a.selectors.size(); ++s)
    for (std::size_t i = 0; i < o.worlds; ++i) {
      CHECK(a.outcome[s][i].size == b.outcome[s][i].size);
      CHECK(a.outcome[s][i].inconsistent_pairs == b.outcome[s][i].inconsistent_pairs);
      CHECK(a.outcome[s][i].inliers == b.outcome[s][i].inliers);
      CHECK(a.outcome[s][i].time_s >= 0.0);
    }
  const auto& comb = a.of(Selector1D::combinatorial);
  const auto& exact = a.of(Selector1D::pcm_exact);
  const auto& heur = a.of(Selector1D::pcm_heuristic);
  for (std::size_t i = 0; i < o.worlds; ++i) {
    // World i is the world generate_world1d(…, seed, i) would give on its own.
    const auto w = generate_world1d(o.world, o.seed, i);
    CHECK(a.measurements[i] == w.size());
    CHECK(exact[i].size == comb[i].size);
    CHECK(heur[i].size <= exact[i].size);
    CHECK(exact[i].inconsistent_pairs == 0);
    CHECK(heur[i].inconsistent_pairs == 0);
    CHECK(comb[i].inconsistent_pairs == 0);
    const auto Q = world1d_consistency_matrix(w);
    CHECK(a.of(Selector1D::ransac)[i].size == static_cast<int>(select_ransac(Q, o.ransac_gamma).selected.size()));
  }
  CHECK(contains(message_of([&] { (void)a.of(Selector1D::scgp); }), "<no throw>"));
  o.selectors = {Selector1D::ransac};
  const auto c = run_world1d_study(o);
  CHECK(contains(message_of([&] { (void)c.of(Selector1D::pcm_exact); }), "not run"));

  World1DStudyOptions bad = o;
  bad.pcm_gamma = 0.0;
  CHECK(contains(message_of([&] { bad.validate(); }), "pcm_gamma"));
  bad = o;
  bad.selectors = {Selector1D::scgp, Selector1D::scgp};
  CHECK(contains(message_of([&] { bad.validate(); }), "twice"));
  bad = o;
  bad.selectors = {Selector1D::combinatorial};
  bad.combinatorial = CombinatorialMethod::exhaustive;
  bad.world.random_min = bad.world.random_max = 20;
  CHECK(contains(message_of([&] { bad.validate(); }), "combinatorial limit of 30"));
  CHECK(selector1d_from_string("pcm_heuristic") == Selector1D::pcm_heuristic);
  CHECK(contains(message_of([] { (void)selector1d_from_string("jcbb"); }), "jcbb"));
}
