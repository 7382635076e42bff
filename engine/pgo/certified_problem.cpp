// keel::pgo::certified — the problem data of the isotropic model and the manifold of the Burer–Monteiro lift:
// M by edges, F and its gradient, the tangent bases and the retraction (certified_internal.hpp).
#include "pgo/certified_internal.hpp"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/blas.hpp"
#include "core/timing.hpp"
#include "linalg/double_double.hpp"
#include "linalg/psd_proof.hpp"
#include "linalg/sparse_cholesky.hpp"

namespace keel::pgo::certified {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(fmt::format("pgo: {}", what)); }

std::string edge_name(const std::string& source, int index, int line) {
  std::string s = fmt::format("edge {}", index);
  if (line > 0) s += fmt::format(" (line {})", line);
  if (!source.empty()) s += fmt::format(" of '{}'", source);
  return s;
}

template <class Edge>
void check_weights(const IsotropicWeights& w, const Edge& e) {
  if (!(std::isfinite(w.kappa) && w.kappa > 0.0 && std::isfinite(w.tau) && w.tau > 0.0))
    fail(fmt::format(
        "isotropic weights of the edge ({}, {}){} are not positive and finite (κ = {}, τ = {}): the "
        "information's rotation or translation block has a non-positive inverse trace",
        e.i, e.j, e.line > 0 ? fmt::format(" on line {}", e.line) : std::string(), w.kappa, w.tau));
}

template <class Graph>
Problem make_problem(const Graph& g, int d) {
  Problem P;
  P.d = d;
  P.source = g.source;
  int n = static_cast<int>(g.poses.size());
  for (const auto& e : g.edges) n = std::max({n, e.i + 1, e.j + 1});
  P.n = n;
  if (n < 2)
    fail(fmt::format("solve_certified: the graph{} has fewer than two poses",
                     g.source.empty() ? "" : " '" + g.source + "'"));
  P.edges.reserve(g.edges.size());
  std::vector<int> degree(static_cast<std::size_t>(n), 0);
  for (std::size_t k = 0; k < g.edges.size(); ++k) {
    const auto& e = g.edges[k];
    if (e.i < 0 || e.j < 0 || e.i == e.j)
      fail(fmt::format("solve_certified: {} joins poses {} and {}",
                       edge_name(g.source, static_cast<int>(k), e.line), e.i, e.j));
    const IsotropicWeights w = isotropic_weights(e);
    check_weights(w, e);
    EdgeData x;
    x.i = e.i;
    x.j = e.j;
    x.R = e.measurement.rotation();
    x.t = e.measurement.translation();
    x.kappa = w.kappa;
    x.tau = w.tau;
    P.edges.push_back(std::move(x));
    ++degree[static_cast<std::size_t>(e.i)];
    ++degree[static_cast<std::size_t>(e.j)];
  }
  P.max_degree = *std::max_element(degree.begin(), degree.end());
  // Connected: every pose reachable from pose 0 (the gauge).
  std::vector<std::vector<int>> adj(static_cast<std::size_t>(n));
  for (const auto& e : P.edges) {
    adj[static_cast<std::size_t>(e.i)].push_back(e.j);
    adj[static_cast<std::size_t>(e.j)].push_back(e.i);
  }
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  std::vector<int> stack = {0};
  seen[0] = 1;
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    for (int w : adj[static_cast<std::size_t>(v)])
      if (!seen[static_cast<std::size_t>(w)]) {
        seen[static_cast<std::size_t>(w)] = 1;
        stack.push_back(w);
      }
  }
  for (int v = 0; v < n; ++v)
    if (!seen[static_cast<std::size_t>(v)])
      fail(fmt::format(
          "solve_certified: pose {} of {} is not connected to pose 0 (the certified solve needs a "
          "connected graph)",
          v, g.source.empty() ? std::string("the graph") : "'" + g.source + "'"));
  return P;
}

std::vector<std::pair<int, int>> free_pairs(const Problem& P) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(P.edges.size());
  for (const auto& e : P.edges) pairs.emplace_back(e.i - 1, e.j - 1);
  return pairs;
}

double cost(const Problem& P, const Point& X) {
  double f = 0.0;
  const int d = P.d;
  for (const auto& e : P.edges) {
    const auto Yi = X.Y(e.i, d);
    const auto Yj = X.Y(e.j, d);
    const Small ER = Yj - Yi * e.R;
    const SmallVec et = X.T.col(e.j) - X.T.col(e.i) - Yi * e.t;
    f += e.kappa * ER.squaredNorm() + e.tau * et.squaredNorm();
  }
  return f;
}

Gradient gradient(const Problem& P, const Point& X) {
  const int d = P.d, r = X.r;
  Gradient G;
  G.GY.assign(static_cast<std::size_t>(P.n), Small::Zero(r, d));
  G.GT = Eigen::MatrixXd::Zero(r, P.n);
  for (const auto& e : P.edges) {
    const auto Yi = X.Y(e.i, d);
    const auto Yj = X.Y(e.j, d);
    const Small ER = Yj - Yi * e.R;
    const SmallVec et = X.T.col(e.j) - X.T.col(e.i) - Yi * e.t;
    G.GY[static_cast<std::size_t>(e.j)] += 2.0 * e.kappa * ER;
    G.GY[static_cast<std::size_t>(e.i)] -=
        2.0 * e.kappa * ER * e.R.transpose() + 2.0 * e.tau * et * e.t.transpose();
    G.GT.col(e.j) += 2.0 * e.tau * et;
    G.GT.col(e.i) -= 2.0 * e.tau * et;
  }
  return G;
}

std::vector<std::pair<int, int>> generators(int r, int d) {
  std::vector<std::pair<int, int>> g;
  for (int a = 0; a < d; ++a)
    for (int b = a + 1; b < r; ++b) g.emplace_back(a, b);
  return g;
}

Small tangent_basis(const Small& Q, int d, int a, int b) {
  Small D = Small::Zero(Q.rows(), d);
  D.col(a) = -Q.col(b);
  if (b < d) D.col(b) = Q.col(a);
  return D;
}

// ⟨W, e_x e_yᵀ E⟩ = W(x, y) when y < d.
double pick(const Small& W, int d, int x, int y) { return y < d ? W(x, y) : 0.0; }

double curvature_term(const Small& W, int d, std::pair<int, int> k, std::pair<int, int> l) {
  const auto [a, b] = k;
  const auto [a2, b2] = l;
  double s = 0.0;
  if (b == a2) s += pick(W, d, a, b2);
  if (b == b2) s -= pick(W, d, a, a2);
  if (a == a2) s -= pick(W, d, b, b2);
  if (a == b2) s += pick(W, d, b, a2);
  return s;
}

Small retract(const Small& Q, const Small& B) {
  const int r = static_cast<int>(Q.rows());
  const Small I = Small::Identity(r, r);
  const Small C = (I - 0.5 * B).partialPivLu().solve(I + 0.5 * B);
  return Q * C;
}

double riemannian_gradient_norm(const Problem& P, const Point& X,
                                const std::vector<std::pair<int, int>>& gens) {
  const Gradient G = gradient(P, X);
  double s = G.GT.rightCols(P.n - 1).squaredNorm();
  for (int v = 1; v < P.n; ++v)
    for (const auto& [a, b] : gens) {
      const double gk = G.GY[static_cast<std::size_t>(v)]
                            .cwiseProduct(tangent_basis(X.Q[static_cast<std::size_t>(v)], P.d, a, b))
                            .sum();
      s += gk * gk;
    }
  return std::sqrt(s);
}

template Problem make_problem(const graph::PoseGraph2D& g, int d);
template Problem make_problem(const graph::PoseGraph3D& g, int d);

}  // namespace keel::pgo::certified
