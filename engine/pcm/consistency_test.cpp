// The consistency measure of eq. 2.4: Jacobians against central differences, the relative-pose covariance
// against keel::lie's eq. 5.51, the χ² distribution of inlier pairs (Monte Carlo, fixed seed), symmetry,
// thread independence and bad inputs.
#include <doctest/doctest.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "lie/gaussian.hpp"
#include "lie/metrics.hpp"
#include "lie/uncertain.hpp"
#include "pcm/consistency.hpp"
#include "pcm/consistency_graph.hpp"
#include "kit/test_kit.hpp"

using namespace keel;
using namespace keel::pcm;
using keel::core::Rng;
using keel::testkit::contains;
using keel::testkit::message_of;
using lie::MatX;
using lie::SE2;
using lie::SE3;

namespace {

// exp of a tangent with every entry N(0, scale²).
template <class G>
G random_pose(Rng& rng, double scale) {
  return testkit::random_pose<G>(rng, scale, scale);
}

// A Aᵀ + 0.2 scale² I with A i.i.d. N(0, scale²): the kit's B Bᵀ / d + λ I with B i.i.d. N(0, d scale²).
MatX random_spd(Rng& rng, int d, double scale) {
  return testkit::random_spd(rng, d, scale * std::sqrt(static_cast<double>(d)), 0.2 * scale * scale);
}

// A draw from N(0, L Lᵀ).
template <class V>
V sample(Rng& rng, const MatX& L) {
  return V(L * testkit::random_vector(rng, L.cols()));
}

// Uniform integer in [0, n).
int uniform_index(Rng& rng, int n) { return std::min(n - 1, static_cast<int>(rng.uniform() * n)); }

}  // namespace

TEST_CASE_TEMPLATE("loop_error: analytic Jacobians match central differences (eq. 2.4)", G, SE2, SE3) {
  using J = typename G::Jacobian;
  Rng rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    G in[4] = {random_pose<G>(rng, 1.5), random_pose<G>(rng, 1.5), random_pose<G>(rng, 1.5),
               random_pose<G>(rng, 1.5)};
    const J I = J::Identity();
    const auto e = loop_error(in[0], I, in[1], I, in[2], I, in[3], I);
    const J* analytic[4] = {&e.J_u, &e.J_ij, &e.J_v, &e.J_lk};
    for (int f = 0; f < 4; ++f) {
      // ε as a function of a left perturbation exp(δ^) of input f.
      const MatX numeric = testkit::numerical_jacobian_tangent<G>([&](const typename G::Tangent& delta) {
        G x[4] = {in[0], in[1], in[2], in[3]};
        x[f] = G::exp(delta) * in[f];
        return (x[0].inverse() * x[1] * x[2] * x[3]).log();
      });
      CHECK((numeric - *analytic[f]).cwiseAbs().maxCoeff() < 1e-6);
    }
    // Σ_uv = J Σ Jᵀ with identity inputs.
    const J expect = e.J_u * e.J_u.transpose() + e.J_ij * e.J_ij.transpose() + e.J_v * e.J_v.transpose() +
                     e.J_lk * e.J_lk.transpose();
    CHECK((expect - e.covariance).cwiseAbs().maxCoeff() < 1e-12);
    CHECK(e.q == doctest::Approx(e.epsilon.dot(e.covariance.inverse() * e.epsilon)).epsilon(1e-9));
  }
}

TEST_CASE_TEMPLATE("relative_pose equals keel::lie::relative (eq. 5.51) with and without cross-covariance", G,
                   SE2, SE3) {
  constexpr int d = G::DoF;
  Rng rng(12);
  for (int trial = 0; trial < 10; ++trial) {
    lie::JointPoses<G> jp;
    jp.means = {random_pose<G>(rng, 2.0), random_pose<G>(rng, 2.0)};
    jp.cov = random_spd(rng, 2 * d, 0.1);
    for (const bool cross : {true, false}) {
      const auto ref = lie::relative(jp, 0, 1, cross);
      const auto got = relative_pose(jp.means[0], jp.means[1], jp.cov.template block<d, d>(0, 0),
                                     jp.cov.template block<d, d>(d, d), jp.cov.template block<d, d>(0, d),
                                     cross ? Composition::joint : Composition::independent);
      CHECK((got.x.matrix() - ref.mean.matrix()).cwiseAbs().maxCoeff() < 1e-12);
      CHECK((got.covariance - ref.cov).cwiseAbs().maxCoeff() < 1e-12 * (1 + ref.cov.cwiseAbs().maxCoeff()));
    }
  }
}

// Monte Carlo of the whole §2.6 situation: two solved local maps whose estimates scatter around the truth
// with a strongly correlated joint covariance (a chain: ξ_j = ξ_i + w), two inlier measurements of a common
// true anchor. With the joint composition the squared distances must follow χ²(dof); the independent
// composition, which over-counts the relative-pose uncertainty of correlated poses, must give much smaller
// values.
TEST_CASE_TEMPLATE("inlier pairs: q follows chi-square with dof degrees of freedom (joint composition)" *
                       doctest::test_suite("monte_carlo"),
                   G, SE2, SE3) {
  constexpr int d = G::DoF;
  using J = typename G::Jacobian;
  using V = typename G::Tangent;
  Rng rng(1);
  const G Ti = random_pose<G>(rng, 3.0), Tj = random_pose<G>(rng, 3.0), Tk = random_pose<G>(rng, 3.0),
          Tl = random_pose<G>(rng, 3.0), anchor = random_pose<G>(rng, 3.0);
  const G z_ik = Ti.inverse() * anchor * Tk, z_jl = Tj.inverse() * anchor * Tl;
  auto chain_cov = [&](double s1, double s2) {
    const MatX S1 = random_spd(rng, d, s1), S2 = random_spd(rng, d, s2);
    MatX C(2 * d, 2 * d);
    C << S1, S1, S1, S1 + S2;  // ξ_second = ξ_first + w
    return C;
  };
  const MatX Ca = chain_cov(0.03, 0.01), Cb = chain_cov(0.03, 0.01);  // map a: (i, j); map b: (l, k)
  const J Su = random_spd(rng, d, 0.01), Sv = random_spd(rng, d, 0.01);
  const MatX La = lie::covariance_square_root(Ca), Lb = lie::covariance_square_root(Cb);
  const MatX Lu = lie::covariance_square_root(Su), Lv = lie::covariance_square_root(Sv);

  const int N = 20000;
  std::vector<double> q_joint, q_ind;
  for (int t = 0; t < N; ++t) {
    const lie::VecX xa = sample<lie::VecX>(rng, La), xb = sample<lie::VecX>(rng, Lb);
    const G Ti_hat = G::exp(V(xa.head(d))) * Ti, Tj_hat = G::exp(V(xa.tail(d))) * Tj;
    const G Tl_hat = G::exp(V(xb.head(d))) * Tl, Tk_hat = G::exp(V(xb.tail(d))) * Tk;
    const G zu = G::exp(sample<V>(rng, Lu)) * z_ik, zv = G::exp(sample<V>(rng, Lv)) * z_jl;
    for (const auto comp : {Composition::joint, Composition::independent}) {
      const auto xij = relative_pose(Ti_hat, Tj_hat, J(Ca.topLeftCorner(d, d)), J(Ca.bottomRightCorner(d, d)),
                                     J(Ca.topRightCorner(d, d)), comp);
      const auto xlk = relative_pose(Tl_hat, Tk_hat, J(Cb.topLeftCorner(d, d)), J(Cb.bottomRightCorner(d, d)),
                                     J(Cb.topRightCorner(d, d)), comp);
      const double q = loop_error(zu, Su, xij.x, xij.covariance, zv, Sv, xlk.x, xlk.covariance).q;
      (comp == Composition::joint ? q_joint : q_ind).push_back(q);
    }
  }
  std::sort(q_joint.begin(), q_joint.end());
  double ks = 0.0, mean = 0.0;
  for (int t = 0; t < N; ++t) {
    const double F = lie::chi2_cdf(q_joint[t], d);
    ks = std::max({ks, std::abs(F - (t + 1.0) / N), std::abs(F - static_cast<double>(t) / N)});
    mean += q_joint[t] / N;
  }
  MESSAGE("KS statistic " << ks << " (0.1% critical value " << 1.95 / std::sqrt(N) << "), mean q " << mean);
  CHECK(ks < 1.95 / std::sqrt(static_cast<double>(N)));  // Kolmogorov–Smirnov at the 0.1 % level
  CHECK(mean == doctest::Approx(d).epsilon(0.06));
  double mean_ind = 0.0;
  for (double q : q_ind) mean_ind += q / N;
  MESSAGE("independent composition: mean q " << mean_ind << " (dof " << d << ")");
  CHECK(mean_ind < 0.5 * d);
}

// Monte Carlo of one robot's loop closures (the one-map form): a chain of four poses 0–3 whose estimates
// scatter with the chain's joint covariance (ξ_{m+1} = ξ_m + w_m), two inlier closures u = (0, 3) and
// v = (2, 1). The loop's relative poses x̂_02 and x̂_31 share the step w_1 → w_2, so they are correlated. With
// the cross-covariance the squared distances follow χ²(dof); the two-map form on the same numbers (the
// relative poses taken as independent) must not.
TEST_CASE_TEMPLATE(
    "one robot's closures: q follows chi-square only with the relative poses' cross-covariance" *
        doctest::test_suite("monte_carlo"),
    G, SE2, SE3) {
  constexpr int d = G::DoF;
  using J = typename G::Jacobian;
  using V = typename G::Tangent;
  Rng rng(21);
  std::vector<G> truth;
  for (int m = 0; m < 4; ++m) truth.push_back(random_pose<G>(rng, 3.0));
  // Joint covariance of (ξ_0 … ξ_3): C[a][b] = Σ_{m ≤ min(a, b)} W_m, with a large middle step W_2.
  const std::vector<MatX> W = {random_spd(rng, d, 0.02), random_spd(rng, d, 0.01), random_spd(rng, d, 0.04),
                               random_spd(rng, d, 0.01)};
  MatX C = MatX::Zero(4 * d, 4 * d);
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      for (int m = 0; m <= std::min(a, b); ++m) C.block(d * a, d * b, d, d) += W[static_cast<std::size_t>(m)];
  const J Su = random_spd(rng, d, 0.01), Sv = random_spd(rng, d, 0.01);
  const MatX L = lie::covariance_square_root(C), Lu = lie::covariance_square_root(Su),
             Lv = lie::covariance_square_root(Sv);
  const G z_u = truth[0].inverse() * truth[3], z_v = truth[2].inverse() * truth[1];

  const int N = 20000;
  std::vector<double> q_one, q_two;
  for (int t = 0; t < N; ++t) {
    const lie::VecX xi = sample<lie::VecX>(rng, L);
    LocalMap<G> map;
    for (int m = 0; m < 4; ++m) map.poses.push_back(G::exp(V(xi.segment(d * m, d))) * truth[m]);
    map.ids = {0, 1, 2, 3};
    map.joint = C;
    std::vector<InterRobotMeasurement<G>> c(2);
    c[0].pose_a = 0, c[0].pose_b = 3, c[0].z = G::exp(sample<V>(rng, Lu)) * z_u, c[0].covariance = Su;
    c[1].pose_a = 2, c[1].pose_b = 1, c[1].z = G::exp(sample<V>(rng, Lv)) * z_v, c[1].covariance = Sv;
    q_one.push_back(consistency_matrix(map, c).at(0, 1));
    q_two.push_back(consistency_matrix(map, map, c).at(0, 1));
  }
  auto ks_and_mean = [&](std::vector<double> q) {
    std::sort(q.begin(), q.end());
    double ks = 0.0, mean = 0.0;
    for (int t = 0; t < N; ++t) {
      const double F = lie::chi2_cdf(q[static_cast<std::size_t>(t)], d);
      ks = std::max({ks, std::abs(F - (t + 1.0) / N), std::abs(F - static_cast<double>(t) / N)});
      mean += q[static_cast<std::size_t>(t)] / N;
    }
    return std::pair{ks, mean};
  };
  const auto [ks, mean] = ks_and_mean(q_one);
  const auto [ks_two, mean_two] = ks_and_mean(q_two);
  MESSAGE("one map: KS " << ks << ", mean q " << mean << "; as two maps: KS " << ks_two << ", mean q "
                         << mean_two << " (0.1% critical value " << 1.95 / std::sqrt(N) << ")");
  CHECK(ks < 1.95 / std::sqrt(static_cast<double>(N)));
  CHECK(mean == doctest::Approx(d).epsilon(0.06));
  CHECK(ks_two > 5 * 1.95 / std::sqrt(static_cast<double>(N)));
}

TEST_CASE("left_covariance_from_information matches Monte Carlo of the residual convention" *
          doctest::test_suite("monte_carlo")) {
  Rng rng(5);
  const SE2 X(3.0, -1.0, 2.5);
  lie::Mat3 Sr;
  Sr << 0.004, 0.001, 0.0005, 0.001, 0.002, -0.0003, 0.0005, -0.0003, 0.001;
  const lie::Mat3 info = Sr.inverse();
  const MatX L = lie::covariance_square_root(Sr);
  const int N = 200000;
  lie::Mat3 S = lie::Mat3::Zero();
  for (int t = 0; t < N; ++t) {
    const lie::Vec3 r = sample<lie::Vec3>(rng, L);
    const SE2 E(r(0), r(1), r(2));                // residual E = z⁻¹ X with ρ(E) = r
    const SE2 z = X * E.inverse();                // the measurement
    const lie::Vec3 n = (z * X.inverse()).log();  // its left perturbation about X
    S += n * n.transpose() / N;
  }
  const lie::Mat3 pred = left_covariance_from_information(X, info);
  CHECK((S - pred).norm() / pred.norm() < 0.02);
  CHECK_THROWS_AS(left_covariance_from_information(X, lie::Mat3::Zero()), std::invalid_argument);
}

TEST_CASE("consistency_threshold: chi-square tail probability p") {
  for (int dof : {1, 3, 6})
    for (double p : {0.01, 0.11, 0.5, 0.9}) {
      const double g = consistency_threshold(p, dof);
      CHECK(1.0 - lie::chi2_cdf(g, dof) == doctest::Approx(p).epsilon(1e-9));
    }
  CHECK(consistency_threshold(0.11, 3) > consistency_threshold(0.5, 3));  // larger p is stricter
  CHECK_THROWS_AS(consistency_threshold(0.0, 3), std::invalid_argument);
  CHECK_THROWS_AS(consistency_threshold(1.0, 3), std::invalid_argument);
  CHECK_THROWS_AS(consistency_threshold(std::nan(""), 3), std::invalid_argument);
  CHECK_THROWS_AS(consistency_threshold(0.1, 0), std::invalid_argument);
}

namespace {

template <class G>
struct Fixture {
  LocalMap<G> a, b;
  std::vector<InterRobotMeasurement<G>> c;
};

template <class G>
Fixture<G> make_fixture(std::uint64_t seed, int n_candidates) {
  constexpr int d = G::DoF;
  Rng rng(seed);
  Fixture<G> f;
  for (int s = 0; s < 12; ++s) f.a.poses.push_back(random_pose<G>(rng, 4.0));
  for (int s = 0; s < 9; ++s) f.b.poses.push_back(random_pose<G>(rng, 4.0));
  f.a.ids = {0, 2, 3, 5, 7, 11};
  f.b.ids = {8, 1, 4, 6};
  f.a.joint = random_spd(rng, d * 6, 0.05);
  f.b.joint = random_spd(rng, d * 4, 0.05);
  const G anchor = random_pose<G>(rng, 4.0);
  for (int u = 0; u < n_candidates; ++u) {
    InterRobotMeasurement<G> m;
    m.pose_a = f.a.ids[uniform_index(rng, 6)];
    m.pose_b = f.b.ids[uniform_index(rng, 4)];
    m.z = u % 3 == 2
              ? random_pose<G>(rng, 4.0)
              : random_pose<G>(rng, 0.02) * f.a.poses[m.pose_a].inverse() * anchor * f.b.poses[m.pose_b];
    m.covariance = random_spd(rng, d, 0.03);
    f.c.push_back(m);
  }
  return f;
}

}  // namespace

TEST_CASE_TEMPLATE("consistency_matrix: equals per-pair loop errors, symmetric, thread independent", G, SE2,
                   SE3) {
  constexpr int d = G::DoF;
  using J = typename G::Jacobian;
  const auto f = make_fixture<G>(99, 17);
  ConsistencyOptions one;
  ConsistencyOptions two;
  two.threads = 2;
  const auto Q1 = consistency_matrix(f.a, f.b, f.c, one);
  const auto Q2 = consistency_matrix(f.a, f.b, f.c, two);
  CHECK(Q1.n == 17);
  CHECK(Q1.dof == d);
  CHECK(Q1.q == Q2.q);
  auto slot = [](const LocalMap<G>& m, int id) {
    return static_cast<int>(std::find(m.ids.begin(), m.ids.end(), id) - m.ids.begin());
  };
  auto blk = [&](const LocalMap<G>& m, int s, int t) -> J {
    return m.joint.template block<d, d>(d * s, d * t);
  };
  auto direct = [&](int u, int v) {
    const auto &cu = f.c[u], &cv = f.c[v];
    const int si = slot(f.a, cu.pose_a), sj = slot(f.a, cv.pose_a), sk = slot(f.b, cu.pose_b),
              sl = slot(f.b, cv.pose_b);
    const auto xij = relative_pose(f.a.poses[cu.pose_a], f.a.poses[cv.pose_a], blk(f.a, si, si),
                                   blk(f.a, sj, sj), blk(f.a, si, sj), Composition::joint);
    const auto xlk = relative_pose(f.b.poses[cv.pose_b], f.b.poses[cu.pose_b], blk(f.b, sl, sl),
                                   blk(f.b, sk, sk), blk(f.b, sl, sk), Composition::joint);
    return loop_error(cu.z, cu.covariance, xij.x, xij.covariance, cv.z, cv.covariance, xlk.x, xlk.covariance)
        .q;
  };
  for (int u = 0; u < Q1.n; ++u) {
    CHECK(Q1.at(u, u) == 0.0);
    for (int v = 0; v < Q1.n; ++v) {
      if (u == v) continue;
      CHECK(direct(u, v) == doctest::Approx(Q1.at(u, v)).epsilon(1e-12));
      // Between two inliers (ε small) the loop traced from v has the same distance to first order.
      if (u % 3 != 2 && v % 3 != 2) CHECK(Q1.at(v, u) == doctest::Approx(Q1.at(u, v)).epsilon(0.05));
    }
  }
  // The independent composition drops the cross blocks, so it must change the matrix.
  ConsistencyOptions ind;
  ind.composition = Composition::independent;
  CHECK(consistency_matrix(f.a, f.b, f.c, ind).q != Q1.q);
}

TEST_CASE_TEMPLATE(
    "consistency_matrix with a cutoff: the same graph at every γ up to it, q_vu skipped only "
    "where q_uv exceeds it",
    G, SE2, SE3) {
  const auto f = make_fixture<G>(99, 17);
  const auto full = consistency_matrix(f.a, f.b, f.c);
  const int n = full.n;
  // Cutoffs at quantiles of the matrix's own entries, so that some pairs are cut and some are not.
  std::vector<double> sorted = full.q;
  std::sort(sorted.begin(), sorted.end());
  for (const double quantile : {0.2, 0.5, 0.8}) {
    const double cutoff = sorted[static_cast<std::size_t>(quantile * static_cast<double>(sorted.size()))];
    CAPTURE(cutoff);
    for (const unsigned threads : {1u, 2u}) {
      ConsistencyOptions o;
      o.cutoff = cutoff;
      o.threads = threads;
      const auto cut = consistency_matrix(f.a, f.b, f.c, o);
      int skipped = 0;
      for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v) {
          if (u < v || u == v || full.at(v, u) <= cutoff) {
            CHECK(cut.at(u, v) == full.at(u, v));  // evaluated: bit for bit the full matrix's entry
          } else {
            CHECK(cut.at(u, v) == std::numeric_limits<double>::infinity());
            ++skipped;
          }
        }
      CHECK(skipped > 0);
      for (const double gamma : {0.5 * cutoff, cutoff}) {
        const auto a = ConsistencyGraph::from_threshold(n, full.q, gamma);
        const auto b = ConsistencyGraph::from_threshold(n, cut.q, gamma);
        for (int u = 0; u < n; ++u)
          for (int v = 0; v < n; ++v)
            if (u != v) CHECK(a.adjacent(u, v) == b.adjacent(u, v));
      }
    }
  }
  for (const double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
    ConsistencyOptions o;
    o.cutoff = bad;
    CHECK(contains(message_of([&] { (void)consistency_matrix(f.a, f.b, f.c, o); }), "cutoff must be > 0"));
  }
}

TEST_CASE_TEMPLATE("one-map consistency: the cross term is the only difference from the two-map form", G, SE2,
                   SE3) {
  constexpr int d = G::DoF;
  const auto f = make_fixture<G>(5, 9);
  // One map holding both robots' poses, the joint block-diagonal between them: no pose of a is correlated
  // with one of b, so the one-map form must equal the two-map form bit for bit up to the ordering of sums.
  LocalMap<G> one;
  one.poses = f.a.poses;
  one.poses.insert(one.poses.end(), f.b.poses.begin(), f.b.poses.end());
  const int na = static_cast<int>(f.a.poses.size());
  one.ids = f.a.ids;
  for (const int id : f.b.ids) one.ids.push_back(id + na);
  const auto ma = static_cast<Eigen::Index>(d * f.a.ids.size()),
             mb = static_cast<Eigen::Index>(d * f.b.ids.size());
  one.joint = MatX::Zero(ma + mb, ma + mb);
  one.joint.topLeftCorner(ma, ma) = f.a.joint;
  one.joint.bottomRightCorner(mb, mb) = f.b.joint;
  auto c = f.c;
  for (auto& m : c) m.pose_b += na;
  const auto Q2 = consistency_matrix(f.a, f.b, f.c);
  const auto Q1 = consistency_matrix(one, c);
  for (int u = 0; u < Q1.n; ++u)
    for (int v = 0; v < Q1.n; ++v) CHECK(Q1.at(u, v) == doctest::Approx(Q2.at(u, v)).epsilon(1e-10));
  // Correlate the two groups (+ v vᵀ): the one-map form must now differ from the two-map form given the same
  // diagonal blocks, which sees no correlation.
  Rng rng(8);
  const lie::VecX w = testkit::random_vector(rng, ma + mb) * 0.1;
  one.joint += w * w.transpose();
  auto a = f.a;
  auto b = f.b;
  a.joint = one.joint.topLeftCorner(ma, ma);
  b.joint = one.joint.bottomRightCorner(mb, mb);
  const auto Q1c = consistency_matrix(one, c), Q2c = consistency_matrix(a, b, f.c);
  double moved = 0.0;
  for (std::size_t k = 0; k < Q1c.q.size(); ++k) moved = std::max(moved, std::abs(Q1c.q[k] - Q2c.q[k]));
  CHECK(moved > 1e-3);
  // Composition::independent drops every cross-covariance, so there the two forms agree again.
  ConsistencyOptions ind;
  ind.composition = Composition::independent;
  const auto I1 = consistency_matrix(one, c, ind), I2 = consistency_matrix(a, b, f.c, ind);
  for (std::size_t k = 0; k < I1.q.size(); ++k) CHECK(I1.q[k] == doctest::Approx(I2.q[k]).epsilon(1e-10));
  // Bad inputs name the map's end.
  auto bad = c;
  bad[0].pose_b = static_cast<int>(one.poses.size());
  CHECK(contains(message_of([&] { (void)consistency_matrix(one, bad); }), "of the map (its end k)"));
}

TEST_CASE("consistency_matrix: bad inputs give clear errors") {
  auto f = make_fixture<SE2>(7, 5);
  CHECK(contains(message_of([&] { consistency_matrix(f.a, f.b, {}); }), "candidate set is empty"));
  {
    auto g = f;
    g.c[3].covariance(0, 0) = std::nan("");
    CHECK(contains(message_of([&] { consistency_matrix(g.a, g.b, g.c); }),
                   "candidate 3: covariance has a non-finite"));
  }
  {
    auto g = f;
    g.c[1].pose_a = 40;
    CHECK(contains(message_of([&] { consistency_matrix(g.a, g.b, g.c); }),
                   "candidate 1 touches pose 40 of robot a"));
  }
  {
    auto g = f;
    g.c[2].pose_b = 0;  // a pose of b that exists but has no marginal
    CHECK(contains(message_of([&] { consistency_matrix(g.a, g.b, g.c); }),
                   "pose 0 of robot b has no joint marginal"));
  }
  {
    auto g = f;
    g.a.joint = MatX::Identity(6, 6);
    CHECK(contains(message_of([&] { consistency_matrix(g.a, g.b, g.c); }), "expected 18x18"));
  }
  {
    auto g = f;
    g.b.ids.push_back(1);
    CHECK(contains(message_of([&] { consistency_matrix(g.a, g.b, g.c); }), "listed twice"));
  }
  {
    auto g = f;
    g.a.joint.setZero();
    for (auto& m : g.c) m.covariance.setZero();
    CHECK(contains(message_of([&] { consistency_matrix(g.a, g.b, g.c); }), "not positive definite"));
  }
  CHECK_THROWS_AS(composition_from_string("correlated"), std::invalid_argument);
  CHECK(composition_from_string(to_string(Composition::independent)) == Composition::independent);
}

TEST_CASE("information_from_left_covariance inverts left_covariance_from_information (2D and 3D)") {
  auto rng = core::Rng::stream(11, 0);
  for (int t = 0; t < 20; ++t) {
    const lie::SE2 z(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-3, 3));
    const lie::Mat3 A = testkit::random_matrix(rng, 3, 3);
    const lie::Mat3 info = A * A.transpose() + lie::Mat3::Identity();
    const lie::Mat3 back = information_from_left_covariance(z, left_covariance_from_information(z, info));
    CHECK((back - info).cwiseAbs().maxCoeff() < 1e-8 * info.cwiseAbs().maxCoeff());

    const lie::SE3 z3 = lie::SE3::exp(testkit::random_tangent<lie::SE3>(rng));
    const lie::Mat6 B = testkit::random_matrix(rng, 6, 6);
    const lie::Mat6 info3 = B * B.transpose() + lie::Mat6::Identity();
    const lie::Mat6 back3 = information_from_left_covariance(z3, left_covariance_from_information(z3, info3));
    CHECK((back3 - info3).cwiseAbs().maxCoeff() < 1e-8 * info3.cwiseAbs().maxCoeff());
  }
  CHECK(message_of([] {
          information_from_left_covariance(lie::SE2(), lie::Mat3::Zero());
        }).find("not positive definite") != std::string::npos);
  lie::Mat3 asym = lie::Mat3::Identity();
  asym(0, 1) = 0.5;
  CHECK(message_of([&] { information_from_left_covariance(lie::SE2(), asym); }).find("not symmetric") !=
        std::string::npos);
}
