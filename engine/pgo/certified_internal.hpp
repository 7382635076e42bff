// Internal to engine/pgo: the parts of the certified solver (certified.hpp) in SE-Sync's seams: the problem
// data and the manifold (certified_problem.cpp), the local solves (certified_local.cpp), the chordal
// initialization, the lift and the rounding (certified_rounding.cpp) and the certificate
// (certified_certificate.cpp); certified.cpp runs the staircase over them. Not in the facade.
//
// Conventions. X = [t_1 … t_n | Y_1 … Y_n] ∈ R^{r×(n+dn)}; F(X) = tr(X M Xᵀ). Per edge e = (i, j) with data
// (R̃, t̃, κ, τ) M collects (blocks indexed by the columns of X; only the upper triangle is stored)
//   M[t_i,t_i] += τ,  M[t_j,t_j] += τ,  M[t_i,t_j] −= τ,
//   M[Y_i,Y_i] += κ R̃R̃ᵀ + τ t̃t̃ᵀ,  M[Y_j,Y_j] += κ I,  M[Y_i,Y_j] −= κ R̃,
//   M[Y_i,t_i] += τ t̃,  M[Y_i,t_j] −= τ t̃,
// so that tr(X M Xᵀ) = Σ κ‖Y_j − Y_i R̃‖² + τ‖t_j − t_i − Y_i t̃‖² (R̃R̃ᵀ rather than I keeps M exact for
// rotations stored to rounding). The Euclidean gradient is ∇F = 2 X M.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>

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
#include "pgo/certified.hpp"

namespace keel::pgo::certified {

constexpr int kMaxRank = 12;
// CertifiedOptions::staircase_stationarity: the staircase stops at a loose point whose rounded answer costs
// more than F there by this many gap tolerances (relative).
constexpr double kUncertifiable = 10.0;
using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxRank, kMaxRank>;
using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxRank, 1>;
constexpr int kMaxTangent = kMaxRank * 3 + kMaxRank;  // p_rot ≤ r·d with d ≤ 3, plus r translations
using Block =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 2 * kMaxTangent, 2 * kMaxTangent>;
constexpr double kUnitRoundoff = std::numeric_limits<double>::epsilon() / 2;  // u = 2⁻⁵³

[[noreturn]] void fail(const std::string& what);

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

std::string edge_name(const std::string& source, int index, int line);

template <class Graph>
Problem make_problem(const Graph& g, int d);

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
std::vector<std::pair<int, int>> free_pairs(const Problem& P);

// ---------------------------------------------------------------------------------------------------------------
// The point on the lift: Q_i ∈ O(r) (Y_i = first d columns), translations T (r × n).
struct Point {
  int r = 0;
  std::vector<Small> Q;
  Eigen::MatrixXd T;
  [[nodiscard]] auto Y(int i, int d) const { return Q[static_cast<std::size_t>(i)].leftCols(d); }
};

double cost(const Problem& P, const Point& X);

// ∇F = 2 X M: per pose the r × d block of Y_i and the r-vector of t_i.
struct Gradient {
  std::vector<Small> GY;
  Eigen::MatrixXd GT;
};

Gradient gradient(const Problem& P, const Point& X);

// The generators of the part of so(r) that moves the first d columns: G = e_a e_bᵀ − e_b e_aᵀ, a < d, a < b <
// r.
std::vector<std::pair<int, int>> generators(int r, int d);

// D_k = Q G_k E (r × d): column a is −q_b, column b (when b < d) is +q_a.
Small tangent_basis(const Small& Q, int d, int a, int b);

// ⟨W, G_k G_l E⟩ for generators k = (a, b), l = (a', b'):
// G_k G_l = δ_{b a'} e_a e_b'ᵀ − δ_{b b'} e_a e_a'ᵀ − δ_{a a'} e_b e_b'ᵀ + δ_{a b'} e_b e_a'ᵀ.
double curvature_term(const Small& W, int d, std::pair<int, int> k, std::pair<int, int> l);

// Q exp(B) by the Cayley transform Q (I − B/2)⁻¹ (I + B/2) (orthogonal, and equal to exp(B) to second order,
// so the curvature term of the Newton model is the one of this retraction).
Small retract(const Small& Q, const Small& B);

// ‖grad F‖ in the tangent coordinates of the local solve (pose 0 held): the translation gradient and the
// components of the Y-gradient along the generators.
double riemannian_gradient_norm(const Problem& P, const Point& X,
                                const std::vector<std::pair<int, int>>& gens);

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

// y = A x for the symmetric matrix whose upper triangle `values` holds in the compressed columns (cs, ri).
void symmetric_product(const std::vector<int>& cs, const std::vector<int>& ri,
                       const std::vector<double>& values, const Eigen::VectorXd& x, Eigen::VectorXd& y);

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
using linalg::DD;
using linalg::dd_add;
using linalg::dd_prod;
using linalg::dd_scale;

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
// The right-hand side of the translations' normal equations L_τ t = b for X's rotations (pose 0 removed, t_0
// = 0): row v − 1 of b is Σ over the edges at pose v of ±τ_e Y_i t̃_e (+ where v = j, − where v = i), one
// column per coordinate. optimal_translations and DataPreconditioner::optimal_translations solve with it.
Eigen::MatrixXd translation_rhs(const Problem& P, const Point& X);

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
    chol_ = std::make_unique<linalg::SparseCholesky>(N0, cs, ri, linalg::CholeskyOptions{});
    chol_->values() = values;
    // For apply_reduced(), one pass over 2M₀'s upper triangle: the entries whose row and column are both
    // translations (rows (v − 1)·w) form A_tt, 2 × the translation Laplacian of τ without pose 0, in the same
    // column order; those with one translation and one rotation index form the coupling block A_yt.
    std::vector<int> tcs(static_cast<std::size_t>(n_), 0), tri;
    std::vector<double> tvalues;
    for (int c = 0; c < N0; ++c)
      for (int q = cs[static_cast<std::size_t>(c)]; q < cs[static_cast<std::size_t>(c) + 1]; ++q) {
        const int row = ri[static_cast<std::size_t>(q)];
        const bool row_t = row % w == 0, col_t = c % w == 0;
        if (row_t && col_t) {
          tri.push_back(row / w);
          tvalues.push_back(values[static_cast<std::size_t>(q)]);
          ++tcs[static_cast<std::size_t>(c / w) + 1];
        } else if (row_t != col_t) {
          coupling_.push_back({row_t ? c : row, (row_t ? row : c) / w, values[static_cast<std::size_t>(q)]});
        }
      }
    for (int c = 0; c + 1 < n_; ++c) tcs[static_cast<std::size_t>(c) + 1] += tcs[static_cast<std::size_t>(c)];
    cs_ = std::move(cs);
    ri_ = std::move(ri);
    m0_ = std::move(values);
    for (const auto& e : P.edges) translation_energy_ += e.tau * e.t.squaredNorm();
    ok_ = chol_->factorize();
    if (ok_ && n_ > 1) {
      tchol_ = std::make_unique<linalg::SparseCholesky>(n_ - 1, tcs, tri, linalg::CholeskyOptions{});
      tchol_->values() = tvalues;
      ok_ = tchol_->factorize();
    }
  }
  [[nodiscard]] bool ok() const { return ok_; }
  // Σ_e τ_e ‖t̃_e‖²: F's translation terms with every position at 0 (CertifiedOptions::preconditioner).
  [[nodiscard]] double translation_energy() const { return translation_energy_; }

  // The preconditioner with the translations eliminated exactly (SE-Sync's on the rotations, Rosen et al.
  // 2019 §5.2, whose problem has no translations): with the joint matrix A = 2M₀ in blocks of translations t
  // and rotations y, its Schur complement S = A_yy − A_yt A_tt⁻¹ A_ty, and Π the orthogonal projection onto
  // the rotations' tangent space, the ambient vector u = E G⁻¹ c goes to
  //     z_y = Π S⁻¹ Π (u_y − A_yt A_tt⁻¹ u_t),     z_t = A_tt⁻¹ (u_t − A_ty z_y),
  // and back to coordinates by G⁻¹ Eᵀ. That is the block-LDLᵀ inverse of A with S⁻¹ replaced by Π S⁻¹ Π:
  // symmetric, positive definite on the tangent space. apply() (Π A⁻¹ Π on the joint vector) differs from it
  // where a normal component of A⁻¹'s rotation part carries translations with it that the projection then
  // strands: its preconditioned Hessian has eigenvalues of A_yy against S's, large where translations are
  // long. S⁻¹ v is the rotation part of A⁻¹ (v; 0), from the joint factor.
  void apply_reduced(const std::vector<Small>& Q, const std::vector<std::pair<int, int>>& gens, int r,
                     const Eigen::VectorXd& c, Eigen::VectorXd& z) const {
    const int w = d_ + 1, N0 = (n_ - 1) * w, nt = n_ - 1;
    embed(Q, gens, r, c, true, B_);  // u
    Ut_.resize(nt, r);
    for (int v = 0; v < nt; ++v) Ut_.row(v) = B_.row(v * w);
    Wt_.resize(nt, r);
    tchol_->solve(Ut_.data(), Wt_.data(), r);  // A_tt⁻¹ u_t
    // Π (u_y − A_yt A_tt⁻¹ u_t), translations 0.
    for (int v = 0; v < nt; ++v) B_.row(v * w).setZero();
    for (const Coupling& e : coupling_) B_.row(e.y) -= e.value * Wt_.row(e.t);
    project_ambient(Q, gens, r, B_);
    Z_.resize(N0, r);
    chol_->solve(B_.data(), Z_.data(), r);  // rotation rows: S⁻¹ Π (…)
    for (int v = 0; v < nt; ++v) Z_.row(v * w).setZero();
    project_ambient(Q, gens, r, Z_);                                            // (0; z_y)
    for (const Coupling& e : coupling_) Ut_.row(e.t) -= e.value * Z_.row(e.y);  // u_t − A_ty z_y
    tchol_->solve(Ut_.data(), Wt_.data(), r);                                   // z_t
    for (int v = 0; v < nt; ++v) Z_.row(v * w) = Wt_.row(v);
    project(Q, gens, r, Z_, true, z);
  }

  // X.T := the translations that minimize F for X's rotations, t_0 = 0 (the free function
  // optimal_translations, on this object's factor of A_tt = 2 L_τ, pose 0 removed, instead of a new one):
  // A_tt t = 2b with b = translation_rhs (the factor 2 is exact).
  void optimal_translations(const Problem& P, Point& X) const {
    const int nt = n_ - 1, r = X.r;
    if (nt == 0) return;
    Ut_ = 2.0 * translation_rhs(P, X);
    Wt_.resize(nt, r);
    tchol_->solve(Ut_.data(), Wt_.data(), r);
    X.T.col(0).setZero();
    X.T.rightCols(nt) = Wt_.transpose();
  }

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
  // Z := the orthogonal projection of Z's rotation rows onto the tangent space at Q (E G⁻¹ Eᵀ); translation
  // rows unchanged.
  void project_ambient(const std::vector<Small>& Q, const std::vector<std::pair<int, int>>& gens, int r,
                       Eigen::MatrixXd& Z) const {
    project(Q, gens, r, Z, true, coords_);
    embed(Q, gens, r, coords_, false, Z);
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
  std::unique_ptr<linalg::SparseCholesky> chol_;
  std::vector<int> cs_, ri_;  // 2M₀'s upper triangle (compressed columns)
  std::vector<double> m0_;
  bool ok_ = false;
  double translation_energy_ = 0.0;
  std::unique_ptr<linalg::SparseCholesky> tchol_;  // A_tt
  struct Coupling {
    int y, t;  // a rotation row of 2M₀ and a translation (pose − 1)
    double value;
  };
  std::vector<Coupling> coupling_;  // A_yt's entries
  mutable Eigen::MatrixXd B_, Z_, Ut_, Wt_;
  mutable Eigen::VectorXd coords_;
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
bool preconditioned_cg(const linalg::SparseCholesky& chol, const std::vector<double>& values,
                       const Eigen::VectorXd& g, double eta, Eigen::VectorXd& delta, double& dAd, int& used);

// The tangent model at X (pose 0 held): each pose's basis matrices D (pose v's basis k at D[v·prot + k]), the
// gradient g in those coordinates (pose v ≥ 1 at (v − 1)·p: rotation coordinates, then translation), and the
// symmetric curvature blocks (prot × prot per pose v ≥ 1) that the Riemannian Hessian adds to the Euclidean
// Hessian's compression on the rotation coordinates.
void tangent_model(const Problem& P, const Point& X, const std::vector<std::pair<int, int>>& gens,
                   std::vector<Small>& D, Eigen::VectorXd& g, std::vector<double>& curvature);

// X moved by α·step in the tangent coordinates (pose 0 held), retracted.
Point moved(const Problem& P, const Point& X, const std::vector<std::pair<int, int>>& gens,
            const Eigen::VectorXd& step, double alpha);
LocalOutcome trust_region_solve(const Problem& P, Point& X, const CertifiedOptions& o,
                                const DataPreconditioner& pre, const Deadline& deadline);

// The local solve at the rank of X (pose 0 held). Above rank d: trust_region_solve. At rank d: Newton with
// Levenberg–Marquardt damping, and trust-region steps where the damped Hessian is not positive definite.
LocalOutcome local_solve(const Problem& P, Point& X, const CertifiedOptions& o,
                         std::unique_ptr<DataPreconditioner>& pre, const Deadline& deadline);

// ---------------------------------------------------------------------------------------------------------------
// Linear least squares over the translations (t_0 = 0) for the rotation parts of X: T = argmin F.
void optimal_translations(const Problem& P, Point& X);

Small project_to_rotation(const Small& A);

// Chordal initialization: rotations by linear least squares with R_0 = I (rows of [R_1 … R_{n−1}] solve the
// rotation Laplacian), projected onto SO(d); then the translations.
Point chordal_initialization(const Problem& P);

// Λ_i = sym(Y_iᵀ (X M)_{Y_i}) = sym(Y_iᵀ ∇_{Y_i}F) / 2.
std::vector<Small> multipliers(const Problem& P, const Point& X, const Gradient& G);

// F at X rounded upward, an upper bound on F at the point as stored: every residual entry in double-double
// (exact products; k additions err by at most 8k·u² times the sum of their terms' magnitudes), its
// magnitude bounded above, then squares, weights and sums each moved one ulp toward +∞ (core::round_up).
// Near a zero residual the entries of R_j − R_i R̃ cancel, so a bound relative to F itself would not hold.
double cost_upper(const Problem& P, const Point& X);

// The certificate at X: Λ from the first-order conditions, the shift η* of the gap tolerance and the proof of
// S + η* D ⪰ 0 by a margin-cleared Cholesky factorization. When `escape` is given and the test fails, it
// receives a direction v (over the columns of the certificate matrix) with vᵀ S v < 0 when one is found.
struct EscapeDirection {
  Eigen::VectorXd v;
  double rayleigh = 0.0;  // vᵀ S v / vᵀ D v
  bool found = false;
};

Certificate certificate_at(const Problem& P, const Point& X, double gap_tolerance, EscapeDirection* escape);

// Lift X to rank r + 1 along the escape direction v, with a backtracking step that decreases F.
bool lift(const Problem& P, Point& X, const EscapeDirection& esc);

// Rounding a rank-r point to SO(d)ⁿ and its optimal translations.
Point round_to_rotations(const Problem& P, const Point& X);

}  // namespace keel::pgo::certified
