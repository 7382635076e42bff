#include "merge/robust.hpp"

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "core/blas.hpp"
#include "core/names.hpp"
#include "core/timing.hpp"
#include "cov/chain.hpp"
#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "graph/residuals.hpp"
#include "lie/metrics.hpp"
#include "pgo/optimize.hpp"
#include "pgo/robust.hpp"

namespace keel::merge {

namespace {

std::string at_line(int line) { return line > 0 ? fmt::format(" (line {})", line) : std::string(); }

// pgo's estimate type of a graph.
template <class Graph>
using EstimateOf =
    std::conditional_t<std::is_same_v<Graph, graph::PoseGraph2D>, pgo::Estimate2D, pgo::Estimate3D>;

double group_snooping(Eigen::MatrixXd& Q, const Eigen::VectorXd& r, int* dof_out);

// Data snooping's T = rᵀ Q⁻¹ r (RobustResidualTest::snooping) of each edge of `tested` (edges of `graph`, ids
// global) at `poses`, a maximum-likelihood solution of `graph`: Q = Ω⁻¹ − J Σ Jᵀ, Σ the poses' joint marginal
// (left perturbations, eq. 5.14; the gauge pose fixed), J the residual's Jacobian in the edge's two poses.
// NaN where Q is not positive definite (to 1e-10 of its largest eigenvalue): nothing else constrains the
// edge's relative pose, so it cannot be tested. `groups` non-null: also each group's T (group_snooping,
// below) into group_t and its degrees of freedom into group_dof.
template <class Graph, class Edge, class G>
std::vector<double> snooping_impl(const Graph& graph, const std::vector<G>& poses,
                                  const std::vector<Edge>& tested,
                                  const std::vector<std::vector<std::size_t>>* groups = nullptr,
                                  std::vector<double>* group_t = nullptr,
                                  std::vector<int>* group_dof = nullptr) {
  constexpr int dof = G::DoF;
  cov::GaugeOptions gauge;
  gauge.pose = graph.gauge_pose;
  cov::SparseInformation H;
  if constexpr (dof == 3)
    H = cov::information_matrix(graph, poses, {}, gauge);
  else
    H = cov::information_matrix(graph, poses, gauge);
  const cov::MarginalCovariance marginals(H);
  using Mat = Eigen::Matrix<double, dof, dof>;
  using Lin = decltype(graph::linearize_edge(tested[0].measurement, poses[0], poses[0]));
  // Each residual's linearization, and its linear map r ≈ r̄ + J_i ξ_i + J_j ξ_j in the poses: Q's block
  // (u, v) takes J_u Σ J_vᵀ = Cov(J_u ξ, J_v ξ) (cov::linear_map_covariances, one product per pair of
  // residuals where the pose pairs' joint marginals take four).
  std::vector<Lin> lin;
  std::vector<cov::LinearMap> maps(tested.size());
  lin.reserve(tested.size());
  for (std::size_t k = 0; k < tested.size(); ++k) {
    const auto& e = tested[k];
    lin.push_back(graph::linearize_edge(e.measurement, poses[static_cast<std::size_t>(e.i)],
                                        poses[static_cast<std::size_t>(e.j)]));
    maps[k].vars = {e.i, e.j};
    maps[k].coefficients = {lin[k].J_r_xi_i, lin[k].J_r_xi_j};
  }
  // The blocks B_uv = J_u Σ J_vᵀ, all from one call (one forward pass over the factor): (k, k) for every
  // closure, its own test's; then, for the group test, (u, v) with v < u (indices into `tested`) for each
  // pair of closures that share a group. Q_G's block (u, v) is δ_uv Ω_u⁻¹ − B_uv (group_snooping, below): it
  // depends on the two closures only, not on the group, so neighbouring groups, which share most of their
  // closures, share these blocks.
  std::vector<std::pair<std::size_t, std::size_t>> cross;
  if (groups) {
    for (const auto& grp : *groups)
      for (std::size_t a = 0; a < grp.size(); ++a)
        for (std::size_t b = 0; b < a; ++b) cross.emplace_back(grp[a], grp[b]);
    std::sort(cross.begin(), cross.end());
    cross.erase(std::unique(cross.begin(), cross.end()), cross.end());
  }
  std::vector<std::pair<std::size_t, std::size_t>> asked;
  asked.reserve(tested.size() + cross.size());
  for (std::size_t k = 0; k < tested.size(); ++k) asked.emplace_back(k, k);
  asked.insert(asked.end(), cross.begin(), cross.end());
  // In chunks of at most kChunkValues numbers (128 MiB) of B, so memory stays bounded on large, dense graphs.
  std::vector<Mat> B(asked.size());
  constexpr std::size_t kChunkValues = std::size_t{1} << 24;
  constexpr std::size_t kChunk = kChunkValues / (dof * dof);
  for (std::size_t first = 0; first < asked.size(); first += kChunk) {
    const std::size_t last = std::min(asked.size(), first + kChunk);
    const std::vector<std::pair<std::size_t, std::size_t>> chunk(
        asked.begin() + static_cast<std::ptrdiff_t>(first),
        asked.begin() + static_cast<std::ptrdiff_t>(last));
    const auto b = cov::linear_map_covariances(marginals, maps, chunk);
    for (std::size_t c = first; c < last; ++c) B[c] = b[c - first];
  }
  std::vector<double> t(tested.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < tested.size(); ++k) {
    const Mat omega = tested[k].information;
    Mat Q = omega.inverse() - B[k];
    Q = 0.5 * (Q + Q.transpose()).eval();
    const Eigen::SelfAdjointEigenSolver<Mat> es(Q);
    const auto& l = es.eigenvalues();
    if (!(l(0) > 1e-10 * l(dof - 1))) continue;
    const auto v = (es.eigenvectors().transpose() * lin[k].residual).eval();
    double sum = 0.0;
    for (int a = 0; a < dof; ++a) sum += v(a) * v(a) / l(a);
    t[k] = sum;
  }
  if (groups) {
    group_t->assign(groups->size(), std::numeric_limits<double>::quiet_NaN());
    group_dof->assign(groups->size(), 0);
    auto b_of = [&](std::size_t u, std::size_t v) -> const Mat& {
      if (u == v) return B[u];
      return B[tested.size() +
               static_cast<std::size_t>(std::lower_bound(cross.begin(), cross.end(), std::pair(u, v)) -
                                        cross.begin())];
    };
    for (std::size_t g = 0; g < groups->size(); ++g) {
      const auto& grp = (*groups)[g];
      const auto m = static_cast<Eigen::Index>(grp.size());
      Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(m * dof, m * dof);
      Eigen::VectorXd r(m * dof);
      for (Eigen::Index u = 0; u < m; ++u) {
        const std::size_t k = grp[static_cast<std::size_t>(u)];
        r.segment(u * dof, dof) = lin[k].residual;
        Q.block(u * dof, u * dof, dof, dof) = Mat(tested[k].information).inverse();
      }
      for (Eigen::Index u = 0; u < m; ++u)
        for (Eigen::Index v = 0; v <= u; ++v) {
          const Mat& Buv = b_of(grp[static_cast<std::size_t>(u)], grp[static_cast<std::size_t>(v)]);
          Q.block<dof, dof>(u * dof, v * dof) -= Buv;
          if (v != u) Q.block<dof, dof>(v * dof, u * dof) -= Buv.transpose();
        }
      (*group_t)[g] = group_snooping(Q, r, &(*group_dof)[g]);
    }
  }
  return t;
}

// The groups of RobustResidualTest::groups among `tested` (edges, ids global): for each closure, the closures
// whose ends both lie within `window` poses of its own (|i − i'| ≤ window and |j − j'| ≤ window, each edge's
// ends ordered), itself included; groups of two or more, each listed once (indices into `tested`, ascending).
// Neighbourhoods, not chained components: a long run of true closures along a revisited street stays in
// groups of about 2·window + 1, and a group of wrong closures that agree with one another (consecutive poses
// matched to another place) is inside the neighbourhood of its middle closure.
template <class Edge>
std::vector<std::vector<std::size_t>> closure_groups(const std::vector<Edge>& tested, int window) {
  const std::size_t m = tested.size();
  auto ends = [&](std::size_t k) { return std::minmax(tested[k].i, tested[k].j); };
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t a = 0; a < m; ++a) {
    const auto [ai, aj] = ends(a);
    std::vector<std::size_t> g;
    for (std::size_t b = 0; b < m; ++b) {
      const auto [bi, bj] = ends(b);
      if (std::abs(ai - bi) <= window && std::abs(aj - bj) <= window) g.push_back(b);
    }
    if (g.size() >= 2) groups.push_back(std::move(g));
  }
  std::sort(groups.begin(), groups.end());
  groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
  return groups;
}

// Data snooping for a group of closures (Teunissen, "Testing Theory", §4: the test of a vector of
// observations): T = r_Gᵀ Q_G⁻¹ r_G with r_G the group's residuals stacked and Q_G = blockdiag(Ω_k⁻¹) −
// J_G P J_Gᵀ, P the joint marginal of every pose the group touches. T is, to first order, the drop of Σ rᵀΩr
// when the whole group is left out, so a group of wrong closures that agree with one another (perceptual
// aliasing, §2.7.2), each of which the others mask in the one-closure test, shows as one. Each closure's
// residual depends on its two poses only, so Q_G's block (u, v) is δ_uv Ω_u⁻¹ − Σ J_u,a P_ab J_v,bᵀ over the
// two poses a of u and b of v: small products instead of the dense J P Jᵀ (snooping_impl assembles Q_G so).
// `dof_out` gets the test's degrees of freedom (below); T is NaN when there are none. Q is symmetrized in
// place.
double group_snooping(Eigen::MatrixXd& Q, const Eigen::VectorXd& r, int* dof_out) {
  Q = (0.5 * (Q + Q.transpose())).eval();
  // Well conditioned (Cholesky succeeds and its estimate of 1/cond(Q) is at least 1e-10): T by Cholesky, all
  // m·dof degrees of freedom. Otherwise T over the eigenvalues above 1e-10 of the largest, as in the
  // one-closure test (an eigendecomposition is ~10× a Cholesky factorization on groups of hundreds of rows).
  const Eigen::LLT<Eigen::MatrixXd> llt(Q);
  if (llt.info() == Eigen::Success && llt.rcond() >= 1e-10) {
    *dof_out = static_cast<int>(r.size());
    return llt.matrixL().solve(r).squaredNorm();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Q);
  const auto& l = es.eigenvalues();
  const Eigen::VectorXd v = es.eigenvectors().transpose() * r;
  double sum = 0.0;
  int used = 0;
  for (Eigen::Index a = 0; a < l.size(); ++a)
    if (l(a) > 1e-10 * l(l.size() - 1)) sum += v(a) * v(a) / l(a), ++used;
  *dof_out = used;
  return used > 0 ? sum : std::numeric_limits<double>::quiet_NaN();
}

// A group's test forms its dense Q_G, (dof·m)² numbers for m closures, from blocks of the joint marginal P of
// the poses it touches, at most (dof·poses)² numbers: past 2 GiB together (the consistency stage's limit) the
// group is refused, before anything that size is formed. `what` starts the message.
template <class Edge>
void check_group_memory(const std::vector<Edge>& tested, const std::vector<std::size_t>& group, int dof,
                        const std::string& what) {
  std::vector<int> ids;
  for (const std::size_t k : group) ids.push_back(tested[k].i), ids.push_back(tested[k].j);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  const double side_p = static_cast<double>(dof) * static_cast<double>(ids.size());
  const double side_q = static_cast<double>(dof) * static_cast<double>(group.size());
  const double gib = 8.0 * (side_p * side_p + side_q * side_q) / (1024.0 * 1024 * 1024);
  if (gib > 2.0)
    throw std::invalid_argument(
        fmt::format("{}a group of {} closures touching {} poses: its covariance Q_G and the blocks of the "
                    "joint marginal behind it would take up to {:.1f} GiB (limit 2)",
                    what, group.size(), ids.size(), gib));
}

// Union–find over robots: which robots the given closures join.
struct RobotSets {
  std::vector<int> up;
  explicit RobotSets(int robots) : up(static_cast<std::size_t>(robots)) {
    std::iota(up.begin(), up.end(), 0);
  }
  int top(int r) {
    while (up[static_cast<std::size_t>(r)] != r) r = up[static_cast<std::size_t>(r)];
    return r;
  }
  bool join(int a, int b) {  // false when already joined
    a = top(a), b = top(b);
    if (a == b) return false;
    up[static_cast<std::size_t>(b)] = a;
    return true;
  }
  bool all_joined() {
    for (int r = 1; r < static_cast<int>(up.size()); ++r)
      if (top(r) != top(0)) return false;
    return true;
  }
};

// GNC with truncated least squares (pgo/robust.hpp; Yang, Antonante, Tzoumas, Carlone, RA-L 2020) over the
// closures kept so far, the odometry trusted: weights at μ from each closure's χ² at the last solution, the
// weighted solve (informations scaled by w; w = 0 left out), μ ← factor·μ, until the weights of the last
// solve are all 0 or 1 and are the weights at its own solution, or the round limit. With several robots a
// weight-0 closure that alone joins a robot to the others stays in the weighted solves at weight 1e-3 (the
// robots need a common frame; the least χ² first), and at the end one whose weight is below ½ is kept at
// full weight when the kept ones would leave a robot unjoined (marked joins_robots).
template <class G, class Graph, class EdgeOf, class Assemble, class Chi2At, class Say>
void gnc_stage(RobustRun<G>& run, const Graph& base, const EdgeOf& edge_of, const Assemble& assemble,
               const Chi2At& chi2_at, const Say& say) {
  constexpr double kJoinWeight = 1e-3;
  const RobustOptions& o = run.options;
  const int R = static_cast<int>(run.odometry.size());
  const auto t_gnc = core::Clock::now();
  const double first_solve_s = run.solved.summary.total_time_s;
  const double c2 = pcm::consistency_threshold(o.gnc_p, G::DoF);
  run.gnc_threshold = c2;
  std::vector<std::size_t> pool;  // the closures GNC weighs
  for (std::size_t k = 0; k < run.candidates.size(); ++k)
    if (run.candidates[k].kept) pool.push_back(k);
  run.gnc_weighed = static_cast<int>(pool.size());
  const std::size_t m = pool.size();
  std::vector<double> chi2(m), w(m, 1.0);
  std::vector<G> estimate = run.solved.graph.poses;
  auto residuals = [&] {
    for (std::size_t i = 0; i < m; ++i) chi2[i] = chi2_at(run.candidates[pool[i]], estimate);
  };
  residuals();
  // Weight-0 closures to keep (by index into pool) so that every robot shares a frame: the least χ² first.
  auto joining = [&](const std::vector<double>& weights, double keep_at) {
    std::vector<std::size_t> extra;
    if (R == 1) return extra;
    RobotSets sets(R);
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < m; ++i) {
      const auto& c = run.candidates[pool[i]];
      if (weights[i] >= keep_at)
        sets.join(c.robot_a, c.robot_b);
      else if (c.robot_a != c.robot_b)
        out.push_back(i);
    }
    std::sort(out.begin(), out.end(), [&](std::size_t a, std::size_t b) { return chi2[a] < chi2[b]; });
    for (const std::size_t i : out)
      if (sets.join(run.candidates[pool[i]].robot_a, run.candidates[pool[i]].robot_b)) extra.push_back(i);
    return extra;
  };
  std::optional<pgo::CertifiedSolution<Graph>> last;  // the last weighted solve, when certified-inner
  bool last_repaired = false;
  double mu = pgo::tls_gnc_initial_mu(m == 0 ? 0.0 : *std::max_element(chi2.begin(), chi2.end()), c2);
  if (!std::isfinite(mu)) run.gnc_converged = true;  // every closure within c̄² at the solution: all inliers
  for (int round = 1; std::isfinite(mu); ++round) {
    std::vector<double> next(m);
    for (std::size_t i = 0; i < m; ++i) next[i] = pgo::tls_gnc_weight(chi2[i], mu, c2);
    if (round > 1 && next == w &&
        std::all_of(w.begin(), w.end(), [](double x) { return x == 0.0 || x == 1.0; })) {
      run.gnc_converged = true;
      break;
    }
    if (round > o.gnc_max_rounds) break;
    w = next;
    const auto t_round = core::Clock::now();
    Graph weighted = base;
    weighted.poses = estimate;
    weighted.has_initial_poses = true;
    const auto extra = joining(w, std::numeric_limits<double>::min());
    last_repaired = !extra.empty();
    for (std::size_t i = 0; i < m; ++i) {
      const bool join = std::find(extra.begin(), extra.end(), i) != extra.end();
      if (w[i] <= 0.0 && !join) continue;
      auto e = edge_of(run.candidates[pool[i]]);
      e.information *= join ? kJoinWeight : w[i];
      weighted.edges.push_back(e);
    }
    RobustGncRound r;
    r.mu = mu;
    for (const double x : w) {
      r.inliers += x >= 0.5;
      r.zero += x == 0.0;
      r.weight_sum += x;
    }
    say(fmt::format("GNC round {}: μ = {:.4g}, {} of {} closures weighed ≥ ½, {} at 0", round, mu, r.inliers,
                    m, r.zero));
    if (o.gnc_certified_inner) {
      pgo::CertifiedOptions inner = o.solve;
      inner.chordal_initialization = false;  // from the round before
      last = pgo::certified_solution(weighted, inner);
      estimate = last->graph.poses;
      const auto& cert = last->summary.certificate;
      r.certified = cert.certified;
      r.relative_gap = cert.proven ? cert.bound.relative_gap_up() : std::numeric_limits<double>::infinity();
    } else {
      pgo::Options lm;
      lm.initial_guess = pgo::InitialGuess::supplied;
      lm.constant_poses = {weighted.gauge_pose};
      EstimateOf<Graph> from;
      from.poses = estimate;
      estimate = pgo::optimize(weighted, lm, &from).estimate.poses;
      r.relative_gap = std::numeric_limits<double>::quiet_NaN();
    }
    residuals();
    for (std::size_t i = 0; i < m; ++i) r.tls_cost += std::min(chi2[i], c2);
    r.time_s = core::seconds_since(t_round);
    run.gnc_rounds.push_back(r);
    mu *= o.gnc_mu_factor;
  }
  // The kept closures: weight ≥ ½, and those that alone join a robot.
  const auto extra = joining(w, 0.5);
  run.kept = 0;
  for (std::size_t i = 0; i < m; ++i) {
    auto& c = run.candidates[pool[i]];
    c.gnc_weight = w[i];
    c.joins_robots = std::find(extra.begin(), extra.end(), i) != extra.end();
    c.kept = w[i] >= 0.5 || c.joins_robots;
    run.kept += c.kept;
  }
  assemble();
  const bool binary = std::all_of(w.begin(), w.end(), [](double x) { return x == 0.0 || x == 1.0; });
  if (last && binary && extra.empty() && !last_repaired && !run.gnc_rounds.empty()) {
    // The last weighted solve was the certified solve of exactly the odometry and the kept closures.
    run.solved = std::move(*last);
    run.solved.graph.edges = run.selected.edges;
    run.solved.graph.has_initial_poses = run.selected.has_initial_poses;
  } else if (!run.gnc_rounds.empty()) {
    say(fmt::format("certified solve of the odometry and {} closures GNC kept", run.kept));
    pgo::CertifiedOptions final_solve = o.solve;
    Graph from = run.selected;
    from.poses = estimate;
    from.has_initial_poses = true;
    final_solve.chordal_initialization = false;
    run.solved = pgo::certified_solution(from, final_solve);
    run.solved.graph.has_initial_poses = run.selected.has_initial_poses;
  }
  run.gnc_time_s = first_solve_s + core::seconds_since(t_gnc) -
                   (run.gnc_rounds.empty() ? first_solve_s : run.solved.summary.total_time_s);
}

template <class G, class Graph, class Edge>
RobustRun<G> robust_impl(const std::vector<Graph>& robots, const std::vector<Edge>& inter,
                         const RobustOptions& o, const RobustProgress& progress) {
  o.validate();
  // The whole run on one BLAS thread and with CHOLMOD's OpenMP teams serialized (core/blas.hpp): the
  // Levenberg–Marquardt re-solves and marginals factor small graphs many times, where OpenBLAS's own threads
  // spin against o.threads' workers (and against any other process), and the answer must not depend on the
  // machine's core count. o.threads is the only parallelism. The calls below hold their own guards too; this
  // one keeps OpenBLAS's count at 1 between them instead of switching it back and forth at each.
  const core::SingleThreadedBlas one_blas_thread;
  const core::SerialOpenMp serial_openmp;
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  using J = typename G::Jacobian;
  constexpr int dof = G::DoF;
  if (robots.empty()) throw std::invalid_argument("robust: no robot's graph given");
  const int R = static_cast<int>(robots.size());
  RobustRun<G> run;
  run.options = o;
  auto robot_name = [&](int r) {
    const std::string& src = robots[static_cast<std::size_t>(r)].source;
    return R == 1 ? std::string("the robot")
                  : fmt::format("robot {}{}", r, src.empty() ? "" : " (" + src + ")");
  };

  // A candidate from an input edge: its robots and local poses, where it came from, and the left covariance
  // of its measurement (an information that is not positive definite is refused, named by `where`).
  auto candidate = [](int robot_a, int pose_a, int robot_b, int pose_b, int source, std::size_t edge,
                      const Edge& e, const std::string& where) {
    RobustCandidate<G> c;
    c.robot_a = robot_a;
    c.pose_a = pose_a;
    c.robot_b = robot_b;
    c.pose_b = pose_b;
    c.source = source;
    c.edge = static_cast<int>(edge);
    c.line = e.line;
    c.z = e.measurement;
    try {
      c.covariance = pcm::left_covariance_from_information(e.measurement, e.information);
    } catch (const std::invalid_argument& ex) {
      throw std::invalid_argument(fmt::format("{}: {}", where, ex.what()));
    }
    return c;
  };

  // Each robot's odometry (edges between consecutive poses, either direction, chaining every pose) and its
  // own candidate closures (every other edge).
  int total = 0;
  for (int r = 0; r < R; ++r) {
    const Graph& g = robots[static_cast<std::size_t>(r)];
    const int n = static_cast<int>(g.poses.size());
    if (n == 0) throw std::invalid_argument(fmt::format("robust: {} has no poses", robot_name(r)));
    run.offsets.push_back(total);
    total += n;
    Graph odo;
    odo.poses = g.poses;
    odo.has_initial_poses = g.has_initial_poses;
    odo.source = g.source;
    std::vector<char> chained(static_cast<std::size_t>(n), 0);
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      const auto& e = g.edges[k];
      if (e.i < 0 || e.i >= n || e.j < 0 || e.j >= n)
        throw std::invalid_argument(
            fmt::format("robust: {}: edge {} → {}{} names a pose it does not have (0 … {})", robot_name(r),
                        e.i, e.j, at_line(e.line), n - 1));
      if (std::abs(e.j - e.i) == 1) {
        odo.edges.push_back(e);
        chained[static_cast<std::size_t>(std::max(e.i, e.j))] = 1;
        continue;
      }
      run.candidates.push_back(candidate(
          r, e.i, r, e.j, r, k, e,
          fmt::format("robust: {}: loop closure {} → {}{}", robot_name(r), e.i, e.j, at_line(e.line))));
    }
    for (int k = 1; k < n; ++k)
      if (!chained[static_cast<std::size_t>(k)])
        throw std::invalid_argument(fmt::format(
            "robust: {}: pose {} has no odometry edge from pose {} (the odometry, edges between consecutive "
            "poses, must chain every pose; the loop closures are the other edges)",
            robot_name(r), k, k - 1));
    run.odometry.push_back(std::move(odo));
  }

  // The inter-robot candidates, ids global; each oriented from the lower robot to the higher (z⁻¹ =
  // exp(−Ad(z⁻¹) n) z̄⁻¹ to first order, so Σ' = Ad(z⁻¹) Σ Ad(z⁻¹)ᵀ).
  auto robot_of = [&](int id) {
    const auto it = std::upper_bound(run.offsets.begin(), run.offsets.end(), id);
    return static_cast<int>(it - run.offsets.begin()) - 1;
  };
  for (std::size_t k = 0; k < inter.size(); ++k) {
    const auto& e = inter[k];
    const std::string where = fmt::format("robust: inter-robot candidate {}{}", k, at_line(e.line));
    for (const int id : {e.i, e.j})
      if (id < 0 || id >= total)
        throw std::invalid_argument(
            fmt::format("{}: id {} is not a pose of the robots ({} poses together: ids 0 … {}, robot r's "
                        "pose k is id k plus "
                        "the poses of the robots before it)",
                        where, id, total, total - 1));
    const int ra = robot_of(e.i), rb = robot_of(e.j);
    RobustCandidate<G> c = candidate(ra, e.i - run.offsets[static_cast<std::size_t>(ra)], rb,
                                     e.j - run.offsets[static_cast<std::size_t>(rb)], -1, k, e, where);
    if (c.robot_a > c.robot_b) {
      std::swap(c.robot_a, c.robot_b);
      std::swap(c.pose_a, c.pose_b);
      c.z = c.z.inverse();
      const J A = c.z.adjoint();
      const J S = A * c.covariance * A.transpose();
      c.covariance = 0.5 * (S + S.transpose());
    }
    run.candidates.push_back(c);
  }

  // Groups: each robot's own closures, then each pair of robots, in that order.
  std::map<std::pair<int, int>, int> group_of;
  {
    std::vector<std::pair<int, int>> keys;
    for (const auto& c : run.candidates) keys.emplace_back(c.robot_a, c.robot_b);
    std::sort(keys.begin(), keys.end(), [](const auto& x, const auto& y) {
      return std::tuple(x.first != x.second, x) < std::tuple(y.first != y.second, y);
    });
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (const auto& k : keys) {
      group_of[k] = static_cast<int>(run.groups.size());
      RobustGroup grp;
      grp.robot_a = k.first;
      grp.robot_b = k.second;
      run.groups.push_back(grp);
    }
    for (std::size_t k = 0; k < run.candidates.size(); ++k) {
      auto& c = run.candidates[k];
      c.group = group_of.at({c.robot_a, c.robot_b});
      run.groups[static_cast<std::size_t>(c.group)].members.push_back(static_cast<int>(k));
    }
  }

  run.gamma = pcm::consistency_threshold(o.p, dof);
  if (o.gnc == RobustGnc::only) {
    // No consistency check: every candidate goes to GNC (each group's selection is all of it, unsearched).
    for (auto& grp : run.groups) {
      grp.selection.selected.resize(grp.members.size());
      std::iota(grp.selection.selected.begin(), grp.selection.selected.end(), 0);
    }
    for (auto& c : run.candidates) c.kept = true;
    run.kept = static_cast<int>(run.candidates.size());
  }
  // Each robot's odometry map and the joint marginal of the poses its candidates touch.
  if (o.gnc != RobustGnc::only)
    say(fmt::format("odometry maps ({} robot{}, {} poses, {} candidate loop closures)", R, R == 1 ? "" : "s",
                    total, run.candidates.size()));
  std::vector<pcm::LocalMap<G>> maps(static_cast<std::size_t>(R));
  if (o.gnc != RobustGnc::only)
    for (const auto& c : run.candidates) {
      maps[static_cast<std::size_t>(c.robot_a)].ids.push_back(c.pose_a);
      maps[static_cast<std::size_t>(c.robot_b)].ids.push_back(c.pose_b);
    }
  for (int r = 0; r < R; ++r) {
    auto& map = maps[static_cast<std::size_t>(r)];
    if (map.ids.empty()) continue;  // no candidate touches it: its odometry is solved with the rest
    std::sort(map.ids.begin(), map.ids.end());
    map.ids.erase(std::unique(map.ids.begin(), map.ids.end()), map.ids.end());
    const double gib = 8.0 * std::pow(static_cast<double>(dof) * static_cast<double>(map.ids.size()), 2) /
                       (1024.0 * 1024 * 1024);
    if (gib > 2.0)
      throw std::invalid_argument(
          fmt::format("robust: {}: its candidates touch {} poses, whose dense joint marginal would take "
                      "{:.1f} GiB (limit 2)",
                      robot_name(r), map.ids.size(), gib));
    const auto t0 = core::Clock::now();
    const auto local = solve_local(run.odometry[static_cast<std::size_t>(r)], o.local);
    run.odometry_time_s += core::seconds_since(t0);
    say(fmt::format("joint marginals of the {} poses of {} that candidates touch", map.ids.size(),
                    robot_name(r)));
    const auto t1 = core::Clock::now();
    map.poses = local.poses;
    // The odometry map is a chain: its joint marginal in closed form (cov/chain.hpp), H⁻¹ exactly.
    map.joint = cov::chain_joint(run.odometry[static_cast<std::size_t>(r)], local.poses, map.ids);
    run.marginals_time_s += core::seconds_since(t1);
  }

  // Each group's Q (eq. 2.4), its threshold and its largest consistent set (eq. 2.5).
  pcm::ConsistencyOptions co;
  co.composition = o.composition;
  co.threads = o.threads;
  co.cutoff = run.gamma;  // only the consistency graph at γ is used: q_vu is not needed where q_uv > γ
  pcm::CliqueOptions clique;
  clique.time_limit_s = o.time_limit_s;
  for (auto& grp : run.groups) {
    if (o.gnc == RobustGnc::only) break;
    std::vector<pcm::InterRobotMeasurement<G>> cand;
    for (const int k : grp.members) {
      const auto& c = run.candidates[static_cast<std::size_t>(k)];
      cand.push_back({c.pose_a, c.pose_b, c.z, c.covariance});
    }
    const auto& ma = maps[static_cast<std::size_t>(grp.robot_a)];
    say(fmt::format("{}: consistency of {} candidates, then the largest consistent set",
                    grp.robot_a == grp.robot_b ? robot_name(grp.robot_a)
                                               : robot_name(grp.robot_a) + " and " + robot_name(grp.robot_b),
                    cand.size()));
    const auto t0 = core::Clock::now();
    grp.q = grp.robot_a == grp.robot_b
                ? pcm::consistency_matrix(ma, cand, co)
                : pcm::consistency_matrix(ma, maps[static_cast<std::size_t>(grp.robot_b)], cand, co);
    grp.consistency_time_s = core::seconds_since(t0);
    run.consistency_time_s += grp.consistency_time_s;
    grp.selector = o.selector != RobustSelector::automatic          ? o.selector
                   : static_cast<int>(cand.size()) <= o.exact_up_to ? RobustSelector::exact
                                                                    : RobustSelector::densest;
    if (grp.selector == RobustSelector::densest) {
      grp.selection = pcm::select_densest(grp.q, run.gamma);
      // No search proves its size; the degeneracy bound of the consistency graph (max core + 1) bounds it.
      const auto t1 = core::Clock::now();
      const auto bound =
          pcm::maximum_clique_heuristic(pcm::ConsistencyGraph::from_threshold(grp.q.n, grp.q.q, run.gamma));
      pcm::CliqueResult r;
      r.clique = grp.selection.selected;
      r.upper_bound = bound.upper_bound;
      r.status = static_cast<int>(r.clique.size()) == r.upper_bound ? core::SearchStatus::optimal
                                                                    : core::SearchStatus::unproven;
      grp.selection.search = r;
      grp.selection.time_s += core::seconds_since(t1);
    } else {
      grp.selection = pcm::select_pcm(grp.q, run.gamma,
                                      grp.selector == RobustSelector::exact ? pcm::CliqueAlgorithm::exact
                                                                            : pcm::CliqueAlgorithm::heuristic,
                                      clique);
    }
    run.selection_time_s += grp.selection.time_s;
    for (const int s : grp.selection.selected)
      run.candidates[static_cast<std::size_t>(grp.members[static_cast<std::size_t>(s)])].kept = true;
    for (std::size_t u = 0; u < grp.members.size(); ++u) {
      int against = 0;
      for (const int s : grp.selection.selected)
        if (grp.q.at(static_cast<int>(u), s) > run.gamma || grp.q.at(s, static_cast<int>(u)) > run.gamma)
          ++against;
      run.candidates[static_cast<std::size_t>(grp.members[u])].inconsistent_with_kept = against;
    }
    run.kept += static_cast<int>(grp.selection.selected.size());
  }

  // The first robot that kept closures (all but candidate `skip`) leave unjoined to robot 0, or −1 when every
  // robot is joined: without a join the robots have no common frame.
  auto unjoined_robot = [&](std::size_t skip) {
    RobotSets sets(R);
    for (std::size_t k = 0; k < run.candidates.size(); ++k)
      if (k != skip && run.candidates[k].kept)
        sets.join(run.candidates[k].robot_a, run.candidates[k].robot_b);
    for (int r = 1; r < R; ++r)
      if (sets.top(r) != sets.top(0)) return r;
    return -1;
  };
  if (const int r = unjoined_robot(run.candidates.size()); r >= 0)
    throw std::invalid_argument(fmt::format(
        "robust: no kept inter-robot closure joins {} to robot 0, so the robots have no common frame "
        "({} of {} candidates kept)",
        robot_name(r), run.kept, run.candidates.size()));

  // All odometry, then the kept closures, as the inputs gave them (ids moved by the robots' offsets).
  Graph base;
  for (int r = 0; r < R; ++r) {
    const auto off = run.offsets[static_cast<std::size_t>(r)];
    const Graph& odo = run.odometry[static_cast<std::size_t>(r)];
    base.poses.insert(base.poses.end(), odo.poses.begin(), odo.poses.end());
    for (auto e : odo.edges) {
      e.i += off;
      e.j += off;
      base.edges.push_back(e);
    }
  }
  base.has_initial_poses =
      std::all_of(robots.begin(), robots.end(), [](const Graph& g) { return g.has_initial_poses; });
  base.source = R == 1 ? robots[0].source : std::string();
  auto edge_of = [&](const RobustCandidate<G>& c) {
    if (c.source < 0) return inter[static_cast<std::size_t>(c.edge)];
    auto e = robots[static_cast<std::size_t>(c.source)].edges[static_cast<std::size_t>(c.edge)];
    e.i += run.offsets[static_cast<std::size_t>(c.source)];
    e.j += run.offsets[static_cast<std::size_t>(c.source)];
    return e;
  };
  auto assemble = [&] {
    run.selected = base;
    for (const auto& c : run.candidates)
      if (c.kept) run.selected.edges.push_back(edge_of(c));
  };
  auto chi2_at = [&](const RobustCandidate<G>& c, const std::vector<G>& poses) {
    const auto e = edge_of(c);
    const auto res = graph::edge_residual(e.measurement, poses[static_cast<std::size_t>(e.i)],
                                          poses[static_cast<std::size_t>(e.j)]);
    return static_cast<double>(res.dot(e.information * res));
  };
  assemble();
  say(fmt::format("certified solve of the odometry and {} kept loop closures", run.kept));
  const bool residual_check = o.gnc == RobustGnc::off && o.residual_p > 0.0;
  // first_solve_rank_d: the residual check starts from the certified solver's local optimum at rank d (no
  // staircase). Certified there, it is the certified solve's answer (the staircase stops at rank d with that
  // point); otherwise the check starts from it, and the certified solve comes once nothing is removed.
  const bool rank_d_first = residual_check && o.first_solve_rank_d;
  {
    pgo::CertifiedOptions first = o.solve;
    if (rank_d_first) first.max_rank = G::Dim - 1;  // d (G's matrices are (d + 1) × (d + 1))
    run.solved = pgo::certified_solution(run.selected, first);
  }
  // The residual check: the kept closure whose χ² = rᵀΩr at the solution is largest, above γ_r =
  // F⁻¹_χ²(dof)(1 − residual_p), is removed and the rest re-solved by Levenberg–Marquardt from the current
  // estimate, one closure per round (never one whose removal would leave a robot without a common frame);
  // once none is above γ_r, the certified solve of what is left gives the answer and its certificate.
  if (residual_check) {
    run.residual_threshold = pcm::consistency_threshold(o.residual_p, dof);  // edge; snooping: set below
    // Time of the check: the certified solves whose answers a later round replaced (the first among them) and
    // the re-solves; the last certified solve is the answer's own (solved.summary).
    const auto t_check = core::Clock::now();
    const double first_solve_s = run.solved.summary.total_time_s;
    // Levenberg–Marquardt on the kept graph from `from` (the anisotropic cost the statistics assume).
    auto relax = [&](const std::vector<G>& from_poses) {
      pgo::Options lm;
      lm.initial_guess = pgo::InitialGuess::supplied;
      lm.constant_poses = {run.selected.gauge_pose};
      EstimateOf<Graph> from;
      from.poses = from_poses;
      return pgo::optimize(run.selected, lm, &from).estimate.poses;
    };
    const bool by_groups = o.residual_test == RobustResidualTest::groups;
    const bool snooping = o.residual_test == RobustResidualTest::snooping || by_groups;
    bool first_round = true;
    // The closure a round removes, and the statistics behind it.
    struct Pick {
      std::size_t k = 0;                                          // candidates.size(): none
      double chi2 = 0.0;                                          // its χ² (at the statistic's solution)
      double t = std::numeric_limits<double>::quiet_NaN();        // snooping: its T
      double group_t = std::numeric_limits<double>::quiet_NaN();  // groups: the T of the group that picked it
      int group_dof = 0, group_size = 0;
    };
    // The worst kept closure above its threshold at `estimate`, if any (k = candidates.size() if none). For
    // snooping, at the maximum-likelihood solution: `estimate` relaxed first when it is the certified
    // solve's. Groups: the test most in excess of its own threshold, T / F⁻¹_χ²(dof)(1 − α) with α the
    // Bonferroni share over every test of the round, single or group; a group's test picks its member with
    // the largest single T (the one the others mask least).
    auto worst_at = [&](const std::vector<G>& estimate, bool certified) {
      Pick pick;
      pick.k = run.candidates.size();
      std::vector<std::size_t> tested;
      for (std::size_t k = 0; k < run.candidates.size(); ++k)
        if (run.candidates[k].kept) tested.push_back(k);
      if (!snooping) {
        double worst = run.residual_threshold;
        for (const std::size_t k : tested)
          if (const double x = chi2_at(run.candidates[k], estimate); x > worst && unjoined_robot(k) < 0)
            worst = x, pick.k = k;
        pick.chi2 = worst;
        return pick;
      }
      const std::vector<G> at = certified ? relax(estimate) : estimate;
      std::vector<Edge> edges;
      for (const std::size_t k : tested) edges.push_back(edge_of(run.candidates[k]));
      std::vector<std::vector<std::size_t>> groups;
      std::vector<double> group_t;
      std::vector<int> group_dof;
      if (by_groups) {
        groups = closure_groups(edges, o.group_window);
        for (const auto& g : groups)
          check_group_memory(edges, g, dof,
                             fmt::format("robust: the residual test's groups (group_window = {}; a smaller "
                                         "window gives smaller groups): ",
                                         o.group_window));
      }
      const auto statistic =
          snooping_impl(run.selected, at, edges, by_groups ? &groups : nullptr, &group_t, &group_dof);
      const auto finite = [](double x) { return !std::isnan(x); };
      const auto m = std::count_if(statistic.begin(), statistic.end(), finite) +
                     std::count_if(group_t.begin(), group_t.end(), finite);
      const double alpha = o.residual_p / static_cast<double>(std::max<std::ptrdiff_t>(m, 1));
      const double threshold = pcm::consistency_threshold(alpha, dof);
      if (first_round) run.residual_threshold = threshold, first_round = false;
      double excess = 1.0;
      std::size_t u_pick = tested.size();
      for (std::size_t u = 0; u < tested.size(); ++u)
        if (statistic[u] / threshold > excess && unjoined_robot(tested[u]) < 0)
          excess = statistic[u] / threshold, u_pick = u;
      for (std::size_t g = 0; g < groups.size(); ++g) {
        if (std::isnan(group_t[g])) continue;
        const double x = group_t[g] / lie::chi2_quantile(1.0 - alpha, group_dof[g]);
        if (!(x > excess)) continue;
        std::size_t best = tested.size();
        for (const std::size_t u : groups[g])
          if (unjoined_robot(tested[u]) < 0 && (best == tested.size() || statistic[u] > statistic[best]))
            best = u;
        if (best == tested.size()) continue;
        excess = x, u_pick = best;
        pick.group_t = group_t[g], pick.group_dof = group_dof[g];
        pick.group_size = static_cast<int>(groups[g].size());
      }
      if (u_pick == tested.size()) return pick;
      pick.k = tested[u_pick];
      pick.t = statistic[u_pick];
      pick.chi2 = chi2_at(run.candidates[pick.k], at);
      return pick;
    };
    std::vector<G> estimate = run.solved.graph.poses;
    bool solver_estimate = true;  // `estimate` is a point of the certified solver (relaxed before snooping)
    // `estimate` is the certified solve's answer (the rank-d solve's only when it is certified: the whole
    // staircase would have stopped there with the same point)
    bool certified_estimate = !rank_d_first || run.solved.summary.status == core::SearchStatus::optimal;
    bool resolved = false;  // run.solved is no longer the first solve's
    while (run.residual_rounds < o.max_residual_rounds) {
      const Pick pick = worst_at(estimate, solver_estimate);
      if (pick.k == run.candidates.size()) {
        if (certified_estimate) break;
        // None is above its threshold at LM's estimate: solve what is left with the certificate, and check
        // its answer.
        say(fmt::format("certified solve of the odometry and {} kept loop closures", run.kept));
        run.solved = pgo::certified_solution(run.selected, o.solve);
        estimate = run.solved.graph.poses;
        certified_estimate = solver_estimate = resolved = true;
        continue;
      }
      auto& c = run.candidates[pick.k];
      c.kept = false;
      c.removed_in_round = ++run.residual_rounds;
      c.residual_chi2 = pick.chi2;
      c.snooping_t = pick.t;
      c.residual_group_t = pick.group_t;
      c.residual_group_dof = pick.group_dof;
      c.residual_group_size = pick.group_size;
      --run.kept;
      assemble();
      if (!std::isnan(pick.group_t))
        say(fmt::format(
            "residual check, round {}: closure {} → {} removed (its group of {}: T {:.4g}, {} dof)",
            run.residual_rounds, c.pose_a, c.pose_b, pick.group_size, pick.group_t, pick.group_dof));
      else if (snooping)
        say(fmt::format("residual check, round {}: closure {} → {} removed (T {:.4g})", run.residual_rounds,
                        c.pose_a, c.pose_b, pick.t));
      else
        say(fmt::format("residual check, round {}: closure {} → {} removed (χ² {:.4g} > {:.4g})",
                        run.residual_rounds, c.pose_a, c.pose_b, pick.chi2, run.residual_threshold));
      estimate = relax(estimate);
      certified_estimate = solver_estimate = false;
    }
    if (!certified_estimate) {  // the round limit was reached after a removal (or at once, rank d
                                // uncertified)
      run.solved = pgo::certified_solution(run.selected, o.solve);
      resolved = true;
    }
    if (run.residual_rounds > 0 || resolved)
      run.residual_time_s = first_solve_s + core::seconds_since(t_check) - run.solved.summary.total_time_s;
  }
  if (o.gnc != RobustGnc::off) gnc_stage(run, base, edge_of, assemble, chi2_at, say);
  for (auto& c : run.candidates)
    if (c.kept) c.residual_chi2 = chi2_at(c, run.solved.graph.poses);
  return run;
}

}  // namespace

namespace {
constexpr core::NameTable<RobustSelector, 4> kSelectorNames{"merge::RobustSelector",
                                                            {{{RobustSelector::automatic, "auto"},
                                                              {RobustSelector::exact, "exact"},
                                                              {RobustSelector::heuristic, "heuristic"},
                                                              {RobustSelector::densest, "densest"}}}};
constexpr core::NameTable<RobustResidualTest, 3> kResidualTestNames{
    "merge::RobustResidualTest",
    {{{RobustResidualTest::edge, "edge"},
      {RobustResidualTest::snooping, "snooping"},
      {RobustResidualTest::groups, "groups"}}}};
constexpr core::NameTable<RobustGnc, 3> kGncNames{
    "merge::RobustGnc",
    {{{RobustGnc::off, "off"}, {RobustGnc::after_pcm, "after"}, {RobustGnc::only, "only"}}}};
}  // namespace

std::string_view to_string(RobustSelector s) { return kSelectorNames.name(s); }
RobustSelector robust_selector_from_string(std::string_view text) { return kSelectorNames.parse(text); }
std::string_view to_string(RobustGnc g) { return kGncNames.name(g); }
std::string_view to_string(RobustResidualTest t) { return kResidualTestNames.name(t); }
RobustResidualTest robust_residual_test_from_string(std::string_view text) {
  return kResidualTestNames.parse(text);
}
RobustGnc robust_gnc_from_string(std::string_view text) { return kGncNames.parse(text); }

void RobustOptions::validate() const {
  if (!(residual_p >= 0.0 && residual_p < 1.0))
    throw std::invalid_argument(fmt::format(
        "merge::RobustOptions: residual_p must be in [0, 1), 0 for no residual check (got {})", residual_p));
  if (group_window < 1)
    throw std::invalid_argument(
        fmt::format("merge::RobustOptions: group_window must be >= 1 (got {})", group_window));
  if (max_residual_rounds < 0)
    throw std::invalid_argument(
        fmt::format("merge::RobustOptions: max_residual_rounds must be >= 0 (got {})", max_residual_rounds));
  if (exact_up_to < 1)
    throw std::invalid_argument(
        fmt::format("merge::RobustOptions: exact_up_to must be >= 1 (got {})", exact_up_to));
  if (!(p > 0.0 && p < 1.0))
    throw std::invalid_argument(fmt::format("merge::RobustOptions: p must be in (0, 1) (got {})", p));
  if (!(gnc_p > 0.0 && gnc_p < 1.0))
    throw std::invalid_argument(fmt::format("merge::RobustOptions: gnc_p must be in (0, 1) (got {})", gnc_p));
  if (!(std::isfinite(gnc_mu_factor) && gnc_mu_factor > 1.0))
    throw std::invalid_argument(
        fmt::format("merge::RobustOptions: gnc_mu_factor must be finite and > 1 (got {})", gnc_mu_factor));
  if (gnc_max_rounds < 1)
    throw std::invalid_argument(
        fmt::format("merge::RobustOptions: gnc_max_rounds must be >= 1 (got {})", gnc_max_rounds));
  if (!(std::isfinite(time_limit_s) && time_limit_s >= 0.0))
    throw std::invalid_argument(fmt::format(
        "merge::RobustOptions: time_limit_s must be finite and >= 0, 0 for none (got {})", time_limit_s));
  local.validate();
  solve.validate();
}

std::vector<double> snooping_statistics(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& poses,
                                        const std::vector<graph::Edge2>& tested) {
  return snooping_impl(graph, poses, tested);
}
std::vector<double> snooping_statistics(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& poses,
                                        const std::vector<graph::Edge3>& tested) {
  return snooping_impl(graph, poses, tested);
}

namespace {
template <class Graph, class Edge, class G>
GroupStatistic group_statistic_impl(const Graph& graph, const std::vector<G>& poses,
                                    const std::vector<Edge>& tested) {
  if (tested.empty()) return {std::numeric_limits<double>::quiet_NaN(), 0};
  std::vector<std::vector<std::size_t>> one(1);
  for (std::size_t k = 0; k < tested.size(); ++k) one[0].push_back(k);
  check_group_memory(tested, one[0], G::DoF, "group_snooping_statistic: ");
  std::vector<double> t;
  std::vector<int> dof;
  (void)snooping_impl(graph, poses, tested, &one, &t, &dof);
  return {t[0], dof[0]};
}
}  // namespace

GroupStatistic group_snooping_statistic(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& poses,
                                        const std::vector<graph::Edge2>& tested) {
  return group_statistic_impl(graph, poses, tested);
}
GroupStatistic group_snooping_statistic(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& poses,
                                        const std::vector<graph::Edge3>& tested) {
  return group_statistic_impl(graph, poses, tested);
}

RobustRun2 robust(const std::vector<graph::PoseGraph2D>& robots, const std::vector<graph::Edge2>& inter_robot,
                  const RobustOptions& options, const RobustProgress& progress) {
  return robust_impl<lie::SE2>(robots, inter_robot, options, progress);
}
RobustRun3 robust(const std::vector<graph::PoseGraph3D>& robots, const std::vector<graph::Edge3>& inter_robot,
                  const RobustOptions& options, const RobustProgress& progress) {
  return robust_impl<lie::SE3>(robots, inter_robot, options, progress);
}

}  // namespace keel::merge
