// keel::pgo::certified — chordal initialization, the optimal translations, the lift of a point to the next
// rank along an escape direction and the rounding back to SO(d) (certified_internal.hpp).
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

Eigen::MatrixXd translation_rhs(const Problem& P, const Point& X) {
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(P.n - 1, X.r);
  for (const auto& e : P.edges) {
    const int a = e.i - 1, b = e.j - 1;
    const SmallVec c = X.Y(e.i, P.d) * e.t;
    if (b >= 0) B.row(b) += e.tau * c.transpose();
    if (a >= 0) B.row(a) -= e.tau * c.transpose();
  }
  return B;
}

void optimal_translations(const Problem& P, Point& X) {
  const int r = X.r, nb = P.n - 1;
  BlockPattern pattern(std::vector<int>(static_cast<std::size_t>(nb), 1), free_pairs(P));
  linalg::SparseCholesky chol(nb, pattern.col_start(), pattern.row_index());
  auto& L = chol.values();
  const Eigen::MatrixXd B = translation_rhs(P, X);  // right-hand sides, one column per coordinate
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

Point chordal_initialization(const Problem& P) {
  const int d = P.d, nb = P.n - 1;
  BlockPattern pattern(std::vector<int>(static_cast<std::size_t>(nb), d), free_pairs(P));
  linalg::SparseCholesky chol(pattern.dimension(), pattern.col_start(), pattern.row_index(),
                              linalg::CholeskyOptions{});
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

}  // namespace keel::pgo::certified
