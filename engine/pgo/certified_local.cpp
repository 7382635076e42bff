// keel::pgo::certified — the local solves on the lift: Newton with Levenberg–Marquardt damping at rank d
// (factorized by CHOLMOD, or CG on an earlier factor), the matrix-free Riemannian trust region above
// (certified_internal.hpp).
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

bool preconditioned_cg(const linalg::SparseCholesky& chol, const std::vector<double>& values,
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
//
// Each trial point X + δ (retracted) gets the translations that minimize F for its rotations (one solve with
// the factor of A_tt the preconditioner holds) before F is evaluated: the trust region then measures the step
// on F(Y) = min_t F(Y, t), SE-Sync's problem with the translations eliminated (Rosen et al. 2019), with the
// joint model. The step's translation part is a straight line while the retraction bends the rotations, so at
// the joint trial point the translations no longer fit the rotations. With them re-solved, City10000's
// subsets with rotation noise of 1–2 rad or outlier closures took about half the trust-region steps and CG
// iterations (docs/measurements/2026-12-08-certified-optimal-translations.md). F at the trial is never above
// the joint step's, so an accepted step still decreases F.
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
  LocalOutcome out;
  double f = cost(P, X);
  // CertifiedOptions::preconditioner. Automatic: the reduced form where Σ τ‖t̃‖² ≥ F. The joint form's
  // preconditioned Hessian has, along the normal directions the projection drops, eigenvalues of A_yy against
  // the Schur complement S (DataPreconditioner::apply_reduced); along Y itself that ratio is
  // (F_rot + Σ τ‖t̃‖²) / F*, with F_rot the rotation terms of F and F* ≤ F its value at optimal translations:
  // it grows with Σ τ‖t̃‖² / F, and the reduced form pays for its extra work only where that is large. The
  // threshold 1 is measured, not derived: on ext_certified_noise's graphs Σ τ‖t̃‖² / F was ≥ 1.9 on every
  // graph where the reduced form saved time and ≤ 0.84 on every one where it cost time
  // (docs/measurements/2026-12-07-certified-reduced-preconditioner.md).
  const bool reduced =
      o.preconditioner == TrustRegionPreconditioner::reduced ||
      (o.preconditioner == TrustRegionPreconditioner::automatic && pre.translation_energy() >= f);
  auto precondition = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out_z) {
    if (reduced)
      pre.apply_reduced(X.Q, gens, r, in, out_z);
    else
      pre.apply(X.Q, gens, r, in, out_z);
  };
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
    pre.optimal_translations(P, trial);
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
      // CertifiedOptions::staircase_relative_decrease (0 in the tight solves): the model's own minimizer,
      // predicted well, and F all but unmoved. A small decrease after the radius shrank, or from a step the
      // model predicted badly, says nothing about F having stopped.
      const bool slow =
          end == TcgEnd::converged && rho >= 0.25 && f - f_new < o.staircase_relative_decrease * std::abs(f);
      f = f_new;
      rebuild = true;
      if (slow) break;
    }
  }
  out.cost = f;
  out.gradient_norm = rebuild ? riemannian_gradient_norm(P, X, gens) : gnorm;
  return out;
}

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
  linalg::SparseCholesky chol(pattern.dimension(), pattern.col_start(), pattern.row_index(),
                              linalg::CholeskyOptions{});
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

}  // namespace keel::pgo::certified
