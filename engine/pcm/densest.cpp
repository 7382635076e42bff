#include "pcm/densest.hpp"

#include <fmt/format.h>

#include <Eigen/Core>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace keel::pcm {

void DensestOptions::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("DensestOptions: " + what); };
  if (max_outer < 1) fail(fmt::format("max_outer must be >= 1 (got {})", max_outer));
  if (max_inner < 1) fail(fmt::format("max_inner must be >= 1 (got {})", max_inner));
  if (max_stalled_outer < 0) fail(fmt::format("max_stalled_outer must be >= 0 (got {})", max_stalled_outer));
  if (!(beta > 0.0 && beta < 1.0)) fail(fmt::format("beta must be in (0, 1) (got {:g})", beta));
  if (!(tol_u > 0.0) || !(tol_f > 0.0) || !(eps > 0.0))
    fail(fmt::format("tol_u, tol_f and eps must be > 0 (got {:g}, {:g}, {:g})", tol_u, tol_f, eps));
}

namespace {

using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

// The data of F_d: the 0/1 adjacency A of the consistency graph and, for weighted affinities, M (already zero
// on inconsistent pairs, 1 on the diagonal). Binary affinities use M = A + I without storing it. C̄ = 11ᵀ − A
// − I, so C̄u = (Σu)·1 − Au − u needs no matrix of its own.
//
// Two storages. Dense: A (and M) as n x n matrices; the products cost one pass over the columns in the
// support of u when it is small (after the first steps the projection onto u >= 0 leaves about the cluster's
// size of non-zero entries), else a dense matrix-vector product. Sparse (compressed rows of the adjacency;
// M's off-diagonal weights beside them): Au = Σ_{j in supp u} u_j A_{:,j} scattered over the neighbours of
// the support when they are fewer than half the stored entries, else gathered row by row; the cost follows
// the edges, not n². A is symmetric, so a row is also a column. The two differ only in the order of the sums.
struct Problem {
  bool binary = true;
  bool sparse = false;
  Mat A, M;                      // dense storage
  std::vector<int> start, next;  // sparse storage: the neighbours of i are next[start[i] … start[i+1])
  std::vector<double> weight;    // sparse, weighted: M_{i,next[k]} beside next[k]

  void products(const Vec& u, Vec& Mu, Vec& Cu) const {
    support_.clear();
    for (Eigen::Index i = 0; i < u.size(); ++i)
      if (u(i) != 0.0) support_.push_back(static_cast<int>(i));
    if (sparse) {
      sparse_product(u, nullptr, Au_);
      if (binary) {
        Mu = Au_ + u;
      } else {
        sparse_product(u, weight.data(), Mu);
        Mu += u;
      }
    } else {
      dense_product(A, u, Au_);  // A and M are symmetric
      if (binary)
        Mu = Au_ + u;
      else
        dense_product(M, u, Mu);
    }
    Cu = Vec::Constant(u.size(), u.sum()) - Au_ - u;
  }

 private:
  void dense_product(const Mat& X, const Vec& u, Vec& out) const {
    const auto n = u.size();
    if (static_cast<Eigen::Index>(support_.size()) * 4 > n) {
      out.noalias() = X * u;
      return;
    }
    out.setZero(n);
    for (const int j : support_) out.noalias() += u(j) * X.col(j);
  }
  // out = Xu for X = A (w == nullptr) or X = M − I (w: the weights beside `next`).
  void sparse_product(const Vec& u, const double* w, Vec& out) const {
    const int n = static_cast<int>(u.size());
    std::size_t touched = 0;
    for (const int j : support_) touched += static_cast<std::size_t>(start[j + 1] - start[j]);
    if (2 * touched < next.size()) {
      out.setZero(n);
      for (const int j : support_) {
        const double uj = u(j);
        for (int k = start[j]; k < start[j + 1]; ++k) out(next[k]) += w ? w[k] * uj : uj;
      }
      return;
    }
    out.resize(n);
    for (int i = 0; i < n; ++i) {
      double sum = 0.0;
      for (int k = start[i]; k < start[i + 1]; ++k) sum += w ? w[k] * u(next[k]) : u(next[k]);
      out(i) = sum;
    }
  }
  mutable std::vector<int> support_;
  mutable Vec Au_;
};

bool use_sparse(const ConsistencyGraph& g, DensestOptions::Storage storage) {
  switch (storage) {
    case DensestOptions::Storage::dense:
      return false;
    case DensestOptions::Storage::sparse:
      return true;
    case DensestOptions::Storage::automatic:
      break;
  }
  const double n = g.size();
  return n < 2 || 2.0 * static_cast<double>(g.num_edges()) < kSparseDensity * n * (n - 1.0);
}

// The adjacency in the chosen storage (weights are filled by the weighted overload).
Problem adjacency(const ConsistencyGraph& g, bool sparse) {
  const int n = g.size();
  Problem p;
  p.sparse = sparse;
  if (sparse) {
    p.start.assign(static_cast<std::size_t>(n) + 1, 0);
    p.next.reserve(static_cast<std::size_t>(2 * g.num_edges()));
    for (int v = 0; v < n; ++v) {
      const std::uint64_t* r = g.row(v);
      for (int w = 0; w < g.words(); ++w)
        for (std::uint64_t bits = r[w]; bits; bits &= bits - 1)
          p.next.push_back(w * 64 + std::countr_zero(bits));
      p.start[static_cast<std::size_t>(v) + 1] = static_cast<int>(p.next.size());
    }
  } else {
    p.A = Mat::Zero(n, n);
    for (int v = 0; v < n; ++v)
      for (int w : g.neighbors(v)) p.A(v, w) = 1.0;
  }
  return p;
}

// Raw selection, its repair to a maximal clique, and the violation count (see the header).
void round_and_repair(const ConsistencyGraph& g, const Vec& u, double objective, double eps,
                      DensestResult& r) {
  const int n = g.size();
  std::vector<int> support;
  for (int i = 0; i < n; ++i)
    if (u(i) > eps) support.push_back(i);
  std::sort(support.begin(), support.end(), [&](int a, int b) { return u(a) != u(b) ? u(a) > u(b) : a < b; });
  const long long width =
      std::clamp<long long>(std::llround(objective), 1, static_cast<long long>(support.size()));
  r.raw.assign(support.begin(), support.begin() + width);
  std::sort(r.raw.begin(), r.raw.end());
  for (std::size_t a = 0; a < r.raw.size(); ++a)
    for (std::size_t b = a + 1; b < r.raw.size(); ++b) r.violations += g.adjacent(r.raw[a], r.raw[b]) ? 0 : 1;

  std::vector<int> s = r.raw;
  for (;;) {
    int worst = -1, worst_count = 0;
    for (int v : s) {
      int count = 0;
      for (int w : s) count += (w != v && !g.adjacent(v, w)) ? 1 : 0;
      const bool better = count > worst_count || (count == worst_count && count > 0 &&
                                                  (u(v) < u(worst) || (u(v) == u(worst) && v > worst)));
      if (better) worst = v, worst_count = count;
    }
    if (worst_count == 0) break;
    s.erase(std::find(s.begin(), s.end(), worst));
  }
  // Extend to a maximal clique: candidates adjacent to every member.
  std::vector<char> in(static_cast<std::size_t>(n), 0), candidate(static_cast<std::size_t>(n), 1);
  for (int v : s) in[static_cast<std::size_t>(v)] = 1;
  for (int v = 0; v < n; ++v) {
    if (in[static_cast<std::size_t>(v)]) {
      candidate[static_cast<std::size_t>(v)] = 0;
      continue;
    }
    for (int w : s)
      if (!g.adjacent(v, w)) {
        candidate[static_cast<std::size_t>(v)] = 0;
        break;
      }
  }
  for (;;) {
    int best = -1;
    for (int v = 0; v < n; ++v)
      if (candidate[static_cast<std::size_t>(v)] && (best < 0 || u(v) > u(best))) best = v;
    if (best < 0) break;
    s.push_back(best);
    candidate[static_cast<std::size_t>(best)] = 0;
    for (int v = 0; v < n; ++v)
      if (candidate[static_cast<std::size_t>(v)] && !g.adjacent(v, best))
        candidate[static_cast<std::size_t>(v)] = 0;
  }
  std::sort(s.begin(), s.end());
  r.selection = std::move(s);
}

DensestResult solve(const ConsistencyGraph& g, const Problem& p, const DensestOptions& o) {
  o.validate();
  const auto t0 = std::chrono::steady_clock::now();
  DensestResult r;
  const int n = g.size();
  if (n == 0) {
    r.converged = true;
    return r;
  }
  // u0: one power step of M on the all-ones vector, normalised (deterministic; the paper draws u0 at random).
  Vec u, Mu, Cu;
  p.products(Vec::Ones(n), Mu, Cu);
  u = Mu / Mu.norm();
  p.products(u, Mu, Cu);

  // The smallest penalty that makes an active constraint bind: d = min over I of (Mu)_i / (C̄u)_i, with I the
  // vertices in the support of u that have an inconsistent partner in it.
  // With PenaltyStep::mean, the mean of those ratios instead (the CLIPPER paper's schedule).
  auto penalty_step = [&](const Vec& mu, const Vec& cu, const Vec& x) {
    double step = std::numeric_limits<double>::infinity(), sum = 0.0;
    int active = 0;
    for (int i = 0; i < n; ++i)
      if (cu(i) > o.eps && x(i) > o.eps) {
        const double ratio = std::fabs(mu(i) / cu(i));
        step = std::min(step, ratio);
        sum += ratio;
        ++active;
      }
    if (o.penalty_step == DensestOptions::PenaltyStep::mean && active > 0) return sum / active;
    return step;
  };
  double d = penalty_step(Mu, Cu, u);
  if (!std::isfinite(d)) d = 0.0;
  auto objective = [&](const Vec& x, const Vec& mx, const Vec& cx) { return x.dot(mx) - d * x.dot(cx); };

  double F = objective(u, Mu, Cu);
  int stalled_outer = 0;  // consecutive outer iterations that moved u by less than tol_u
  Vec u_outer;
  for (r.outer_iterations = 0; r.outer_iterations < o.max_outer;) {
    ++r.outer_iterations;
    u_outer = u;
    F = objective(u, Mu, Cu);
    for (int inner = 0; inner < o.max_inner; ++inner) {
      // Gradient of F_d (up to the factor 2), projected onto the tangent of the unit sphere.
      Vec grad = Mu - d * Cu;
      grad -= u.dot(grad) * u;
      const double gnorm = grad.norm();
      if (gnorm < 1e-10) break;
      // First step length (1/β)³/‖g‖, shortened by β until F_d does not decrease. Stopping at the first hit
      // of the orthant's boundary instead (one more zero of u per step) costs about n − |support| steps:
      // measured 10–20× slower at n = 2000 with the same selections (bench_clique, BM_PlantedDensest).
      double alpha = std::pow(1.0 / o.beta, 3) / gnorm;
      Vec un, Mun, Cun;
      double Fn = -std::numeric_limits<double>::infinity();
      bool accepted = false;
      for (int tries = 0; tries < 99; ++tries, alpha *= o.beta) {
        un = (u + alpha * grad).cwiseMax(0.0);
        const double norm = un.norm();
        if (!(norm > 0.0)) continue;
        un /= norm;
        p.products(un, Mun, Cun);
        Fn = objective(un, Mun, Cun);
        if (Fn >= F - o.eps) {
          accepted = true;
          break;
        }
      }
      ++r.inner_iterations;
      if (!accepted) break;  // no ascent step: a local maximum at this d
      const bool small = (un - u).norm() < o.tol_u || std::fabs(Fn - F) < o.tol_f;
      u = std::move(un), Mu = std::move(Mun), Cu = std::move(Cun), F = Fn;
      if (small) break;
    }
    const double step = penalty_step(Mu, Cu, u);
    if (!std::isfinite(step)) {  // no inconsistent pair left in the support
      r.converged = true;
      break;
    }
    stalled_outer = (u - u_outer).norm() < o.tol_u ? stalled_outer + 1 : 0;
    if (o.max_stalled_outer > 0 && stalled_outer >= o.max_stalled_outer) {
      r.stalled = true;
      break;
    }
    d += step;
  }
  r.sparse = p.sparse;
  r.penalty = d;
  r.objective = objective(u, Mu, Cu);
  round_and_repair(g, u, r.objective, o.eps, r);
  r.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace

DensestResult densest_subgraph(const ConsistencyGraph& g, const DensestOptions& options) {
  options.validate();
  Problem p = adjacency(g, use_sparse(g, options.storage));
  p.binary = true;
  return solve(g, p, options);
}

DensestResult densest_subgraph(const ConsistencyGraph& g, const std::vector<double>& affinity,
                               const DensestOptions& options) {
  const int n = g.size();
  const auto nn = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  if (affinity.size() != nn)
    throw std::invalid_argument(
        fmt::format("densest_subgraph: affinity has {} entries, expected n² = {}", affinity.size(), nn));
  options.validate();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      const double a = affinity[static_cast<std::size_t>(i) * n + j];
      const double b = affinity[static_cast<std::size_t>(j) * n + i];
      if (!std::isfinite(a) || a < 0.0 || a > 1.0)
        throw std::invalid_argument(
            fmt::format("densest_subgraph: affinity({}, {}) = {:g} is not in [0, 1]", i, j, a));
      if (a != b)
        throw std::invalid_argument(
            fmt::format("densest_subgraph: affinity is not symmetric: ({}, {}) = {:g}, ({}, {}) = {:g}", i, j,
                        a, j, i, b));
    }
  Problem p = adjacency(g, use_sparse(g, options.storage));
  p.binary = false;
  if (p.sparse) {
    p.weight.resize(p.next.size());
    for (int i = 0; i < n; ++i)
      for (int k = p.start[i]; k < p.start[i + 1]; ++k)
        p.weight[k] = affinity[static_cast<std::size_t>(i) * n + p.next[k]];
  } else {
    p.M = Mat::Identity(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (i != j && p.A(i, j) != 0.0) p.M(i, j) = affinity[static_cast<std::size_t>(i) * n + j];
  }
  return solve(g, p, options);
}

}  // namespace keel::pcm
