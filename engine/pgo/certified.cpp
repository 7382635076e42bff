// Certified pose-graph optimization (certified.hpp): the isotropic problem, chordal initialization, the
// local solves on the Burer–Monteiro lift (Newton at rank d, a matrix-free trust region above), the
// certificate with its rounding margin, the staircase and the rounding back to SO(d).
//
// Conventions. X = [t_1 … t_n | Y_1 … Y_n] ∈ R^{r×(n+dn)}; F(X) = tr(X M Xᵀ). Per edge e = (i, j) with data
// (R̃, t̃, κ, τ) M collects (blocks indexed by the columns of X; only the upper triangle is stored)
//   M[t_i,t_i] += τ,  M[t_j,t_j] += τ,  M[t_i,t_j] −= τ,
//   M[Y_i,Y_i] += κ R̃R̃ᵀ + τ t̃t̃ᵀ,  M[Y_j,Y_j] += κ I,  M[Y_i,Y_j] −= κ R̃,
//   M[Y_i,t_i] += τ t̃,  M[Y_i,t_j] −= τ t̃,
// so that tr(X M Xᵀ) = Σ κ‖Y_j − Y_i R̃‖² + τ‖t_j − t_i − Y_i t̃‖² (R̃R̃ᵀ rather than I keeps M exact for
// rotations stored to rounding). The Euclidean gradient is ∇F = 2 X M.
#include "pgo/certified.hpp"

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
#include "pgo/double_double.hpp"
#include "pgo/psd_proof.hpp"
#include "pgo/sparse_cholesky.hpp"

namespace keel::pgo {

namespace {

constexpr int kMaxRank = 12;
using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxRank, kMaxRank>;
using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxRank, 1>;
constexpr int kMaxTangent = kMaxRank * 3 + kMaxRank;  // p_rot ≤ r·d with d ≤ 3, plus r translations
using Block =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 2 * kMaxTangent, 2 * kMaxTangent>;
constexpr double kUnitRoundoff = std::numeric_limits<double>::epsilon() / 2;  // u = 2⁻⁵³

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(fmt::format("pgo: {}", what)); }

struct EdgeData {
  int i = 0, j = 0;
  Small R;     // R̃ (d × d)
  SmallVec t;  // t̃ (d)
  double kappa = 0.0, tau = 0.0;
};

struct Problem {
  int d = 2;
  int n = 0;
  std::vector<EdgeData> edges;
  int max_degree = 0;
  std::string source;
};

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

// ---------------------------------------------------------------------------------------------------------------
// A block-sparse symmetric pattern (upper triangle, compressed columns) over blocks of given sizes; the
// blocks adjacent in the graph carry an off-diagonal block. Block −1 means "not a variable" (the gauge).
class BlockPattern {
 public:
  BlockPattern(std::vector<int> sizes, const std::vector<std::pair<int, int>>& pairs)
      : size_(std::move(sizes)) {
    const int nb = static_cast<int>(size_.size());
    offset_.assign(static_cast<std::size_t>(nb) + 1, 0);
    for (int b = 0; b < nb; ++b)
      offset_[static_cast<std::size_t>(b) + 1] =
          offset_[static_cast<std::size_t>(b)] + size_[static_cast<std::size_t>(b)];
    rows_.assign(static_cast<std::size_t>(nb), {});
    for (const auto& [a, b] : pairs) {
      if (a < 0 || b < 0 || a == b) continue;
      rows_[static_cast<std::size_t>(std::max(a, b))].push_back(std::min(a, b));
    }
    for (int b = 0; b < nb; ++b) {
      auto& r = rows_[static_cast<std::size_t>(b)];
      std::sort(r.begin(), r.end());
      r.erase(std::unique(r.begin(), r.end()), r.end());
      r.push_back(b);
    }
    start_.assign(static_cast<std::size_t>(nb), {});
    const int N = offset_.back();
    col_start_.assign(static_cast<std::size_t>(N) + 1, 0);
    for (int b = 0; b < nb; ++b) {
      const auto& r = rows_[static_cast<std::size_t>(b)];
      auto& st = start_[static_cast<std::size_t>(b)];
      st.resize(r.size());
      int acc = 0;
      for (std::size_t q = 0; q < r.size(); ++q) {
        st[q] = acc;
        acc += size_[static_cast<std::size_t>(r[q])];
      }
      const int off_rows = acc - size_[static_cast<std::size_t>(b)];
      for (int cc = 0; cc < size_[static_cast<std::size_t>(b)]; ++cc) {
        const int c = offset_[static_cast<std::size_t>(b)] + cc;
        col_start_[static_cast<std::size_t>(c) + 1] =
            col_start_[static_cast<std::size_t>(c)] + off_rows + cc + 1;
      }
    }
    row_index_.resize(static_cast<std::size_t>(col_start_.back()));
    for (int b = 0; b < nb; ++b) {
      const auto& r = rows_[static_cast<std::size_t>(b)];
      for (int cc = 0; cc < size_[static_cast<std::size_t>(b)]; ++cc) {
        int q = col_start_[static_cast<std::size_t>(offset_[static_cast<std::size_t>(b)] + cc)];
        for (const int a : r) {
          const int len = a == b ? cc + 1 : size_[static_cast<std::size_t>(a)];
          for (int ri = 0; ri < len; ++ri)
            row_index_[static_cast<std::size_t>(q++)] = offset_[static_cast<std::size_t>(a)] + ri;
        }
      }
    }
  }
  [[nodiscard]] int dimension() const { return offset_.back(); }
  [[nodiscard]] int offset(int b) const { return offset_[static_cast<std::size_t>(b)]; }
  [[nodiscard]] int block_size(int b) const { return size_[static_cast<std::size_t>(b)]; }
  // Position of block row a in block column b ≥ a.
  [[nodiscard]] int position(int a, int b) const {
    const auto& r = rows_[static_cast<std::size_t>(b)];
    return static_cast<int>(std::lower_bound(r.begin(), r.end(), a) - r.begin());
  }
  // Index into the values of entry (row ri of block a, column cc of block b), a ≤ b, a at `pos` in column b;
  // for a = b only ri ≤ cc.
  [[nodiscard]] int index(int pos, int b, int ri, int cc) const {
    return col_start_[static_cast<std::size_t>(offset_[static_cast<std::size_t>(b)] + cc)] +
           start_[static_cast<std::size_t>(b)][static_cast<std::size_t>(pos)] + ri;
  }
  [[nodiscard]] const std::vector<int>& block_rows(int b) const { return rows_[static_cast<std::size_t>(b)]; }
  [[nodiscard]] int diagonal_position(int b) const {
    return static_cast<int>(rows_[static_cast<std::size_t>(b)].size()) - 1;
  }
  const std::vector<int>& col_start() const { return col_start_; }
  const std::vector<int>& row_index() const { return row_index_; }

  // values += the block H (size_a × size_b) at (a, b) (a ≠ b; the transpose goes in when a > b).
  template <class Mat>
  void add_off_diagonal(std::vector<double>& values, int a, int b, int pos, const Mat& H) const {
    if (a < b) {
      for (int cc = 0; cc < block_size(b); ++cc)
        for (int ri = 0; ri < block_size(a); ++ri)
          values[static_cast<std::size_t>(index(pos, b, ri, cc))] += H(ri, cc);
    } else {
      for (int cc = 0; cc < block_size(a); ++cc)
        for (int ri = 0; ri < block_size(b); ++ri)
          values[static_cast<std::size_t>(index(pos, a, ri, cc))] += H(cc, ri);
    }
  }
  template <class Mat>
  void add_diagonal(std::vector<double>& values, int b, const Mat& H) const {
    const int pos = diagonal_position(b);
    for (int cc = 0; cc < block_size(b); ++cc)
      for (int ri = 0; ri <= cc; ++ri) values[static_cast<std::size_t>(index(pos, b, ri, cc))] += H(ri, cc);
  }

 private:
  std::vector<int> size_, offset_;
  std::vector<std::vector<int>> rows_;   // per block column: the block rows (sorted, itself last)
  std::vector<std::vector<int>> start_;  // per block column: the first local row of each block row
  std::vector<int> col_start_, row_index_;
};

// Pose v ≥ 1 is block v − 1 (pose 0 is the gauge).
std::vector<std::pair<int, int>> free_pairs(const Problem& P) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(P.edges.size());
  for (const auto& e : P.edges) pairs.emplace_back(e.i - 1, e.j - 1);
  return pairs;
}

// ---------------------------------------------------------------------------------------------------------------
// The point on the lift: Q_i ∈ O(r) (Y_i = first d columns), translations T (r × n).
struct Point {
  int r = 0;
  std::vector<Small> Q;
  Eigen::MatrixXd T;
  [[nodiscard]] auto Y(int i, int d) const { return Q[static_cast<std::size_t>(i)].leftCols(d); }
};

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

// ∇F = 2 X M: per pose the r × d block of Y_i and the r-vector of t_i.
struct Gradient {
  std::vector<Small> GY;
  Eigen::MatrixXd GT;
};

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

// The generators of the part of so(r) that moves the first d columns: G = e_a e_bᵀ − e_b e_aᵀ, a < d, a < b <
// r.
std::vector<std::pair<int, int>> generators(int r, int d) {
  std::vector<std::pair<int, int>> g;
  for (int a = 0; a < d; ++a)
    for (int b = a + 1; b < r; ++b) g.emplace_back(a, b);
  return g;
}

// D_k = Q G_k E (r × d): column a is −q_b, column b (when b < d) is +q_a.
Small tangent_basis(const Small& Q, int d, int a, int b) {
  Small D = Small::Zero(Q.rows(), d);
  D.col(a) = -Q.col(b);
  if (b < d) D.col(b) = Q.col(a);
  return D;
}

// ⟨W, e_x e_yᵀ E⟩ = W(x, y) when y < d.
double pick(const Small& W, int d, int x, int y) { return y < d ? W(x, y) : 0.0; }

// ⟨W, G_k G_l E⟩ for generators k = (a, b), l = (a', b'):
// G_k G_l = δ_{b a'} e_a e_b'ᵀ − δ_{b b'} e_a e_a'ᵀ − δ_{a a'} e_b e_b'ᵀ + δ_{a b'} e_b e_a'ᵀ.
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

// Q exp(B) by the Cayley transform Q (I − B/2)⁻¹ (I + B/2) (orthogonal, and equal to exp(B) to second order,
// so the curvature term of the Newton model is the one of this retraction).
Small retract(const Small& Q, const Small& B) {
  const int r = static_cast<int>(Q.rows());
  const Small I = Small::Identity(r, r);
  const Small C = (I - 0.5 * B).partialPivLu().solve(I + 0.5 * B);
  return Q * C;
}

// ‖grad F‖ in the tangent coordinates of the local solve (pose 0 held): the translation gradient and the
// components of the Y-gradient along the generators.
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

// CertifiedOptions::time_limit_s from the start of the solve (none: never passed).
struct Deadline {
  core::Clock::time_point start;
  double limit_s = 0.0;
  [[nodiscard]] bool passed() const { return limit_s > 0.0 && core::seconds_since(start) >= limit_s; }
};

struct LocalOutcome {
  int iterations = 0;
  int factorizations = 0;  // numeric factorizations (successful or not)
  int cg_steps = 0;        // steps solved by conjugate gradients on an earlier factor instead
  int tcg_iterations = 0;  // Steihaug–Toint iterations of the trust-region steps (indefinite Hessian)
  bool timed_out = false;  // stopped at the deadline
  double cost = 0.0;
  double gradient_norm = 0.0;
  std::string ordering;
  // The solve's counts into the summary's totals over all ranks.
  void add_to(CertifiedSummary& S) const {
    S.iterations += iterations;
    S.factorizations += factorizations;
    S.cg_steps += cg_steps;
    S.tcg_iterations += tcg_iterations;
  }
};

// The Gauss–Newton part of the Newton system, JᵀJ summed over the edges into `hessian` (pattern's values),
// with J of an edge: rows vec(δ(Y_j − Y_i R̃)) (r·d) then δ(t_j − t_i − Y_i t̃) (r); columns [b_i, t_i, b_j,
// t_j] (the tangent coordinates of both poses, p = prot + r each). D_ holds the tangent basis of every pose.
// For compile-time D and R the matrices have fixed sizes and JᵀJ is a coefficient-wise product (Eigen would
// call its GEMM, with packing, for 12 × 12 · 12 × 12); Eigen::Dynamic takes d and r at run time.
template <int Dc, int Rc>
void gauss_newton_blocks(const Problem& P, const std::vector<Small>& D_, int prot, int p,
                         const BlockPattern& pattern, const std::vector<int>& pos,
                         std::vector<double>& hessian, int d = Dc, int r = Rc) {
  constexpr bool kFixed = Dc != Eigen::Dynamic && Rc != Eigen::Dynamic;
  constexpr int kP = kFixed ? Dc * Rc - Dc * (Dc + 1) / 2 + Rc : Eigen::Dynamic;
  constexpr int kRows = kFixed ? Dc * Rc + Rc : Eigen::Dynamic, kCols = kFixed ? 2 * kP : Eigen::Dynamic;
  using Jac = std::conditional_t<kFixed, Eigen::Matrix<double, kRows, kCols>, Block>;
  using Hes = std::conditional_t<kFixed, Eigen::Matrix<double, kCols, kCols>, Block>;
  using Basis = std::conditional_t<kFixed, Eigen::Matrix<double, Rc, Dc>, Small>;
  using Rot = std::conditional_t<kFixed, Eigen::Matrix<double, Dc, Dc>, Small>;
  using Vec = std::conditional_t<kFixed, Eigen::Matrix<double, Dc, 1>, SmallVec>;
  Jac J(d * r + r, 2 * p);
  Hes H(2 * p, 2 * p);
  for (std::size_t k = 0; k < P.edges.size(); ++k) {
    const auto& e = P.edges[k];
    const double sk = std::sqrt(2.0 * e.kappa), st = std::sqrt(2.0 * e.tau);
    const Rot R = e.R;
    const Vec t = e.t;
    J.setZero();
    for (int q = 0; q < prot; ++q) {
      const Basis Di = D_[static_cast<std::size_t>(e.i) * prot + q];
      const Basis Dj = D_[static_cast<std::size_t>(e.j) * prot + q];
      const Basis DiR = Di * R;
      for (int c = 0; c < d; ++c) {
        J.block(c * r, q, r, 1) = -sk * DiR.col(c);
        J.block(c * r, p + q, r, 1) = sk * Dj.col(c);
      }
      J.block(d * r, q, r, 1) = -st * (Di * t);
    }
    for (int c = 0; c < r; ++c) {
      J(d * r + c, prot + c) = -st;
      J(d * r + c, p + prot + c) = st;
    }
    if constexpr (kFixed)
      H.noalias() = J.transpose().lazyProduct(J);
    else
      H = J.transpose() * J;
    const int a = e.i - 1, b = e.j - 1;
    if (a >= 0) pattern.add_diagonal(hessian, a, H.topLeftCorner(p, p));
    if (b >= 0) pattern.add_diagonal(hessian, b, H.bottomRightCorner(p, p));
    if (a >= 0 && b >= 0) pattern.add_off_diagonal(hessian, a, b, pos[k], H.topRightCorner(p, p));
  }
}

// y = A x for the symmetric matrix whose upper triangle `values` holds in the compressed columns (cs, ri).
void symmetric_product(const std::vector<int>& cs, const std::vector<int>& ri,
                       const std::vector<double>& values, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  y.setZero(x.size());
  for (int c = 0; c + 1 < static_cast<int>(cs.size()); ++c) {
    double acc = 0.0;
    const double xc = x(c);
    for (int q = cs[static_cast<std::size_t>(c)]; q < cs[static_cast<std::size_t>(c) + 1]; ++q) {
      const int r = ri[static_cast<std::size_t>(q)];
      const double v = values[static_cast<std::size_t>(q)];
      if (r == c) {
        acc += v * xc;
      } else {
        y(r) += v * xc;
        acc += v * x(r);
      }
    }
    y(c) += acc;
  }
}

// The inexact Newton steps' conjugate gradients (preconditioned_cg, after steihaug_cg below). The limits: one
// CG iteration (two triangular solves with the factor and a product with A) costs 1/10 to 1/23 of a numeric
// factorization on the SE-Sync benchmark graphs (measured on this machine kind: sphere2500 2 ms against 25–35
// ms, torus3D 6 against 65–84, manhattan 0.25 against 5.9, kitti_00 0.25 against 2.6; CHOLMOD's flop counts
// predict that ratio poorly, 1.3 … 93, since the factorization runs dense kernels and the solves are bound by
// memory). So CG gives up after 10 iterations, and the step after one whose CG needed more than 5 factorizes
// instead: the preconditioner has drifted too far from the Hessian.
constexpr int kMaxCg = 10;
constexpr int kRefreshAfterCg = 5;

// The certificate matrix is formed in double-double (double_double.hpp): the entries' own rounding then stays
// below a few u² of their terms instead of γ_m of them, and the proof's residual is taken against the entries
// as formed (psd_proof.hpp).
using detail::DD;
using detail::dd_add;
using detail::dd_prod;
using detail::dd_scale;

// M's entries of one edge as blocks in the local coordinates of pose blocks (pose 0 has no translation
// column), in double-double. Returns through `add(a, b, row, col, value, magnitude)` with a, b the poses,
// row/col local indices (translation 0 when present, rotation c at 1 + c; for pose 0 rotation c at c) and
// `magnitude` ≥ the sum of the magnitudes of the products the value is formed from, rounded up: the error of
// forming a value scales with it, not with the value (the off-diagonal entries of R̃R̃ᵀ cancel to ~u while
// their products are of order one).
template <class Add>
void edge_entries(const EdgeData& e, int d, Add&& add) {
  using core::round_up;
  const int ti = e.i == 0 ? -1 : 0, tj = e.j == 0 ? -1 : 0;
  const int ri = e.i == 0 ? 0 : 1, rj = e.j == 0 ? 0 : 1;
  if (ti >= 0) add(e.i, e.i, ti, ti, DD{e.tau, 0.0}, e.tau);
  if (tj >= 0) add(e.j, e.j, tj, tj, DD{e.tau, 0.0}, e.tau);
  if (ti >= 0 && tj >= 0) add(e.i, e.j, ti, tj, DD{-e.tau, 0.0}, e.tau);
  for (int c = 0; c < d; ++c) {
    for (int c2 = 0; c2 < d; ++c2) {
      DD rr;              // (R̃ R̃ᵀ)_{c c2}, of the stored R̃ (orthonormal only to rounding)
      double rr_abs = 0;  // Σ_m |R̃_{cm} R̃_{c2 m}|, rounded up
      for (int m = 0; m < d; ++m) {
        rr = dd_add(rr, dd_prod(e.R(c, m), e.R(c2, m)));
        rr_abs = round_up(rr_abs + round_up(std::abs(e.R(c, m) * e.R(c2, m))));
      }
      const double magnitude =
          round_up(round_up(e.kappa * rr_abs) + round_up(e.tau * round_up(std::abs(e.t(c) * e.t(c2)))));
      add(e.i, e.i, ri + c, ri + c2, dd_add(dd_scale(rr, e.kappa), dd_scale(dd_prod(e.t(c), e.t(c2)), e.tau)),
          magnitude);
      if (c == c2) add(e.j, e.j, rj + c, rj + c2, DD{e.kappa, 0.0}, e.kappa);
      add(e.i, e.j, ri + c, rj + c2, dd_prod(-e.kappa, e.R(c, c2)), round_up(std::abs(e.kappa * e.R(c, c2))));
    }
    // Translation first: the upper triangle.
    if (ti >= 0) add(e.i, e.i, ti, ri + c, dd_prod(e.tau, e.t(c)), round_up(std::abs(e.tau * e.t(c))));
    if (tj >= 0) add(e.i, e.j, ri + c, tj, dd_prod(-e.tau, e.t(c)), round_up(std::abs(e.tau * e.t(c))));
  }
}

// The preconditioner of the trust-region steps (SE-Sync's, Rosen et al. 2019 §5.2, in the tangent
// coordinates of the local solve): F = Σ_a x_aᵀ M x_a over the r rows x_a of [t_v, Y_v]_v, so its Euclidean
// Hessian is 2 M ⊗ I_r whatever the point and the rank. M₀ (M without pose 0, which the local solve holds;
// positive definite for a connected graph) is factorized once per solve. A tangent vector with coordinates c
// is ξ = E c (E: each pose's basis matrices D_k and the identity on its translation; EᵀE = G diagonal, 2 or
// 1), and the preconditioner is c ↦ G⁻¹ Eᵀ (2 M₀ ⊗ I_r)⁻¹ E G⁻¹ c, symmetric positive definite: the
// projection of M₀⁻¹ applied to the vector the coordinates stand for.
class DataPreconditioner {
 public:
  explicit DataPreconditioner(const Problem& P) : d_(P.d), n_(P.n) {
    const int w = d_ + 1, N0 = (n_ - 1) * w;
    // The upper triangle of 2M₀ in compressed columns, from the certificate's own edge entries (edge_entries
    // writes the rotation blocks of a pose in both orders and the other entries once, in either triangle).
    struct Entry {
      int row, col;
      double value;
    };
    std::vector<Entry> upper;
    for (int c = 0; c < N0; ++c) upper.push_back({c, c, 0.0});  // every diagonal present
    for (const auto& e : P.edges) {
      edge_entries(e, d_, [&](int a, int b, int row, int col, DD value, double) {
        if (a == 0 || b == 0) return;  // pose 0 is held
        const int gr = (a - 1) * w + row, gc = (b - 1) * w + col;
        if (a == b && row != 0 && col != 0 && gr > gc) return;  // the other order of a rotation block
        upper.push_back({std::min(gr, gc), std::max(gr, gc), 2.0 * (value.hi + value.lo)});
      });
    }
    std::sort(upper.begin(), upper.end(),
              [](const Entry& x, const Entry& y) { return x.col != y.col ? x.col < y.col : x.row < y.row; });
    std::vector<int> cs(static_cast<std::size_t>(N0) + 1, 0), ri;
    std::vector<double> values;
    for (std::size_t k = 0; k < upper.size(); ++k) {
      if (k > 0 && upper[k].row == upper[k - 1].row && upper[k].col == upper[k - 1].col) {
        values.back() += upper[k].value;
        continue;
      }
      ri.push_back(upper[k].row);
      values.push_back(upper[k].value);
      ++cs[static_cast<std::size_t>(upper[k].col) + 1];
    }
    for (int c = 0; c < N0; ++c) cs[static_cast<std::size_t>(c) + 1] += cs[static_cast<std::size_t>(c)];
    chol_ = std::make_unique<detail::SparseCholesky>(N0, cs, ri, detail::FillOrdering::automatic, false);
    chol_->values() = values;
    cs_ = std::move(cs);
    ri_ = std::move(ri);
    m0_ = std::move(values);
    ok_ = chol_->factorize();
  }
  [[nodiscard]] bool ok() const { return ok_; }

  // z = G⁻¹ Eᵀ (2 M₀ ⊗ I_r)⁻¹ E G⁻¹ c at the point whose poses' rotation parts are Q (r × r each).
  void apply(const std::vector<Small>& Q, const std::vector<std::pair<int, int>>& gens, int r,
             const Eigen::VectorXd& c, Eigen::VectorXd& z) const {
    embed(Q, gens, r, c, true, B_);
    Z_.resize(B_.rows(), r);
    chol_->solve(B_.data(), Z_.data(), r);
    project(Q, gens, r, Z_, true, z);
  }

  // y = Eᵀ (2 M₀ ⊗ I_r) E c: the Euclidean Hessian of F in the tangent coordinates (the Gauss–Newton part of
  // the Riemannian Hessian, without forming it: O(r) per edge where the assembled blocks cost O(r²)).
  void euclidean_hessian(const std::vector<Small>& Q, const std::vector<std::pair<int, int>>& gens, int r,
                         const Eigen::VectorXd& c, Eigen::VectorXd& y) const {
    embed(Q, gens, r, c, false, B_);
    Z_.resize(B_.rows(), r);
    Eigen::VectorXd col_out;
    for (int a = 0; a < r; ++a) {
      const Eigen::VectorXd col = B_.col(a);
      symmetric_product(cs_, ri_, m0_, col, col_out);
      Z_.col(a) = col_out;
    }
    project(Q, gens, r, Z_, false, y);
  }

 private:
  // The basis matrix of generator k = (a, b) at Q is D_k = [Q (E_ab − E_ba)] restricted to the first d
  // columns (tangent_basis), so Σ_k c_k D_k = Q Ω(c)[:, :d] with Ω(c) the skew matrix of the coefficients,
  // and ⟨Z, D_k⟩ = (QᵀZ)(a, b)·[b < d] − (QᵀZ)(b, a); G_k = ‖D_k‖² is 2 when b < d, else 1.
  //
  // B = E G⁻¹ c (scaled) or E c, as the N₀ × r matrix whose column a is row a of [t_v, Y_v]_{v ≥ 1}.
  void embed(const std::vector<Small>& Q, const std::vector<std::pair<int, int>>& gens, int r,
             const Eigen::VectorXd& c, bool scaled, Eigen::MatrixXd& B) const {
    const int w = d_ + 1, N0 = (n_ - 1) * w, prot = static_cast<int>(gens.size()), p = prot + r;
    B.resize(N0, r);
    Small Omega(r, r), Y(r, d_);
    for (int v = 1; v < n_; ++v) {
      const int o0 = (v - 1) * p, row = (v - 1) * w;
      B.block(row, 0, 1, r) = c.segment(o0 + prot, r).transpose();
      Omega.setZero();
      for (int k = 0; k < prot; ++k) {
        const auto [a, b] = gens[static_cast<std::size_t>(k)];
        const double ck = scaled && b < d_ ? 0.5 * c(o0 + k) : c(o0 + k);
        Omega(a, b) += ck;
        Omega(b, a) -= ck;
      }
      Y.noalias() = Q[static_cast<std::size_t>(v)] * Omega.leftCols(d_);
      B.block(row + 1, 0, d_, r) = Y.transpose();
    }
  }
  // z = (G⁻¹) Eᵀ Z.
  void project(const std::vector<Small>& Q, const std::vector<std::pair<int, int>>& gens, int r,
               const Eigen::MatrixXd& Z, bool scaled, Eigen::VectorXd& z) const {
    const int w = d_ + 1, prot = static_cast<int>(gens.size()), p = prot + r;
    z.resize(static_cast<Eigen::Index>(n_ - 1) * p);
    Small W(r, d_);
    for (int v = 1; v < n_; ++v) {
      const int o0 = (v - 1) * p, row = (v - 1) * w;
      z.segment(o0 + prot, r) = Z.block(row, 0, 1, r).transpose();
      W.noalias() = Q[static_cast<std::size_t>(v)].transpose() * Z.block(row + 1, 0, d_, r).transpose();
      for (int k = 0; k < prot; ++k) {
        const auto [a, b] = gens[static_cast<std::size_t>(k)];
        const double s = (b < d_ ? W(a, b) : 0.0) - W(b, a);
        z(o0 + k) = scaled && b < d_ ? 0.5 * s : s;
      }
    }
  }

  int d_, n_;
  std::unique_ptr<detail::SparseCholesky> chol_;
  std::vector<int> cs_, ri_;  // 2M₀'s upper triangle (compressed columns)
  std::vector<double> m0_;
  bool ok_ = false;
  mutable Eigen::MatrixXd B_, Z_;
};

// Steihaug–Toint truncated conjugate gradients (Conn, Gould & Toint, Trust-Region Methods, Alg. 7.5.1; the
// inner solver of SE-Sync's Riemannian trust region) on the model m(δ) = gᵀδ + ½ δᵀAδ, A the symmetric matrix
// (possibly indefinite), inside the trust region
// ‖δ‖_M ≤ radius of the preconditioner M (positive definite): `product(x, y)` sets y = Ax, `precondition(r,
// z)` sets z = M⁻¹r. From δ = 0 until the residual ‖g + Aδ‖ ≤ eta·‖g‖, or a direction of non-positive
// curvature or the boundary is met: then δ goes to the boundary along the last direction (the model decreases
// along it). The first iterate is the preconditioned steepest-descent step −M⁻¹g, cut to the region. Returns
// why it stopped; δᵀAδ in dAd; the iterations in `used`, ‖δ‖_M in `norm_m`. At most kMaxTcg iterations (each
// a product with A and two triangular solves, 1/10 to 1/23 of a factorization).
constexpr int kMaxTcg = 50;
constexpr int kRefreshAfterTcg = 10;
enum class TcgEnd { converged, boundary, negative_curvature, iteration_limit };
template <class Product, class Precondition>
TcgEnd steihaug_cg(Product&& product, Precondition&& precondition, const Eigen::VectorXd& g, double radius,
                   double eta, int max_iterations, Eigen::VectorXd& delta, double& dAd, double& norm_m,
                   int& used) {
  const Eigen::Index n = g.size();
  delta.setZero(n);
  TcgEnd end = TcgEnd::iteration_limit;
  Eigen::VectorXd r = g, z(n), Ap(n);
  precondition(r, z);
  Eigen::VectorXd dir = -z;
  double rz = r.dot(z);
  // M-norm inner products carried by the recurrences (no products with M): ⟨δ,δ⟩_M, ⟨δ,p⟩_M, ⟨p,p⟩_M.
  double dd = 0.0, dp = 0.0, pp = rz;
  const double target = eta * g.norm(), r2 = radius * radius;
  const bool bounded = std::isfinite(radius);
  used = 0;
  for (int k = 0; k < max_iterations && rz > 0.0; ++k) {
    used = k + 1;
    product(dir, Ap);
    const double curvature = dir.dot(Ap);
    const double alpha = rz / curvature;
    const double dd_next = dd + 2.0 * alpha * dp + alpha * alpha * pp;
    if (!bounded && !(curvature > 0.0)) {
      end = TcgEnd::negative_curvature;  // no boundary to go to: δ stays where CG left it
      break;
    }
    if (!(curvature > 0.0) || (bounded && dd_next >= r2)) {
      // τ ≥ 0 with ‖δ + τ p‖_M = radius.
      const double tau = (-dp + std::sqrt(std::max(0.0, dp * dp + pp * (r2 - dd)))) / pp;
      delta += tau * dir;
      dd = r2;
      end = curvature > 0.0 ? TcgEnd::boundary : TcgEnd::negative_curvature;
      break;
    }
    delta += alpha * dir;
    r += alpha * Ap;
    dd = dd_next;
    if (r.norm() <= target) {
      end = TcgEnd::converged;
      break;
    }
    precondition(r, z);
    const double rz_next = r.dot(z);
    const double beta = rz_next / rz;
    dir = -z + beta * dir;
    dp = beta * (dp + alpha * pp);
    pp = rz_next + beta * beta * pp;
    rz = rz_next;
  }
  product(delta, Ap);
  dAd = delta.dot(Ap);
  norm_m = std::sqrt(dd);
  return end;
}

// The stopping rules of a local solve, checked at each new point. Stationarity: |F − tr Λ| and the
// first-order change of F along X are at most ‖grad‖·‖X‖, and the certificate needs them well inside the gap
// tolerance. At the rounding floor of the gradient, steps stop halving it: two new points without that, once
// steps decrease F by less than 1e-10·F, end the solve (the certificate then judges the point). Five cost
// kitti_05 four more steps that moved nothing once its steps were inexact (CG), where a rejected step had
// ended it before.
struct Stopping {
  double first_gradient = 0.0;  // ‖grad‖ at the start (the forcing terms' scale)
  double best_gradient = std::numeric_limits<double>::infinity();
  double last_decrease = std::numeric_limits<double>::infinity();  // F's decrease at the last accepted step
  int stalled = 0;
  [[nodiscard]] bool done(const Problem& P, const Point& X, const CertifiedOptions& o, double gnorm,
                          double f) {
    if (first_gradient == 0.0) first_gradient = std::max(gnorm, std::numeric_limits<double>::min());
    const double xnorm = std::sqrt(X.T.squaredNorm() + static_cast<double>(P.n) * P.d);
    if (gnorm * xnorm <= o.stationarity_tolerance * o.gap_tolerance * std::max(f, 1.0)) return true;
    if (gnorm < 0.5 * best_gradient) {
      best_gradient = gnorm;
      stalled = 0;
      return false;
    }
    return last_decrease <= 1e-10 * std::max(f, 1.0) && ++stalled >= 2;
  }
};

// Conjugate gradients on A δ = −g (A: `values` in chol's pattern), preconditioned by chol's current factor
// (of an earlier matrix), from δ = 0 until ‖g + Aδ‖ ≤ eta·‖g‖: steihaug_cg without a trust region. False when
// A shows non-positive curvature along a search direction or kMaxCg iterations do not suffice; otherwise δ
// and dAd = δᵀAδ. `used`: the iterations spent either way.
bool preconditioned_cg(const detail::SparseCholesky& chol, const std::vector<double>& values,
                       const Eigen::VectorXd& g, double eta, Eigen::VectorXd& delta, double& dAd, int& used) {
  double norm_m = 0.0;
  const TcgEnd end = steihaug_cg(
      [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
        symmetric_product(chol.col_start(), chol.row_index(), values, x, y);
      },
      [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) { chol.solve(r.data(), z.data(), 1); }, g,
      std::numeric_limits<double>::infinity(), eta, kMaxCg, delta, dAd, norm_m, used);
  return end == TcgEnd::converged && dAd > 0.0;
}

// The tangent model at X (pose 0 held): each pose's basis matrices D (pose v's basis k at D[v·prot + k]), the
// gradient g in those coordinates (pose v ≥ 1 at (v − 1)·p: rotation coordinates, then translation), and the
// symmetric curvature blocks (prot × prot per pose v ≥ 1) that the Riemannian Hessian adds to the Euclidean
// Hessian's compression on the rotation coordinates.
void tangent_model(const Problem& P, const Point& X, const std::vector<std::pair<int, int>>& gens,
                   std::vector<Small>& D, Eigen::VectorXd& g, std::vector<double>& curvature) {
  const int d = P.d, r = X.r, prot = static_cast<int>(gens.size()), p = prot + r;
  for (int v = 0; v < P.n; ++v)
    for (int k = 0; k < prot; ++k)
      D[static_cast<std::size_t>(v) * prot + k] =
          tangent_basis(X.Q[static_cast<std::size_t>(v)], d, gens[static_cast<std::size_t>(k)].first,
                        gens[static_cast<std::size_t>(k)].second);
  const Gradient G = gradient(P, X);
  for (int v = 1; v < P.n; ++v) {
    const int o0 = (v - 1) * p;
    for (int k = 0; k < prot; ++k)
      g(o0 + k) =
          G.GY[static_cast<std::size_t>(v)].cwiseProduct(D[static_cast<std::size_t>(v) * prot + k]).sum();
    g.segment(o0 + prot, r) = G.GT.col(v);
    const Small W = X.Q[static_cast<std::size_t>(v)].transpose() * G.GY[static_cast<std::size_t>(v)];
    double* C = &curvature[static_cast<std::size_t>(v - 1) * prot * prot];
    for (int k = 0; k < prot; ++k)
      for (int l = 0; l < prot; ++l)
        C[k * prot + l] =
            0.5 *
            (curvature_term(W, d, gens[static_cast<std::size_t>(k)], gens[static_cast<std::size_t>(l)]) +
             curvature_term(W, d, gens[static_cast<std::size_t>(l)], gens[static_cast<std::size_t>(k)]));
  }
}

// X moved by α·step in the tangent coordinates (pose 0 held), retracted.
Point moved(const Problem& P, const Point& X, const std::vector<std::pair<int, int>>& gens,
            const Eigen::VectorXd& step, double alpha) {
  const int r = X.r, prot = static_cast<int>(gens.size()), p = prot + r;
  Point t = X;
  for (int v = 1; v < P.n; ++v) {
    const int o0 = (v - 1) * p;
    Small B = Small::Zero(r, r);
    for (int k = 0; k < prot; ++k) {
      const auto [a, b] = gens[static_cast<std::size_t>(k)];
      B(a, b) += alpha * step(o0 + k);
      B(b, a) -= alpha * step(o0 + k);
    }
    t.Q[static_cast<std::size_t>(v)] = retract(X.Q[static_cast<std::size_t>(v)], B);
    t.T.col(v) += alpha * step.segment(o0 + prot, r);
  }
  return t;
}

// The local solve above rank d: a Riemannian trust region (Absil, Baker & Gallivan 2007; SE-Sync's local
// solver) whose steps are Steihaug–Toint CG on the exact Riemannian Hessian, applied without forming it
// (DataPreconditioner::euclidean_hessian plus the curvature blocks) and preconditioned by the factor of 2M₀.
// Above rank d the Newton system's blocks grow as r² and its factorizations as r³, and at the minimizers of a
// relaxation that is not exact Y is rank-deficient, so the Hessian is singular there and indefinite around
// them: Newton steps with a factorized, damped Hessian spent 300 iterations per rank without converging. The
// stopping rules are local_solve's.
constexpr int kMaxTcgMatrixFree = 1000;
LocalOutcome trust_region_solve(const Problem& P, Point& X, const CertifiedOptions& o,
                                const DataPreconditioner& pre, const Deadline& deadline) {
  const int d = P.d, r = X.r;
  const auto gens = generators(r, d);
  const int prot = static_cast<int>(gens.size()), p = prot + r, nb = P.n - 1, N = nb * p;
  std::vector<Small> D(static_cast<std::size_t>(P.n) * static_cast<std::size_t>(prot));
  std::vector<double> curvature(static_cast<std::size_t>(nb) * static_cast<std::size_t>(prot * prot));
  Eigen::VectorXd g(N), step(N);
  auto product = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
    pre.euclidean_hessian(X.Q, gens, r, x, y);
    for (int b = 0; b < nb; ++b) {
      const Eigen::Map<const Eigen::MatrixXd> C(&curvature[static_cast<std::size_t>(b) * prot * prot], prot,
                                                prot);
      y.segment(b * p, prot).noalias() += C * x.segment(b * p, prot);
    }
  };
  auto precondition = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out_z) {
    pre.apply(X.Q, gens, r, in, out_z);
  };

  LocalOutcome out;
  double f = cost(P, X);
  double radius = 0.0;  // M-norm; 0: set from the first preconditioned gradient step
  bool rebuild = true;
  double gnorm = 0.0;
  Stopping stop;
  for (int it = 0; it < o.max_iterations; ++it) {
    if (deadline.passed()) {
      out.timed_out = true;
      break;
    }
    if (rebuild) {
      tangent_model(P, X, gens, D, g, curvature);
      gnorm = g.norm();
      if (stop.done(P, X, o, gnorm, f)) break;
      rebuild = false;
    }
    ++out.iterations;
    if (!(radius > 0.0)) {
      precondition(-g, step);
      radius = std::sqrt(std::max(-g.dot(step), std::numeric_limits<double>::min()));
    }
    const double eta = std::min(0.1, std::sqrt(gnorm / stop.first_gradient));
    double dAd = 0.0, step_norm = 0.0;
    int used = 0;
    const TcgEnd end =
        steihaug_cg(product, precondition, g, radius, eta, kMaxTcgMatrixFree, step, dAd, step_norm, used);
    out.tcg_iterations += used;
    const double predicted = -g.dot(step) - 0.5 * dAd;
    if (!(predicted > 0.0)) {
      radius = 0.25 * step_norm;
      if (!(radius > 0.0)) break;
      continue;
    }
    const bool below_rounding = predicted <= 64.0 * kUnitRoundoff * std::max(std::abs(f), 1e-300);
    Point trial = moved(P, X, gens, step, 1.0);
    const double f_new = cost(P, trial);
    const double rho = (f - f_new) / predicted;
    bool accept = rho > 1e-4;
    if (!(rho >= 0.25))
      radius = 0.25 * step_norm;
    else if (rho > 0.75 && end != TcgEnd::converged)
      radius *= 2.0;
    if (below_rounding) {
      accept = riemannian_gradient_norm(P, trial, gens) < gnorm;
      if (!accept) break;  // neither F nor the gradient can be improved in double precision
    }
    if (accept) {
      stop.last_decrease = f - f_new;
      X = std::move(trial);
      f = f_new;
      rebuild = true;
    }
  }
  out.cost = f;
  out.gradient_norm = rebuild ? riemannian_gradient_norm(P, X, gens) : gnorm;
  return out;
}

// The local solve at the rank of X (pose 0 held). Above rank d: trust_region_solve. At rank d: Newton with
// Levenberg–Marquardt damping, and trust-region steps where the damped Hessian is not positive definite.
LocalOutcome local_solve(const Problem& P, Point& X, const CertifiedOptions& o,
                         std::unique_ptr<DataPreconditioner>& pre, const Deadline& deadline) {
  // The data matrix is factorized the first time the staircase climbs above rank d (never on a graph whose
  // relaxation is certified at rank d), then kept for every higher rank.
  if (X.r > P.d && o.trust_region_above_d) {
    if (!pre) pre = std::make_unique<DataPreconditioner>(P);
    if (pre->ok()) return trust_region_solve(P, X, o, *pre, deadline);
  }
  const int d = P.d, r = X.r;
  const auto gens = generators(r, d);
  const int prot = static_cast<int>(gens.size());
  const int p = prot + r;
  const int nb = P.n - 1;
  BlockPattern pattern(std::vector<int>(static_cast<std::size_t>(nb), p), free_pairs(P));
  std::vector<int> pos(P.edges.size(), -1);
  for (std::size_t k = 0; k < P.edges.size(); ++k) {
    const int a = P.edges[k].i - 1, b = P.edges[k].j - 1;
    if (a >= 0 && b >= 0) pos[k] = pattern.position(std::min(a, b), std::max(a, b));
  }
  detail::SparseCholesky chol(pattern.dimension(), pattern.col_start(), pattern.row_index(),
                              detail::FillOrdering::automatic, false);
  const int N = pattern.dimension();
  std::vector<double> hessian(chol.values().size()), gauss_newton;
  double radius = 0.0;  // the trust region of the Steihaug–Toint steps (M-norm; 0: not yet set)
  Eigen::VectorXd g(N), step(N), diag(N);

  LocalOutcome out;
  out.ordering = chol.ordering_name();
  double f = cost(P, X);
  double lambda = 1e-10;
  double nu = 2.0;
  bool rebuild = true;
  std::vector<Small> D(static_cast<std::size_t>(P.n) * static_cast<std::size_t>(prot));
  std::vector<double> curvature(static_cast<std::size_t>(nb) * static_cast<std::size_t>(prot * prot));
  double gnorm = 0.0;
  Stopping stop;
  int last_cg = 0;            // CG iterations of the last inexact step (0 after a factorization)
  bool factor_valid = false;  // chol holds the factor of an earlier damped system (CG's preconditioner)
  bool indefinite = false;    // H + λ diag was not positive definite: trust-region steps (Steihaug–Toint)
  bool preconditioner_valid = false;  // chol holds the factor of a damped Gauss–Newton matrix
  int last_tcg = 0;                   // Steihaug–Toint iterations of the last trust-region step

  for (int it = 0; it < o.max_iterations; ++it) {
    if (deadline.passed()) {
      out.timed_out = true;
      break;
    }
    if (rebuild) {
      // Tangent basis per pose, the gradient in tangent coordinates and the Hessian (pattern.offset(b) =
      // b·p).
      tangent_model(P, X, gens, D, g, curvature);
      gnorm = g.norm();
      if (stop.done(P, X, o, gnorm, f)) break;
      std::fill(hessian.begin(), hessian.end(), 0.0);
      // The common ranks with fixed-size matrices (no dynamic-size products), others at run-time sizes.
      if (d == 2 && r == 2)
        gauss_newton_blocks<2, 2>(P, D, prot, p, pattern, pos, hessian);
      else if (d == 2 && r == 3)
        gauss_newton_blocks<2, 3>(P, D, prot, p, pattern, pos, hessian);
      else if (d == 3 && r == 3)
        gauss_newton_blocks<3, 3>(P, D, prot, p, pattern, pos, hessian);
      else if (d == 3 && r == 4)
        gauss_newton_blocks<3, 4>(P, D, prot, p, pattern, pos, hessian);
      else
        gauss_newton_blocks<Eigen::Dynamic, Eigen::Dynamic>(P, D, prot, p, pattern, pos, hessian, d, r);
      gauss_newton = hessian;  // before the curvature: positive semidefinite
      for (int b = 0; b < nb; ++b) {
        Block C = Block::Zero(p, p);  // the curvature acts on the rotation coordinates only
        const double* c = &curvature[static_cast<std::size_t>(b) * prot * prot];
        for (int k = 0; k < prot; ++k)
          for (int l = 0; l < prot; ++l) C(k, l) = c[k * prot + l];
        const int dp = pattern.diagonal_position(b);
        for (int cc = 0; cc < p; ++cc)
          diag(pattern.offset(b) + cc) = hessian[static_cast<std::size_t>(pattern.index(dp, b, cc, cc))];
        pattern.add_diagonal(hessian, b, C);
      }
      rebuild = false;
    }
    ++out.iterations;
    // Damped system (H + λ diag(H_GN)) δ = −g.
    auto& values = chol.values();
    values = hessian;
    const double floor = 1e-12 * diag.maxCoeff();
    for (int b = 0; b < nb; ++b) {
      const int dp = pattern.diagonal_position(b);
      for (int cc = 0; cc < p; ++cc) {
        const int c = pattern.offset(b) + cc;
        values[static_cast<std::size_t>(pattern.index(dp, b, cc, cc))] += lambda * std::max(diag(c), floor);
      }
    }
    const Eigen::VectorXd minus_g = -g;
    double dAd = 0.0;  // δᵀ (damped matrix) δ; δᵀHδ for a trust-region step
    bool solved = false;
    bool trust_step = false, on_boundary = false;
    double step_norm_m = 0.0;
    if (indefinite) {
      // Trust-region steps on the exact Hessian (Conn, Gould & Toint, Alg. 6.1.1, the scheme of SE-Sync's
      // Riemannian trust region): Steihaug–Toint CG on H, preconditioned by the factor of the damped
      // Gauss–Newton matrix (positive semidefinite, so definite once damped) of this or an earlier point,
      // inside ‖δ‖_M ≤ radius. They follow the negative curvature that a Gauss–Newton step cannot see, where
      // Gauss–Newton steps alone crawl: with large residuals (a relaxation that is not exact) they spent 300
      // iterations per rank without converging. The factor is refreshed when CG needed more than
      // kRefreshAfterTcg iterations; the first radius is the Gauss–Newton step's M-norm.
      if (!preconditioner_valid || last_tcg > kRefreshAfterTcg) {
        values = gauss_newton;
        for (int b = 0; b < nb; ++b) {
          const int dp = pattern.diagonal_position(b);
          for (int cc = 0; cc < p; ++cc) {
            const int c = pattern.offset(b) + cc;
            values[static_cast<std::size_t>(pattern.index(dp, b, cc, cc))] +=
                lambda * std::max(diag(c), floor);
          }
        }
        ++out.factorizations;
        preconditioner_valid = chol.factorize();
        factor_valid = false;  // not a factor of the damped Hessian: no inexact Newton steps on it
        last_tcg = 0;
        if (!preconditioner_valid) {
          lambda *= nu;
          nu *= 2.0;
          if (lambda > 1e16) break;
          continue;
        }
      }
      auto precondition = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out_z) {
        chol.solve(in.data(), out_z.data(), 1);
      };
      if (!(radius > 0.0)) {
        precondition(minus_g, step);
        radius = std::sqrt(std::max(-g.dot(step), std::numeric_limits<double>::min()));
      }
      const double eta = std::min(0.1, std::sqrt(gnorm / stop.first_gradient));
      auto product = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
        symmetric_product(chol.col_start(), chol.row_index(), hessian, x, y);
      };
      const TcgEnd end =
          steihaug_cg(product, precondition, g, radius, eta, kMaxTcg, step, dAd, step_norm_m, last_tcg);
      out.tcg_iterations += last_tcg;
      on_boundary = end == TcgEnd::boundary || end == TcgEnd::negative_curvature;
      // CG converged inside the region without meeting negative curvature: H is (on its Krylov space)
      // positive definite here, so the next point tries Newton steps again. Not above rank d: there the
      // minimizers of a relaxation that is not exact have rank-deficient Y, so H is singular at them and
      // factorizations of the damped H keep failing near them.
      if (end == TcgEnd::converged && r == d) indefinite = false;
      trust_step = true;
    } else {
      // An inexact Newton step first (Dembo–Eisenstat–Steihaug): conjugate gradients on the damped system,
      // preconditioned by the factor of an earlier one, to the relative residual η = min(0.1, √(‖g‖/‖g₀‖))
      // (superlinear convergence as η → 0). Near a minimum the Hessian changes little between steps, so a
      // few triangular solves replace a factorization; when CG meets negative curvature or needs more than
      // kMaxCg iterations the system is factorized as before.
      if (o.inexact_newton && factor_valid && last_cg <= kRefreshAfterCg) {
        const double eta = std::min(0.1, std::sqrt(gnorm / stop.first_gradient));
        solved = preconditioned_cg(chol, values, g, eta, step, dAd, last_cg);
        if (solved) ++out.cg_steps;
      }
      if (!solved) {
        ++out.factorizations;
        factor_valid = chol.factorize();
        preconditioner_valid = false;
        last_cg = 0;
        if (!factor_valid) {
          // H + λ diag is not positive definite: trust-region steps from here on (above), until they find
          // H positive definite again.
          indefinite = true;
          continue;
        }
        chol.solve(minus_g.data(), step.data(), 1);
        dAd = -g.dot(step);  // the damped system holds to rounding: (H + λ diag) δ = −g
      }
    }
    // Model decrease −(gᵀδ + ½ δᵀ H δ) with the undamped H: δᵀHδ = δᵀ(H + λ diag)δ − λ δᵀ diag δ (a
    // trust-region step's dAd is δᵀHδ itself).
    const double model_damping = trust_step ? 0.0 : lambda;
    double damped = 0.0;
    for (int c = 0; c < N; ++c) damped += step(c) * step(c) * std::max(diag(c), floor);
    const double predicted = -g.dot(step) - 0.5 * (dAd - model_damping * damped);
    if (!(predicted > 0.0)) {
      if (trust_step) radius = 0.25 * step_norm_m;
      lambda *= nu;
      nu *= 2.0;
      if (lambda > 1e16) break;
      continue;
    }
    // Below the rounding of F a decrease cannot be measured: such a step is judged by the gradient instead.
    const bool below_rounding = predicted <= 64.0 * kUnitRoundoff * std::max(std::abs(f), 1e-300);
    // The point at X + α·step (retracted), its cost, and the model's decrease there: α·(−gᵀδ) − ½α²·δᵀHδ with
    // δᵀHδ = δᵀ(H + λ diag)δ − λ·δᵀ diag δ.
    const double descent = -g.dot(step), curvature_along = dAd - model_damping * damped;
    auto trial_at = [&](double alpha) { return moved(P, X, gens, step, alpha); };
    Point trial = trial_at(1.0);
    double f_new = cost(P, trial);
    double rho = (f - f_new) / predicted;
    bool backtracked = false;
    if (!(rho > 1e-4) && !below_rounding) {
      // The full step overshoots: shorter steps along it cost a cost evaluation each, a larger damping a
      // whole factorization. Two halvings before the damping grows.
      for (const double alpha : {0.5, 0.25}) {
        Point shorter = trial_at(alpha);
        const double f_alpha = cost(P, shorter);
        const double pred_alpha = alpha * descent - 0.5 * alpha * alpha * curvature_along;
        if (pred_alpha > 0.0 && (f - f_alpha) / pred_alpha > 1e-4) {
          trial = std::move(shorter);
          f_new = f_alpha;
          rho = (f - f_alpha) / pred_alpha;
          backtracked = true;
          break;
        }
      }
    }
    bool accept = rho > 1e-4;
    if (trust_step) {
      // The radius follows the model's agreement (Conn, Gould & Toint, Alg. 6.1.1).
      if (!(rho >= 0.25))
        radius = 0.25 * step_norm_m;
      else if (rho > 0.75 && on_boundary)
        radius *= 2.0;
    }
    if (below_rounding) {
      accept = riemannian_gradient_norm(P, trial, gens) < gnorm;
      if (!accept) break;  // neither F nor the gradient can be improved in double precision
    }
    if (accept) {
      stop.last_decrease = f - f_new;
      X = std::move(trial);
      f = f_new;
      // After a shortened step the model was too optimistic: more damping next time (as a rejection would).
      // Below the rounding of F, ρ is noise: the step counts as a good one.
      lambda *= backtracked      ? nu
                : below_rounding ? 1.0 / 3.0
                                 : std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
      lambda = std::max(lambda, 1e-14);
      nu = 2.0;
      rebuild = true;
    } else {
      lambda *= nu;
      nu *= 2.0;
      if (lambda > 1e16) break;
    }
  }
  out.cost = f;
  out.gradient_norm = rebuild ? riemannian_gradient_norm(P, X, gens) : gnorm;
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Linear least squares over the translations (t_0 = 0) for the rotation parts of X: T = argmin F.
void optimal_translations(const Problem& P, Point& X) {
  const int r = X.r, d = P.d, nb = P.n - 1;
  BlockPattern pattern(std::vector<int>(static_cast<std::size_t>(nb), 1), free_pairs(P));
  detail::SparseCholesky chol(nb, pattern.col_start(), pattern.row_index(), detail::FillOrdering::automatic,
                              false);
  auto& L = chol.values();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(nb, r);  // right-hand sides, one column per coordinate
  Eigen::Matrix<double, 1, 1> one;
  for (const auto& e : P.edges) {
    const int a = e.i - 1, b = e.j - 1;
    one(0, 0) = e.tau;
    if (a >= 0) pattern.add_diagonal(L, a, one);
    if (b >= 0) pattern.add_diagonal(L, b, one);
    if (a >= 0 && b >= 0) {
      one(0, 0) = -e.tau;
      pattern.add_off_diagonal(L, a, b, pattern.position(std::min(a, b), std::max(a, b)), one);
    }
    const SmallVec c = X.Y(e.i, d) * e.t;
    if (b >= 0) B.row(b) += e.tau * c.transpose();
    if (a >= 0) B.row(a) -= e.tau * c.transpose();
  }
  if (!chol.factorize())
    fail("solve_certified: the translation Laplacian is singular (is the graph connected?)");
  Eigen::MatrixXd T(nb, r);
  chol.solve(B.data(), T.data(), r);
  X.T.col(0).setZero();
  X.T.rightCols(nb) = T.transpose();
}

Small project_to_rotation(const Small& A) {
  Eigen::JacobiSVD<Small> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Small U = svd.matrixU();
  const Small V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0) U.col(U.cols() - 1) *= -1.0;
  return U * V.transpose();
}

// Chordal initialization: rotations by linear least squares with R_0 = I (rows of [R_1 … R_{n−1}] solve the
// rotation Laplacian), projected onto SO(d); then the translations.
Point chordal_initialization(const Problem& P) {
  const int d = P.d, nb = P.n - 1;
  BlockPattern pattern(std::vector<int>(static_cast<std::size_t>(nb), d), free_pairs(P));
  detail::SparseCholesky chol(pattern.dimension(), pattern.col_start(), pattern.row_index(),
                              detail::FillOrdering::automatic, false);
  auto& L = chol.values();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(pattern.dimension(), d);  // Bᵀ stacked: column = row of R
  for (const auto& e : P.edges) {
    const int a = e.i - 1, b = e.j - 1;
    const Small RRt = e.kappa * e.R * e.R.transpose();
    const Small kI = e.kappa * Small::Identity(d, d);
    if (a >= 0) pattern.add_diagonal(L, a, RRt);
    if (b >= 0) pattern.add_diagonal(L, b, kI);
    if (a >= 0 && b >= 0)
      pattern.add_off_diagonal(L, a, b, pattern.position(std::min(a, b), std::max(a, b)),
                               Small(-e.kappa * e.R));
    if (a < 0) B.middleRows(pattern.offset(b), d) += (e.kappa * e.R).transpose();  // B_j += κ R̃ (rows)
    if (b < 0) B.middleRows(pattern.offset(a), d) += e.kappa * e.R;                // B_i += κ R̃ᵀ
  }
  if (!chol.factorize())
    fail("solve_certified: the rotation Laplacian of the chordal initialization is singular");
  Eigen::MatrixXd Z(pattern.dimension(), d);
  chol.solve(B.data(), Z.data(), d);
  Point X;
  X.r = d;
  X.Q.assign(static_cast<std::size_t>(P.n), Small::Identity(d, d));
  for (int v = 1; v < P.n; ++v)
    X.Q[static_cast<std::size_t>(v)] =
        project_to_rotation(Small(Z.middleRows(pattern.offset(v - 1), d).transpose()));
  X.T = Eigen::MatrixXd::Zero(d, P.n);
  optimal_translations(P, X);
  return X;
}

// ---------------------------------------------------------------------------------------------------------------
// The certificate matrix S + η D over the columns [pose 0: Y_0 | pose v ≥ 1: t_v, Y_v].
struct CertificateMatrix {
  BlockPattern pattern;
  std::vector<int> pos;  // per edge
  explicit CertificateMatrix(const Problem& P)
      : pattern(
            [&] {
              std::vector<int> s(static_cast<std::size_t>(P.n), P.d + 1);
              s[0] = P.d;
              return s;
            }(),
            [&] {
              std::vector<std::pair<int, int>> pairs;
              for (const auto& e : P.edges) pairs.emplace_back(e.i, e.j);
              return pairs;
            }()) {
    pos.resize(P.edges.size());
    for (std::size_t k = 0; k < P.edges.size(); ++k)
      pos[k] = pattern.position(std::min(P.edges[k].i, P.edges[k].j), std::max(P.edges[k].i, P.edges[k].j));
  }
};

// Λ_i = sym(Y_iᵀ (X M)_{Y_i}) = sym(Y_iᵀ ∇_{Y_i}F) / 2.
std::vector<Small> multipliers(const Problem& P, const Point& X, const Gradient& G) {
  std::vector<Small> Lam(static_cast<std::size_t>(P.n));
  for (int v = 0; v < P.n; ++v) {
    const Small A = 0.5 * X.Y(v, P.d).transpose() * G.GY[static_cast<std::size_t>(v)];
    Lam[static_cast<std::size_t>(v)] = 0.5 * (A + A.transpose());
  }
  return Lam;
}

// F at X rounded upward, an upper bound on F at the point as stored: every residual entry in double-double
// (exact products; k additions err by at most 8k·u² times the sum of their terms' magnitudes), its
// magnitude bounded above, then squares, weights and sums each moved one ulp toward +∞ (core::round_up).
// Near a zero residual the entries of R_j − R_i R̃ cancel, so a bound relative to F itself would not hold.
double cost_upper(const Problem& P, const Point& X) {
  using core::round_up;
  const int d = P.d, r = X.r;
  constexpr double u2 = kUnitRoundoff * kUnitRoundoff;
  // |exact| ≤ |hi| + |lo| + 8(k + 1)u²·magnitude (exact products of small integers and powers of two).
  auto entry = [&](DD s, double magnitude, int additions) {
    const double err = round_up(8.0 * (additions + 1) * u2 * magnitude);
    const double v = round_up(round_up(std::abs(s.hi) + std::abs(s.lo)) + err);
    return round_up(v * v);
  };
  double f = 0.0;
  for (const auto& e : P.edges) {
    const auto Yi = X.Y(e.i, d);
    const auto Yj = X.Y(e.j, d);
    double rot = 0.0, trans = 0.0;
    for (int a = 0; a < r; ++a) {
      for (int c = 0; c < d; ++c) {
        DD s{Yj(a, c), 0.0};
        double mag = std::abs(Yj(a, c));
        for (int m = 0; m < d; ++m) {
          s = dd_add(s, dd_prod(-Yi(a, m), e.R(m, c)));
          mag = round_up(mag + round_up(std::abs(Yi(a, m) * e.R(m, c))));
        }
        rot = round_up(rot + entry(s, mag, d));
      }
      DD s = dd_add(DD{X.T(a, e.j), 0.0}, DD{-X.T(a, e.i), 0.0});
      double mag = round_up(std::abs(X.T(a, e.j)) + std::abs(X.T(a, e.i)));
      for (int m = 0; m < d; ++m) {
        s = dd_add(s, dd_prod(-Yi(a, m), e.t(m)));
        mag = round_up(mag + round_up(std::abs(Yi(a, m) * e.t(m))));
      }
      trans = round_up(trans + entry(s, mag, d + 1));
    }
    f = round_up(f + round_up(round_up(e.kappa * rot) + round_up(e.tau * trans)));
  }
  return f;
}

// The certificate at X: Λ from the first-order conditions, the shift η* of the gap tolerance and the proof of
// S + η* D ⪰ 0 by a margin-cleared Cholesky factorization. When `escape` is given and the test fails, it
// receives a direction v (over the columns of the certificate matrix) with vᵀ S v < 0 when one is found.
struct EscapeDirection {
  Eigen::VectorXd v;
  double rayleigh = 0.0;  // vᵀ S v / vᵀ D v
  bool found = false;
};

Certificate certificate_at(const Problem& P, const Point& X, double gap_tolerance, EscapeDirection* escape) {
  const auto t0 = core::Clock::now();
  const int d = P.d;
  Certificate C;
  const double F = cost(P, X);
  const Gradient G = gradient(P, X);
  const std::vector<Small> Lam = multipliers(P, X, G);
  double trace = 0.0, trace_abs = 0.0;
  for (const auto& L : Lam)
    for (int c = 0; c < d; ++c) {
      trace += L(c, c);
      trace_abs = core::round_up(trace_abs + std::abs(L(c, c)));  // an upper bound on Σ|Λ_cc|
    }
  C.trace_lambda = trace;
  const double dn = static_cast<double>(d) * P.n;
  const double eta = (gap_tolerance * std::max(F, 1.0) - (F - trace)) / dn;
  C.tolerance_shift = eta;
  C.rank = X.r;
  C.bound.upper = cost_upper(P, X);
  CertificateMatrix CM(P);
  const BlockPattern& pat = CM.pattern;
  const int N = pat.dimension();
  C.size = N;
  // S = M − diag(0, Λ) in double-double: its hi parts (S) and lo parts (S_lo); Sabs holds Σ|terms| and
  // S_terms the number of terms of each entry, for the bound on the formation's own error.
  const std::size_t nnz = pat.row_index().size();
  std::vector<double> S(nnz, 0.0), S_lo(nnz, 0.0), Sabs(nnz, 0.0);
  std::vector<int> S_terms(nnz, 0);
  auto accumulate = [&](int idx, DD value, double magnitude) {
    const auto q = static_cast<std::size_t>(idx);
    const DD sum = dd_add(DD{S[q], S_lo[q]}, value);
    S[q] = sum.hi;
    S_lo[q] = sum.lo;
    Sabs[q] = core::round_up(Sabs[q] + magnitude);
    ++S_terms[q];
  };
  for (std::size_t k = 0; k < P.edges.size(); ++k) {
    const int pos = CM.pos[k];
    edge_entries(P.edges[k], d, [&](int a, int b, int row, int col, DD value, double magnitude) {
      int idx = 0;
      if (a == b) {
        if (row > col) return;  // upper triangle only (the lower one is its mirror)
        idx = pat.index(pat.diagonal_position(a), a, row, col);
      } else if (a < b) {
        idx = pat.index(pos, b, row, col);
      } else {
        idx = pat.index(pos, a, col, row);
      }
      accumulate(idx, value, magnitude);
    });
  }
  // − Λ on the rotation blocks (Λ as stored: any symmetric Λ gives a valid bound).
  for (int v = 0; v < P.n; ++v) {
    const int rot = v == 0 ? 0 : 1;
    const int dp = pat.diagonal_position(v);
    for (int c2 = 0; c2 < d; ++c2)
      for (int c = 0; c <= c2; ++c)
        accumulate(pat.index(dp, v, rot + c, rot + c2), DD{-Lam[static_cast<std::size_t>(v)](c, c2), 0.0},
                   std::abs(Lam[static_cast<std::size_t>(v)](c, c2)));
  }
  // Each term of an entry is formed from products of stored numbers with an error below (4d + 7)·u² times the
  // sum of those products' magnitudes (the term's `magnitude`: d exact products added in double-double for
  // R̃R̃ᵀ, 4u² of the partial sums each, then κ· and τ· scalings of 3u² and one addition of 4u²), and each of
  // the entry's m additions errs by at most 4u²·(the partial sums' magnitudes) ≤ 4u²·Σ magnitudes:
  // |error| ≤ (4m + 4d + 8)·u²·Σ magnitudes.
  const std::vector<double> S_unshifted = S;
  auto is_rotation = [&](int col) {
    // Pose 0 occupies columns 0 … d−1 (all rotation); pose v ≥ 1 starts with its translation.
    if (col < d) return true;
    return (col - d) % (d + 1) != 0;
  };
  detail::DoubleDoubleSymmetric SS;
  SS.n = N;
  SS.col_start = pat.col_start();
  SS.row_index = pat.row_index();
  SS.hi = S;
  SS.lo = S_lo;
  SS.error.resize(nnz);
  for (std::size_t q = 0; q < nnz; ++q)
    SS.error[q] =
        core::round_up((4.0 * S_terms[q] + 4.0 * d + 8.0) * kUnitRoundoff * kUnitRoundoff * Sabs[q]);
  std::vector<char> rotation_columns(static_cast<std::size_t>(N));
  for (int col = 0; col < N; ++col)
    rotation_columns[static_cast<std::size_t>(col)] = is_rotation(col) ? 1 : 0;
  detail::ShiftedPsdProver prover(std::move(SS), std::move(rotation_columns));
  detail::SparseCholesky& chol = prover.cholesky();
  C.max_row_count = chol.max_row_count();
  auto diagonal_index = [&](int col) { return prover.diagonal_index(col); };
  // The proof of S + η·D ⪰ 0 at the smallest shift it can reach (psd_proof.hpp): η*/33 or η*/2 certify;
  // otherwise up to 10⁵·gap·max(F, 1)/(dn), the tightest bound that can be proven, outside the tolerance.
  const detail::ShiftSearch search = prover.shift_search(eta, gap_tolerance * std::max(F, 1.0) / dn, 5);
  C.attempts = search.attempts;
  C.failed_shift = search.largest_failed;
  C.proven = search.proven;
  // The proof's fields only from the proof that succeeded (search.proof is the last attempt's: a failed one
  // when nothing was proven).
  if (search.proven) {
    C.shift = search.shift;
    C.rounding_margin = search.proof.margin;
    C.residual = search.proof.residual;
    C.worst_case_residual = search.proof.worst_case_residual;
    C.formation_error = search.proof.formation_error;
    C.extended_precision = search.proof.extended_precision;
  }
  // What failed is kept apart from what was proven (C.failure, C.message): a failed attempt is never
  // described beside a proof.
  const std::string all_failed = search.proven
                                     ? std::string()
                                     : fmt::format("; every shift up to η = {:.3g} failed too ({} attempts)",
                                                   C.failed_shift, C.attempts);
  if (!search.within_tolerance)
    C.failure =
        eta > 0.0
            ? fmt::format(
                  "S + η·D ⪰ 0 could not be shown at η*/33 or η*/2 = {:.3g} (η* = {:.3g}): the "
                  "factorization of W(S + η·D)W − μI broke down or its residual exceeded μ{}",
                  0.5 * eta, eta, all_failed)
            : fmt::format("not stationary enough for the gap tolerance: F − tr(Λ) = {:.3g} exceeds {:.3g}{}",
                          F - trace, gap_tolerance * std::max(F, 1.0), all_failed);
  bool certified = false;
  if (search.proven) {
    // The lower bound tr(Λ) − γ_{dn}Σ|Λ_cc| − η d n (γ_{dn}Σ|Λ_cc|: the rounding of the trace's sum), every
    // operation rounded outward: the subtracted terms up, the differences down (core::round_down).
    const double k_u = dn * kUnitRoundoff;  // exact: an integer times a power of two
    const double gamma_up = core::round_up(k_u / core::round_down(1.0 - k_u));
    const double trace_error = core::round_up(gamma_up * trace_abs);
    const double shift_term = core::round_up(C.shift * dn);
    C.bound.lower = core::round_down(core::round_down(trace - trace_error) - shift_term);
    certified = C.bound.relative_gap_up() <= gap_tolerance;
    C.certified = certified;
    C.message = fmt::format("S + {}·D ⪰ 0 proven with rounding margin μ = {:.3g} (scaled){}{}",
                            core::format_upper(C.shift, 3), C.rounding_margin,
                            C.extended_precision ? " by a double-double factor" : "",
                            certified ? "" : ", outside the gap tolerance");
  } else {
    C.message = "no lower bound: " + C.failure;
  }
  if (!certified && escape) {
    // A direction of negative curvature: σ doubled from max(η, tiny) until S + σD factorizes, then inverse
    // iteration v ← (S + σD)⁻¹ D v, whose Rayleigh quotient vᵀSv / vᵀDv tends to the smallest generalized
    // eigenvalue.
    double sigma = std::max(eta, 1e-12 * std::max(1.0, F / dn));
    bool ok = false;
    for (int attempt = 0; attempt < 80 && !ok; ++attempt) {
      auto& A = chol.values();
      A = S_unshifted;
      for (int col = 0; col < N; ++col)
        if (is_rotation(col)) A[static_cast<std::size_t>(diagonal_index(col))] += sigma;
      ok = chol.factorize();
      if (!ok) sigma *= 2.0;
    }
    if (ok) {
      Eigen::VectorXd v(N), Dv(N);
      for (int col = 0; col < N; ++col) v(col) = is_rotation(col) ? std::cos(0.7 * col + 0.3) : 0.0;
      Eigen::VectorXd Sv(N);
      double q = 0.0;
      for (int iter = 0; iter < 60; ++iter) {
        for (int col = 0; col < N; ++col) Dv(col) = is_rotation(col) ? v(col) : 0.0;
        Eigen::VectorXd next(N);
        chol.solve(Dv.data(), next.data(), 1);
        double dnorm = 0.0;
        for (int col = 0; col < N; ++col)
          if (is_rotation(col)) dnorm += next(col) * next(col);
        v = next / std::sqrt(dnorm);
        symmetric_product(pat.col_start(), pat.row_index(), S_unshifted, v, Sv);
        q = v.dot(Sv);  // vᵀDv = 1
        if (iter >= 8 && q < -0.5 * sigma) break;
      }
      escape->v = v;
      escape->rayleigh = q;
      // Below −η* the staircase can descend; in [−η*, 0) the test failed by its rounding margin only, and a
      // lift would not help.
      escape->found = q < -std::max(eta, 0.0);
    }
  }
  C.time_s = core::seconds_since(t0);
  return C;
}

// Lift X to rank r + 1 along the escape direction v, with a backtracking step that decreases F.
bool lift(const Problem& P, Point& X, const EscapeDirection& esc) {
  const int d = P.d, r = X.r;
  const int n = P.n;
  // v's layout: pose 0 rotation c at c; pose v ≥ 1: translation at d + (v−1)(d+1), rotation c one further.
  auto rot_index = [&](int v, int c) { return v == 0 ? c : d + (v - 1) * (d + 1) + 1 + c; };
  auto trans_index = [&](int v) { return d + (v - 1) * (d + 1); };
  double vr = 0.0;
  for (int v = 0; v < n; ++v)
    for (int c = 0; c < d; ++c) vr += esc.v(rot_index(v, c)) * esc.v(rot_index(v, c));
  const double scale = std::sqrt(static_cast<double>(n) / vr);
  Point base;
  base.r = r + 1;
  base.Q.resize(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) {
    Small Q = Small::Identity(r + 1, r + 1);
    Q.topLeftCorner(r, r) = X.Q[static_cast<std::size_t>(v)];
    base.Q[static_cast<std::size_t>(v)] = Q;
  }
  base.T = Eigen::MatrixXd::Zero(r + 1, n);
  base.T.topRows(r) = X.T;
  const double f0 = cost(P, X);
  for (double alpha = 1.0; alpha > 1e-12; alpha *= 0.5) {
    Point trial = base;
    for (int v = 0; v < n; ++v) {
      Small B = Small::Zero(r + 1, r + 1);
      for (int c = 0; c < d; ++c) {
        // Generator (c, r): its tangent moves column c by −q_r = −e_r; we want +α v_c e_r.
        const double coef = -alpha * scale * esc.v(rot_index(v, c));
        B(c, r) += coef;
        B(r, c) -= coef;
      }
      trial.Q[static_cast<std::size_t>(v)] = base.Q[static_cast<std::size_t>(v)] * [&] {
        const Small I = Small::Identity(r + 1, r + 1);
        return Small((I - 0.5 * B).partialPivLu().solve(I + 0.5 * B));
      }();
      if (v > 0) trial.T(r, v) = alpha * scale * esc.v(trans_index(v));
    }
    if (cost(P, trial) < f0) {
      X = std::move(trial);
      return true;
    }
  }
  return false;
}

// Rounding a rank-r point to SO(d)ⁿ and its optimal translations.
Point round_to_rotations(const Problem& P, const Point& X) {
  const int d = P.d, r = X.r, n = P.n;
  Point R;
  R.r = d;
  R.Q.resize(static_cast<std::size_t>(n));
  if (r == d) {
    for (int v = 0; v < n; ++v) R.Q[static_cast<std::size_t>(v)] = project_to_rotation(Small(X.Y(v, d)));
  } else {
    Small YYt = Small::Zero(r, r);
    for (int v = 0; v < n; ++v) YYt += X.Y(v, d) * X.Y(v, d).transpose();
    Eigen::SelfAdjointEigenSolver<Small> eig(YYt);
    const Small U = eig.eigenvectors().rightCols(d);  // top d eigenvectors (ascending order)
    std::vector<Small> blocks(static_cast<std::size_t>(n));
    int positive = 0;
    for (int v = 0; v < n; ++v) {
      blocks[static_cast<std::size_t>(v)] = U.transpose() * X.Y(v, d);
      if (blocks[static_cast<std::size_t>(v)].determinant() > 0) ++positive;
    }
    for (int v = 0; v < n; ++v) {
      Small b = blocks[static_cast<std::size_t>(v)];
      if (2 * positive < n) b.row(d - 1) *= -1.0;
      R.Q[static_cast<std::size_t>(v)] = project_to_rotation(b);
    }
  }
  // Gauge: R_0 = I.
  const Small R0t = R.Q[0].transpose();
  for (auto& Q : R.Q) Q = R0t * Q;
  R.T = Eigen::MatrixXd::Zero(d, n);
  optimal_translations(P, R);
  return R;
}

template <class Pose>
Point point_from_poses(const Problem& P, const std::vector<Pose>& poses) {
  if (static_cast<int>(poses.size()) < P.n)
    fail(fmt::format("certify: {} poses given for a graph of {}", poses.size(), P.n));
  Point X;
  X.r = P.d;
  X.Q.resize(static_cast<std::size_t>(P.n));
  X.T.resize(P.d, P.n);
  for (int v = 0; v < P.n; ++v) {
    X.Q[static_cast<std::size_t>(v)] = poses[static_cast<std::size_t>(v)].rotation();
    X.T.col(v) = poses[static_cast<std::size_t>(v)].translation();
  }
  // Translations relative to pose 0 (the gauge of the certificate matrix), in pose 0's frame so that R_0 = I
  // is not required: F is invariant under a common rigid motion.
  const Small R0t = X.Q[0].transpose();
  const Eigen::VectorXd t0 = X.T.col(0);
  for (int v = 0; v < P.n; ++v) {
    X.Q[static_cast<std::size_t>(v)] = R0t * X.Q[static_cast<std::size_t>(v)];
    X.T.col(v) = R0t * (X.T.col(v) - t0);
  }
  return X;
}

lie::SE2 to_pose(const Small& R, const Eigen::VectorXd& t, const lie::SE2*) {
  return lie::SE2(t(0), t(1), std::atan2(R(1, 0), R(0, 0)));
}
lie::SE3 to_pose(const Small& R, const Eigen::VectorXd& t, const lie::SE3*) {
  return lie::SE3(lie::SO3::from_matrix_unchecked(lie::Mat3(R)), lie::Vec3(t));
}

template <class Pose, class Graph>
void solve_impl(const Graph& graph, const CertifiedOptions& o, CertifiedSummary& S,
                std::vector<Pose>& poses) {
  o.validate();
  // CHOLMOD's supernodal factorizations call the BLAS: one BLAS thread keeps the result independent of the
  // machine's core count (core/blas.hpp), and is what the side-by-side measurements use.
  const core::SingleThreadedBlas one_blas_thread;
  const core::SerialOpenMp serial_openmp;  // CHOLMOD's supernodal teams of four (core/blas.hpp)
  const auto t_total = core::Clock::now();
  const Deadline deadline{t_total, o.time_limit_s};
  const int d = std::is_same_v<Pose, lie::SE2> ? 2 : 3;
  if (o.max_rank < d) fail(fmt::format("CertifiedOptions: max_rank must be >= {} (got {})", d, o.max_rank));
  const Problem P = make_problem(graph, d);
  std::unique_ptr<DataPreconditioner> pre;  // made by the first local solve above rank d
  S.poses = P.n;
  S.edges = static_cast<int>(P.edges.size());
  S.dimension = d;
  S.problem = fmt::format(
      "isotropic (chordal) SE({}) synchronization: Σ κ‖R_j − R_i R̃‖²_F + τ‖t_j − t_i − R_i t̃‖² with "
      "SE-Sync's κ, τ "
      "from each edge's information",
      d);
  auto t0 = core::Clock::now();
  Point X;
  if (o.chordal_initialization) {
    X = chordal_initialization(P);
  } else {
    if (static_cast<int>(graph.poses.size()) < P.n)
      fail("solve_certified: chordal_initialization = false needs an estimate for every pose in the graph");
    X = point_from_poses(P, graph.poses);
  }
  S.initial_cost = cost(P, X);
  S.initialization_time_s = core::seconds_since(t0);

  // The proven certificate with the highest lower bound over every point tested (any proven Λ bounds the
  // minimum, whichever point it came from), and whether it is the last one tested.
  Certificate best;
  int tested = 0, best_index = -1;
  auto keep = [&](const Certificate& C) {
    if (C.proven && (!best.proven || C.bound.lower > best.bound.lower)) {
      best = C;
      best_index = tested;
    }
    ++tested;
  };
  bool rank_limited = false, timed_out = false;
  for (;;) {
    const auto t_rank = core::Clock::now();
    t0 = core::Clock::now();
    const LocalOutcome local = local_solve(P, X, o, pre, deadline);
    S.local_time_s += core::seconds_since(t0);
    local.add_to(S);
    if (S.ordering.empty()) S.ordering = local.ordering;
    RankRecord rec;
    rec.rank = X.r;
    rec.iterations = local.iterations;
    rec.factorizations = local.factorizations;
    rec.cg_steps = local.cg_steps;
    rec.tcg_iterations = local.tcg_iterations;
    rec.cost = local.cost;
    rec.gradient_norm = local.gradient_norm;
    EscapeDirection esc;
    t0 = core::Clock::now();
    const Certificate C = certificate_at(P, X, o.gap_tolerance, X.r < o.max_rank ? &esc : nullptr);
    S.certificate_time_s += core::seconds_since(t0);
    keep(C);
    rec.certified = C.certified;
    rec.lambda_min_estimate = esc.found ? esc.rayleigh : 0.0;
    rec.time_s = core::seconds_since(t_rank);
    S.staircase.push_back(rec);
    S.final_rank = X.r;
    S.certificate = C;
    if (C.certified) break;
    if (local.timed_out || deadline.passed()) {
      timed_out = true;
      break;
    }
    if (X.r >= o.max_rank || !esc.found || !lift(P, X, esc)) {
      rank_limited = X.r >= o.max_rank;
      if (!esc.found && X.r < o.max_rank)
        S.message = fmt::format(
            "the certificate failed at rank {} but S has no curvature below −η* = {:.3g} (estimate {:.3g}): "
            "the "
            "test is at the limit of double precision for this gap tolerance",
            X.r, S.certificate.tolerance_shift, esc.rayleigh);
      break;
    }
  }
  // Back to SO(d)ⁿ, polish at rank d, certify the returned point.
  t0 = core::Clock::now();
  if (X.r > d) {
    X = round_to_rotations(P, X);
    S.rounding_time_s = core::seconds_since(t0);
    t0 = core::Clock::now();
    const LocalOutcome local = local_solve(P, X, o, pre, deadline);
    S.local_time_s += core::seconds_since(t0);
    local.add_to(S);
    timed_out = timed_out || local.timed_out;
    t0 = core::Clock::now();
    Certificate C = certificate_at(P, X, o.gap_tolerance, nullptr);
    S.certificate_time_s += core::seconds_since(t0);
    keep(C);
    S.certificate = C;
  } else {
    // Already SO(d)ⁿ (to rounding): re-project and re-solve the translations so the returned rotations are
    // orthonormal; F changes in the last bits only.
    Point R = round_to_rotations(P, X);
    if (cost(P, R) <= S.certificate.bound.upper * (1.0 + 1e-12)) X = std::move(R);
    S.rounding_time_s = core::seconds_since(t0);
  }
  S.final_cost = cost(P, X);
  // The reported certificate is the proof behind the best lower bound, every field its own; the upper end is
  // F at the returned point, rounded up. Nothing proven: the last test's failure, lower −∞.
  const double upper = cost_upper(P, X);
  if (best.proven) {
    if (best_index != tested - 1) {
      // The bound comes from a staircase point: the returned point's own test is reported beside it.
      S.bound_from_staircase = true;
      S.returned_point = S.certificate;
      S.returned_point.bound.upper = upper;
    }
    S.certificate = best;
  } else {
    S.certificate.bound.lower = -std::numeric_limits<double>::infinity();
  }
  S.certificate.bound.upper = upper;
  const double gap = S.certificate.bound.relative_gap_up();
  S.certificate.certified = S.certificate.proven && gap <= o.gap_tolerance;
  if (S.certificate.certified) {
    S.termination = CertifiedTermination::certified;
    S.status = core::SearchStatus::optimal;
    S.message = fmt::format("numerically certified at rank {}: relative gap {} ≤ {:.3g}", S.final_rank,
                            core::format_upper(gap, 3), o.gap_tolerance);
  } else {
    S.termination = timed_out      ? CertifiedTermination::time_limit
                    : rank_limited ? CertifiedTermination::rank_limit
                                   : CertifiedTermination::not_certified;
    S.status = core::SearchStatus::unproven;
    if (timed_out)
      S.message =
          fmt::format("stopped at the time limit of {} s at rank {}; {}", o.time_limit_s, S.final_rank,
                      S.certificate.proven ? "the lower bound of the points reached holds"
                                           : "no lower bound holds at the points reached");
    if (S.message.empty())
      S.message = rank_limited
                      ? fmt::format("the staircase reached max_rank = {} without a certificate", o.max_rank)
                  : !S.certificate.proven
                      ? fmt::format("not certified: {}", S.certificate.message)
                      : fmt::format(
                            "not certified: the best lower bound (multipliers of the rank-{} point) leaves a "
                            "relative gap of {} > {:.3g}{}",
                            S.certificate.rank, core::format_lower(gap, 3), o.gap_tolerance,
                            S.bound_from_staircase ? "; the returned point's own test failed" : "");
  }
  poses.resize(static_cast<std::size_t>(P.n));
  for (int v = 0; v < P.n; ++v)
    poses[static_cast<std::size_t>(v)] = to_pose(
        X.Q[static_cast<std::size_t>(v)], Eigen::VectorXd(X.T.col(v)), static_cast<const Pose*>(nullptr));
  // The solution holds pose 0 at the identity (the gauge of the certificate matrix). A graph whose gauge is
  // another pose k (g2o's FIX k) gets the rigid motion that puts pose k at its as-read value; F, Λ and the
  // bound are invariant under it (F to rounding at the moved poses).
  if (const auto k = static_cast<std::size_t>(graph.gauge_pose);
      k != 0 && k < graph.poses.size() && k < poses.size()) {
    const Pose move = graph.poses[k] * poses[k].inverse();
    for (auto& T : poses) T = move * T;
    poses[k] = graph.poses[k];
  }
  S.total_time_s = core::seconds_since(t_total);
}

template <class Pose, class Graph>
Certificate certify_impl(const Graph& graph, const std::vector<Pose>& poses, double gap_tolerance) {
  if (!(gap_tolerance > 0.0)) fail(fmt::format("certify: gap_tolerance must be > 0 (got {})", gap_tolerance));
  const int d = std::is_same_v<Pose, lie::SE2> ? 2 : 3;
  const Problem P = make_problem(graph, d);
  const Point X = point_from_poses(P, poses);
  const core::SingleThreadedBlas one_blas_thread;  // as in solve_impl
  const core::SerialOpenMp serial_openmp;
  return certificate_at(P, X, gap_tolerance, nullptr);
}

template <class Pose, class Graph>
double cost_impl(const Graph& graph, const std::vector<Pose>& poses) {
  const int d = std::is_same_v<Pose, lie::SE2> ? 2 : 3;
  const Problem P = make_problem(graph, d);
  return cost(P, point_from_poses(P, poses));
}

}  // namespace

IsotropicWeights isotropic_weights(const graph::Edge2& e) {
  const lie::Mat2 tt = e.information.topLeftCorner<2, 2>();
  IsotropicWeights w;
  w.tau = 2.0 / tt.inverse().trace();
  w.kappa = e.information(2, 2);
  return w;
}

IsotropicWeights isotropic_weights(const graph::Edge3& e) {
  const lie::Mat3 tt = e.information.topLeftCorner<3, 3>();
  const lie::Mat3 qq = 4.0 * e.information.bottomRightCorner<3, 3>();
  IsotropicWeights w;
  w.tau = 3.0 / tt.inverse().trace();
  w.kappa = 3.0 / (2.0 * qq.inverse().trace());
  return w;
}

void CertifiedOptions::validate() const {
  if (!(gap_tolerance > 0.0 && gap_tolerance < 1.0))
    fail(fmt::format("CertifiedOptions: gap_tolerance must be in (0, 1) (got {})", gap_tolerance));
  if (max_rank > kMaxRank)
    fail(fmt::format("CertifiedOptions: max_rank must be <= {} (got {})", kMaxRank, max_rank));
  if (max_iterations < 1)
    fail(fmt::format("CertifiedOptions: max_iterations must be >= 1 (got {})", max_iterations));
  if (!(stationarity_tolerance > 0.0 && stationarity_tolerance <= 1.0))
    fail(fmt::format("CertifiedOptions: stationarity_tolerance must be in (0, 1] (got {})",
                     stationarity_tolerance));
  if (!(time_limit_s >= 0.0) || std::isinf(time_limit_s))
    fail(fmt::format(
        "CertifiedOptions: time_limit_s must be a finite number of seconds >= 0 (0: none; got {})",
        time_limit_s));
}

std::string_view to_string(CertifiedTermination t) {
  switch (t) {
    case CertifiedTermination::certified:
      return "certified";
    case CertifiedTermination::rank_limit:
      return "rank_limit";
    case CertifiedTermination::not_certified:
      return "not_certified";
    case CertifiedTermination::time_limit:
      return "time_limit";
  }
  return "unknown";
}

double isotropic_cost(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& poses) {
  return cost_impl(graph, poses);
}
double isotropic_cost(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& poses) {
  return cost_impl(graph, poses);
}

CertifiedResult2D solve_certified(const graph::PoseGraph2D& graph, const CertifiedOptions& options) {
  if (!graph.landmark_measurements.empty())
    fail(
        "solve_certified: graphs with landmarks are not supported (the isotropic model covers pose-pose "
        "edges)");
  CertifiedResult2D r;
  solve_impl(graph, options, r.summary, r.poses);
  return r;
}

CertifiedResult3D solve_certified(const graph::PoseGraph3D& graph, const CertifiedOptions& options) {
  CertifiedResult3D r;
  solve_impl(graph, options, r.summary, r.poses);
  return r;
}

Certificate certify(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& poses,
                    double gap_tolerance) {
  return certify_impl(graph, poses, gap_tolerance);
}
Certificate certify(const graph::PoseGraph3D& graph, const std::vector<lie::SE3>& poses,
                    double gap_tolerance) {
  return certify_impl(graph, poses, gap_tolerance);
}

}  // namespace keel::pgo
