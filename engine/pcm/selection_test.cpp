// Selection methods on a consistency matrix Q (thesis §2.5, §2.7): PCM = maximum clique (eq. 2.5) against
// brute force on random matrices, RANSAC's single-sample support (and the inconsistent pairs it returns),
// SCGP's dominant cluster, its λ₁/λ₂ confidence test, and bad inputs.
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "kit/test_kit.hpp"
#include "pcm/combinatorial.hpp"
#include "pcm/selection.hpp"

using namespace keel::pcm;

using keel::testkit::contains;
using keel::testkit::message_of;

namespace {

// Q from a symmetric "distance" rule.
template <class F>
ConsistencyMatrix make_q(int n, F&& q_of) {
  ConsistencyMatrix Q;
  Q.n = n;
  Q.dof = 1;
  Q.q.assign(static_cast<std::size_t>(n) * n, 0.0);
  for (int u = 0; u < n; ++u)
    for (int v = 0; v < n; ++v)
      if (u != v) Q.q[static_cast<std::size_t>(u) * n + v] = q_of(u, v);
  return Q;
}

// 1D points with unit standard deviation: q_uv = (z_u − z_v)² / 2 (the 1D case of eq. 2.4, as sim::World1D's
// Q).
ConsistencyMatrix points(const std::vector<double>& z) {
  return make_q(static_cast<int>(z.size()), [&](int u, int v) {
    const double d = z[static_cast<std::size_t>(u)] - z[static_cast<std::size_t>(v)];
    return d * d / 2.0;
  });
}

// Pairs {u, v} of `set` with q_uv > γ or q_vu > γ (eq. 2.3 violated).
int inconsistent_pairs(const ConsistencyMatrix& Q, const std::vector<int>& set, double gamma) {
  int n = 0;
  for (std::size_t a = 0; a < set.size(); ++a)
    for (std::size_t b = a + 1; b < set.size(); ++b)
      n += Q.at(set[a], set[b]) > gamma || Q.at(set[b], set[a]) > gamma;
  return n;
}

}  // namespace

TEST_CASE("RANSAC: a star centre wins and its support holds inconsistent pairs; PCM does not") {
  // Candidate 0 is consistent with 1..4, which are pairwise inconsistent; 5 and 6 are consistent with each
  // other only.
  const auto Q = make_q(7, [](int u, int v) {
    if (u == 0 && v <= 4) return 1.0;
    if (v == 0 && u <= 4) return 1.0;
    if ((u == 5 && v == 6) || (u == 6 && v == 5)) return 0.5;
    return 100.0;
  });
  const double gamma = 3.0;
  const auto r = select_ransac(Q, gamma);
  CHECK(r.selected == std::vector<int>{0, 1, 2, 3, 4});
  CHECK(inconsistent_pairs(Q, r.selected, gamma) == 6);  // all pairs among 1..4
  CHECK_FALSE(r.search.has_value());
  CHECK(r.time_s >= 0.0);

  const auto p = select_pcm(Q, gamma, CliqueAlgorithm::exact);
  CHECK(p.selected.size() == 2);
  CHECK(inconsistent_pairs(Q, p.selected, gamma) == 0);
  CHECK(p.proven_optimal());
  CHECK(p.search->upper_bound == 2);
}

TEST_CASE("RANSAC: ties go to the smallest candidate; the sample's own row decides (asymmetric Q)") {
  // Two disjoint consistent pairs {0,1} and {2,3}: supports of size 2 everywhere, candidate 0 wins.
  const auto Q = make_q(4, [](int u, int v) { return (u / 2 == v / 2) ? 0.1 : 50.0; });
  CHECK(select_ransac(Q, 1.0).selected == std::vector<int>{0, 1});

  // Row 3 says everyone is likely given 3; the other rows disagree. RANSAC uses q_uv of the sample u only.
  auto A = make_q(4, [](int, int) { return 50.0; });
  for (int v = 0; v < 3; ++v) A.q[3 * 4 + v] = 0.2;
  CHECK(select_ransac(A, 1.0).selected == std::vector<int>{0, 1, 2, 3});
  // PCM needs both q_uv and q_vu: no edge at all, a single candidate.
  CHECK(select_pcm(A, 1.0, CliqueAlgorithm::exact).selected.size() == 1);
}

TEST_CASE("RANSAC support equals {u} plus the row's likely candidates") {
  keel::core::Rng rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + static_cast<int>(rng.uniform() * 25);
    const auto Q = make_q(n, [&](int, int) { return 8.0 * rng.uniform(); });
    const double gamma = 0.5 + 3.0 * rng.uniform();
    const auto r = select_ransac(Q, gamma);
    std::size_t best = 0;
    int best_u = -1;
    for (int u = 0; u < n; ++u) {
      std::size_t c = 1;
      for (int v = 0; v < n; ++v) c += (v != u && Q.at(u, v) <= gamma);
      if (c > best) best = c, best_u = u;
    }
    REQUIRE(r.selected.size() == best);
    CHECK(std::find(r.selected.begin(), r.selected.end(), best_u) != r.selected.end());
    for (int v : r.selected) CHECK((v == best_u || Q.at(best_u, v) <= gamma));
  }
}

TEST_CASE("PCM selection = brute-force maximum clique on random Q (symmetric and asymmetric)") {
  keel::core::Rng rng(2018);
  int compared = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const int n = 1 + static_cast<int>(rng.uniform() * 22);
    const bool asymmetric = trial % 3 == 0;
    ConsistencyMatrix Q = make_q(n, [](int, int) { return 0.0; });
    for (int u = 0; u < n; ++u)
      for (int v = u + 1; v < n; ++v) {
        const double a = 6.0 * rng.uniform() * rng.uniform() * 3.0;
        Q.q[static_cast<std::size_t>(u) * n + v] = a;
        Q.q[static_cast<std::size_t>(v) * n + u] = asymmetric ? a * (0.8 + 0.4 * rng.uniform()) : a;
      }
    const double gamma = keel::pcm::consistency_threshold(0.05 + 0.5 * rng.uniform(), 1);
    const auto exact = select_pcm(Q, gamma, CliqueAlgorithm::exact);
    const auto heur = select_pcm(Q, gamma, CliqueAlgorithm::heuristic);
    const auto brute = select_pcm(Q, gamma, CliqueAlgorithm::brute_force);
    const auto comb = max_consistent_set_combinatorial(Q, gamma, CombinatorialMethod::pruned);
    CHECK(exact.selected.size() == brute.selected.size());
    CHECK(exact.selected.size() == comb.selected.size());
    CHECK(exact.proven_optimal());
    CHECK(exact.search->upper_bound == static_cast<int>(exact.selected.size()));
    CHECK(heur.selected.size() <= exact.selected.size());
    CHECK(heur.search->upper_bound >= static_cast<int>(exact.selected.size()));
    CHECK(inconsistent_pairs(Q, exact.selected, gamma) == 0);
    CHECK(inconsistent_pairs(Q, heur.selected, gamma) == 0);
    CHECK(std::is_sorted(exact.selected.begin(), exact.selected.end()));
    ++compared;
  }
  CHECK(compared == 600);
}

TEST_CASE("densest subgraph selector: a consistent set never above PCM's, raw violations reported") {
  keel::core::Rng rng(2024);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + static_cast<int>(rng.uniform() * 30);
    ConsistencyMatrix Q = make_q(n, [](int, int) { return 0.0; });
    for (int u = 0; u < n; ++u)
      for (int v = u + 1; v < n; ++v) {
        const double a = 6.0 * rng.uniform() * rng.uniform() * 3.0;
        Q.q[static_cast<std::size_t>(u) * n + v] = Q.q[static_cast<std::size_t>(v) * n + u] = a;
      }
    const double gamma = keel::pcm::consistency_threshold(0.05 + 0.5 * rng.uniform(), 1);
    const auto exact = select_pcm(Q, gamma, CliqueAlgorithm::exact);
    for (double scale : {0.0, 2.0}) {
      DensestSelectOptions o;
      o.affinity_scale = scale;
      const auto d = select_densest(Q, gamma, o);
      INFO("trial " << trial << ", scale " << scale);
      CHECK(!d.selected.empty());
      CHECK(inconsistent_pairs(Q, d.selected, gamma) == 0);
      CHECK(d.selected.size() <= exact.selected.size());
      CHECK(d.raw_size >= 1);
      CHECK(d.violations >= 0);
      CHECK(!d.search);
    }
  }
  // A clear dominant cluster: both affinities find it.
  const auto Q = points({0.0, 0.1, 0.2, 0.15, 0.05, 7.0, 7.1, 20.0});
  const double gamma = keel::pcm::consistency_threshold(0.11, 1);
  CHECK(select_densest(Q, gamma).selected == std::vector<int>{0, 1, 2, 3, 4});
  CHECK(select_densest(Q, gamma, {2.0, {}}).selected == std::vector<int>{0, 1, 2, 3, 4});
  CHECK(contains(message_of([&] { (void)select_densest(Q, gamma, {-1.0, {}}); }),
                 "affinity_scale must be 0 (binary) or > 0"));
}

TEST_CASE("PCM reports ties when asked") {
  // Two disjoint triangles: two maximum cliques.
  const auto Q = make_q(6, [](int u, int v) { return (u / 3 == v / 3) ? 0.1 : 40.0; });
  CliqueOptions o;
  o.report_ties = true;
  const auto s = select_pcm(Q, 1.0, CliqueAlgorithm::exact, o);
  CHECK(s.selected == std::vector<int>{0, 1, 2});
  CHECK(s.search->ties.size() == 1);
  CHECK(select_pcm(Q, 1.0, CliqueAlgorithm::exact).search->ties.empty());  // not requested
}

TEST_CASE("SCGP finds the dominant block among a smaller block and scattered candidates") {
  // Block B1 = {1, 4, 6, 7, 9, 11} (mutually consistent), block B2 = {0, 2, 5}, scattered = {3, 8, 10}.
  const std::vector<int> group = {2, 1, 2, 3, 1, 2, 1, 1, 3, 1, 3, 1};  // 1 = B1, 2 = B2, 3 = scattered
  keel::core::Rng rng(5);
  std::vector<double> noise(144);
  for (auto& x : noise) x = rng.uniform();
  const auto Q = make_q(12, [&](int u, int v) {
    const int a = std::min(u, v), b = std::max(u, v);
    const double r = noise[a * 12 + b];
    if (group[u] == group[v] && group[u] != 3) return 0.2 + 0.8 * r;  // consistent
    return 20.0 + 30.0 * r;                                           // inconsistent
  });
  for (auto d : {ScgpDiscretization::dot_product, ScgpDiscretization::rayleigh}) {
    ScgpOptions o;
    o.discretization = d;
    const auto r = scgp(Q, o);
    CAPTURE(to_string(d));
    CHECK(r.selection.selected == std::vector<int>{1, 4, 6, 7, 9, 11});
    CHECK(r.confident);
    CHECK(r.cluster_size == 6);
    CHECK(r.lambda1 > r.lambda2);
    CHECK(r.eigen_ratio > 1.5);
    CHECK_FALSE(r.selection.search.has_value());
    double norm = 0.0;
    for (double x : r.eigenvector) norm += x * x;
    CHECK(norm == doctest::Approx(1.0).epsilon(1e-9));
    // The block's entries of v₁ dominate every other entry.
    double low_in = 1.0, high_out = 0.0;
    for (int u = 0; u < 12; ++u) {
      if (group[u] == 1) {
        low_in = std::min(low_in, r.eigenvector[u]);
      } else {
        high_out = std::max(high_out, r.eigenvector[u]);
      }
    }
    CHECK(low_in > high_out);
    CHECK(select_scgp(Q, o).selected == r.selection.selected);
  }
}

TEST_CASE("SCGP: the λ1/λ2 confidence test rejects two equally strong clusters") {
  // Two identical disjoint blocks of 4: λ₁ ≈ λ₂.
  const auto Q = make_q(8, [](int u, int v) { return (u / 4 == v / 4) ? 0.3 : 60.0; });
  // v₁ is any unit vector of the two-dimensional dominant eigenspace, so the cluster is arbitrary: exactly
  // the case the test exists for.
  const auto off = scgp(Q);
  CHECK(off.confident);
  CHECK_FALSE(off.selection.selected.empty());
  CHECK(off.eigen_ratio == doctest::Approx(1.0).epsilon(1e-6));
  ScgpOptions o;
  o.min_eigen_ratio = 2.0;  // Olson (2009)'s "locally unambiguous" test
  const auto on = scgp(Q, o);
  CHECK_FALSE(on.confident);
  CHECK(on.selection.selected.empty());
  CHECK(on.cluster_size == static_cast<int>(off.selection.selected.size()));

  // One block of 6 and one of 2: unambiguous.
  const auto U = make_q(8, [](int u, int v) { return ((u < 6) == (v < 6)) ? 0.3 : 60.0; });
  const auto u = scgp(U, o);
  CHECK(u.confident);
  CHECK(u.selection.selected == std::vector<int>{0, 1, 2, 3, 4, 5});
}

TEST_CASE("SCGP's two leading eigenpairs agree with the full decomposition (Lanczos and its fallback)") {
  // 1D worlds as in §2.7.1: half inliers at 0, a quarter in one aliased group, the rest scattered; n from 1
  // (no Lanczos) to 600. λ₁, λ₂ and v₁ against Eigen's full SelfAdjointEigenSolver of the same A.
  keel::core::Rng rng(11);
  for (const int n : {1, 2, 3, 4, 7, 20, 64, 150, 600}) {
    std::vector<double> z(static_cast<std::size_t>(n));
    for (int u = 0; u < n; ++u)
      z[static_cast<std::size_t>(u)] = u < n / 2       ? rng.normal()
                                       : u < 3 * n / 4 ? 7.0 + rng.normal()
                                                       : 40.0 * rng.uniform() - 20.0;
    const auto Q = points(z);
    const ScgpOptions o;
    Eigen::MatrixXd A(n, n);
    for (int u = 0; u < n; ++u)
      for (int v = 0; v < n; ++v)
        A(u, v) = u == v ? 1.0 : std::exp(-std::max(Q.at(u, v), Q.at(v, u)) / o.affinity_scale);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> full(A);
    const double l1 = full.eigenvalues()(n - 1), l2 = n >= 2 ? full.eigenvalues()(n - 2) : 0.0;
    Eigen::VectorXd v1 = full.eigenvectors().col(n - 1);
    if (v1.sum() < 0.0) v1 = -v1;
    const auto r = scgp(Q, o);
    CAPTURE(n);
    CHECK(std::abs(r.lambda1 - l1) <= 1e-12 * l1);
    CHECK(std::abs(r.lambda2 - l2) <= 1e-12 * l1);
    REQUIRE(r.eigenvector.size() == static_cast<std::size_t>(n));
    double diff = 0.0;
    for (int u = 0; u < n; ++u)
      diff = std::max(diff, std::abs(r.eigenvector[static_cast<std::size_t>(u)] - v1(u)));
    CHECK(diff <= 1e-10);
  }
  // A degenerate top (two identical blocks, λ₁ = λ₂): v₁ is any vector of the eigenspace, but it is one.
  const int n = 40;
  const auto Q = make_q(n, [](int u, int v) { return (u / 20 == v / 20) ? 0.3 : 60.0; });
  const auto r = scgp(Q);
  Eigen::VectorXd v(n);
  for (int u = 0; u < n; ++u) v(u) = r.eigenvector[static_cast<std::size_t>(u)];
  Eigen::MatrixXd A(n, n);
  for (int u = 0; u < n; ++u)
    for (int w = 0; w < n; ++w) A(u, w) = u == w ? 1.0 : std::exp(-Q.at(u, w) / 2.0);
  CHECK((A * v - r.lambda1 * v).norm() <= 1e-10 * r.lambda1);
  CHECK(r.eigen_ratio == doctest::Approx(1.0).epsilon(1e-9));
}

TEST_CASE("SCGP does not enforce pairwise consistency (a smooth chain is one cluster)") {
  // Points 0, 0.5, ..., 3 with σ = 1: neighbours are consistent, the ends are not at γ(0.05) = 3.84 (q
  // = 4.5).
  const auto Q = points({0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0});
  const double gamma = consistency_threshold(0.05, 1);
  const auto s = select_scgp(Q);
  CHECK(s.selected.size() == 7);
  CHECK(inconsistent_pairs(Q, s.selected, gamma) > 0);
  const auto p = select_pcm(Q, gamma, CliqueAlgorithm::exact);
  CHECK(inconsistent_pairs(Q, p.selected, gamma) == 0);
  CHECK(p.selected.size() < 7);
}

TEST_CASE("discretization names round-trip") {
  for (auto d : {ScgpDiscretization::dot_product, ScgpDiscretization::rayleigh})
    CHECK(scgp_discretization_from_string(to_string(d)) == d);
  CHECK(contains(message_of([] { (void)scgp_discretization_from_string("power"); }), "power"));
}

TEST_CASE("bad inputs throw std::invalid_argument with a clear message") {
  const auto good = points({0.0, 1.0, 2.0});
  ConsistencyMatrix empty;
  CHECK(contains(message_of([&] { (void)select_pcm(empty, 1.0, CliqueAlgorithm::exact); }), "n = 0"));
  CHECK(contains(message_of([&] { (void)select_ransac(empty, 1.0); }), "n = 0"));
  CHECK(contains(message_of([&] { (void)select_scgp(empty); }), "n = 0"));

  auto wrong = good;
  wrong.q.pop_back();
  CHECK(contains(message_of([&] { (void)select_pcm(wrong, 1.0, CliqueAlgorithm::heuristic); }),
                 "expected n*n = 9"));
  CHECK(contains(message_of([&] { (void)select_scgp(wrong); }), "8 entries"));

  auto nan = good;
  nan.q[1 * 3 + 2] = std::numeric_limits<double>::quiet_NaN();
  CHECK(contains(message_of([&] { (void)select_ransac(nan, 1.0); }), "q[1][2] = nan is NaN"));
  CHECK(contains(message_of([&] { (void)select_scgp(nan); }), "NaN"));
  auto neg = good;
  neg.q[2 * 3 + 0] = -1.0;
  CHECK(contains(message_of([&] { (void)select_pcm(neg, 1.0, CliqueAlgorithm::exact); }), "negative"));

  for (double g :
       {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    CHECK(contains(message_of([&] { (void)select_pcm(good, g, CliqueAlgorithm::exact); }), "gamma"));
    CHECK(contains(message_of([&] { (void)select_ransac(good, g); }), "gamma"));
  }

  ScgpOptions o;
  o.affinity_scale = 0.0;
  CHECK(contains(message_of([&] { o.validate(); }), "affinity_scale"));
  CHECK(contains(message_of([&] { (void)select_scgp(good, o); }), "affinity_scale"));
  o = {};
  o.min_eigen_ratio = 0.5;
  CHECK(contains(message_of([&] { o.validate(); }), "min_eigen_ratio"));
  o.min_eigen_ratio = std::numeric_limits<double>::quiet_NaN();
  CHECK(contains(message_of([&] { o.validate(); }), "min_eigen_ratio"));

  // +inf distances are allowed: never consistent.
  auto inf = good;
  inf.q[0 * 3 + 1] = inf.q[1 * 3 + 0] = std::numeric_limits<double>::infinity();
  const auto pi = select_pcm(inf, 10.0, CliqueAlgorithm::exact).selected;
  CHECK(pi.size() == 2);
  CHECK(inconsistent_pairs(inf, pi, 10.0) == 0);
  CHECK_FALSE(select_scgp(inf).selected.empty());
}
