#include "sos/verify.hpp"

#include <fmt/format.h>

#include "sos/eigen_sparse.hpp"
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "core/timing.hpp"
#include "graph/io.hpp"
#include "pgo/optimize.hpp"

namespace keel::sos {

namespace {

using SpMat = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

// Q = Bᵀ B with B = [r | A]: the homogenized cost matrix, f(z) = [1; z]ᵀ Q [1; z].
SpMat homogenized_cost(const PlanarProblem& p) {
  std::vector<Triplet> t;
  t.reserve(static_cast<std::size_t>(p.a.nonZeros() + p.r.size()));
  for (Eigen::Index k = 0; k < p.r.size(); ++k)
    if (p.r(k) != 0.0) t.emplace_back(static_cast<int>(k), 0, p.r(k));
  for (int c = 0; c < p.a.outerSize(); ++c)
    for (SpMat::InnerIterator it(p.a, c); it; ++it)
      t.emplace_back(static_cast<int>(it.row()), c + 1, it.value());
  SpMat b(p.a.rows(), p.a.cols() + 1);
  b.setFromTriplets(t.begin(), t.end());
  SpMat q = SpMat(b.transpose()) * b;
  q.makeCompressed();
  return q;
}

double diagonal_scale(const PlanarProblem& p) {
  // max_k Q_kk: column norms² of [r | A].
  double m = p.r.squaredNorm();
  for (int c = 0; c < p.a.outerSize(); ++c) {
    double s = 0.0;
    for (SpMat::InnerIterator it(p.a, c); it; ++it) s += it.value() * it.value();
    m = std::max(m, s);
  }
  return m;
}

}  // namespace

void GlobalCertificateOptions::validate() const {
  if (!(eta_relative > 0 && eta_relative < 1))
    throw std::invalid_argument(
        fmt::format("sos::GlobalCertificateOptions.eta_relative must be in (0, 1) (got {})", eta_relative));
  if (!(stationarity_tolerance > 0 && stationarity_tolerance <= eta_relative))
    throw std::invalid_argument(fmt::format(
        "sos::GlobalCertificateOptions.stationarity_tolerance must be in (0, eta_relative = {}] (got {}): an "
        "inexact stationary point moves S's eigenvalues by about that much",
        eta_relative, stationarity_tolerance));
  if (bound_factorizations < 0)
    throw std::invalid_argument(fmt::format(
        "sos::GlobalCertificateOptions.bound_factorizations must be >= 0 (got {})", bound_factorizations));
  if (!(gap_tolerance > 0))
    throw std::invalid_argument(
        fmt::format("sos::GlobalCertificateOptions.gap_tolerance must be > 0 (got {})", gap_tolerance));
}

void RefineOptions::validate() const {
  if (max_iterations < 1)
    throw std::invalid_argument(
        fmt::format("sos::RefineOptions.max_iterations must be >= 1 (got {})", max_iterations));
  if (!(gradient_tolerance > 0))
    throw std::invalid_argument(
        fmt::format("sos::RefineOptions.gradient_tolerance must be > 0 (got {})", gradient_tolerance));
}

GlobalCertificate certify_solution(const PlanarProblem& p, const Eigen::VectorXd& z,
                                   const GlobalCertificateOptions& o) {
  o.validate();
  const auto t0 = core::Clock::now();
  const int n = p.unknowns();
  if (z.size() != n)
    throw std::invalid_argument(fmt::format(
        "sos::certify_solution: z has {} entries, the problem has {} unknowns ({} poses, {} landmarks)",
        z.size(), n, p.poses, p.landmarks));
  if (!z.allFinite()) throw std::invalid_argument("sos::certify_solution: z has non-finite entries");
  for (int i = 1; i < p.poses; ++i) {
    const double rr = z.segment<2>(4 * (i - 1)).squaredNorm();
    if (std::abs(rr - 1.0) > 1e-9)
      throw std::invalid_argument(fmt::format(
          "sos::certify_solution: rotation of pose {} is off the circle (c² + s² = {:.12g}); project it "
          "first (project_rotations)",
          i, rr));
  }

  GlobalCertificate out;
  const SpMat q = homogenized_cost(p);
  Eigen::VectorXd v(n + 1);
  v(0) = 1.0;
  v.tail(n) = z;
  const Eigen::VectorXd qv = q * v;
  out.bound.upper = v.dot(qv);
  out.scale = q.diagonal().maxCoeff();

  // Multipliers (first-order conditions Q v = Λ v; least squares on each (c_i, s_i) pair).
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(n + 1);  // Λ's diagonal
  lambda(0) = qv(0);
  out.multiplier_sum = lambda(0);
  out.min_rotation_multiplier = std::numeric_limits<double>::infinity();
  for (int i = 1; i < p.poses; ++i) {
    const int c = 1 + 4 * (i - 1);
    const double li = v(c) * qv(c) + v(c + 1) * qv(c + 1);
    lambda(c) = lambda(c + 1) = li;
    out.multiplier_sum += li;
    out.min_rotation_multiplier = std::min(out.min_rotation_multiplier, li);
  }
  if (p.poses < 2) out.min_rotation_multiplier = 0.0;

  // S = Q − Λ with every diagonal entry stored (the pattern must not change with the shift).
  SpMat s = q;
  {
    std::vector<Triplet> d;
    d.reserve(static_cast<std::size_t>(n + 1));
    for (int k = 0; k <= n; ++k) d.emplace_back(k, k, -lambda(k));
    SpMat dl(n + 1, n + 1);
    dl.setFromTriplets(d.begin(), d.end());
    s += dl;
    s.makeCompressed();
  }
  const Eigen::VectorXd sv = qv - lambda.cwiseProduct(v);
  out.stationarity = sv.cwiseAbs().maxCoeff() / (out.scale * v.cwiseAbs().maxCoeff());
  out.stationary = out.stationarity <= o.stationarity_tolerance;

  // Positive definiteness of S + η D by sparse Cholesky (AMD ordering, one symbolic analysis), with D the
  // diagonal that is 1 on v₀ and the rotations and 0 on translations and landmarks: every feasible v' has
  // v'ᵀ D v' = poses, so success proves f(v') = v'ᵀ S v' + Σλ ≥ Σλ − η · poses for every feasible v' — a
  // lower bound on the minimum, whatever the translations. (S's translation block AᵀA is positive definite
  // for a connected graph, so the shift is needed only where the circles are.)
  SpMat identity(n + 1, n + 1);
  {
    std::vector<Triplet> d;
    d.emplace_back(0, 0, 1.0);
    for (int k = 0; k < n; ++k)
      if (p.is_rotation(k)) d.emplace_back(k + 1, k + 1, 1.0);
    identity.setFromTriplets(d.begin(), d.end());
  }
  double rotation_scale = q.coeff(0, 0);
  for (int k = 0; k < n; ++k)
    if (p.is_rotation(k)) rotation_scale = std::max(rotation_scale, q.coeff(k + 1, k + 1));
  Eigen::SimplicialLLT<SpMat, Eigen::Lower, Eigen::AMDOrdering<int>> llt;
  const auto tf = core::Clock::now();
  llt.analyzePattern(s);
  auto positive_definite = [&](double eta) {
    llt.factorize(s + eta * identity);
    ++out.factorizations;
    const bool ok = llt.info() == Eigen::Success;
    if (ok) out.factor_nonzeros = static_cast<long>(llt.matrixL().nestedExpression().nonZeros());
    return ok;
  };
  out.eta = o.eta_relative * rotation_scale;
  out.psd = positive_definite(out.eta);
  double best = std::numeric_limits<double>::infinity();  // smallest successful shift
  if (out.psd) {
    best = out.eta;
    double eta = out.eta;
    for (int k = 0; k < o.bound_factorizations; ++k) {
      eta /= 10.0;
      if (!positive_definite(eta)) {
        out.failed_shift = eta;
        break;
      }
      best = eta;
    }
  } else {
    out.failed_shift = out.eta;
    double eta = out.eta;
    for (int k = 0; k < o.bound_factorizations; ++k) {
      eta *= 10.0;
      if (positive_definite(eta)) {
        best = eta;
        break;
      }
      out.failed_shift = eta;
    }
  }
  out.factor_time_s = core::seconds_since(tf);
  out.lambda_min_bound = std::isfinite(best) ? -best : -std::numeric_limits<double>::infinity();
  const double poses = static_cast<double>(p.poses);
  out.bound.lower =
      std::isfinite(best) ? out.multiplier_sum - best * poses : -std::numeric_limits<double>::infinity();
  out.status = out.stationary && out.psd && out.relative_gap() <= o.gap_tolerance
                   ? core::SearchStatus::optimal
                   : core::SearchStatus::unproven;
  out.time_s = core::seconds_since(t0);
  return out;
}

RefineReport refine_solution(const PlanarProblem& p, Eigen::VectorXd& z, const RefineOptions& o) {
  o.validate();
  const int n = p.unknowns();
  if (z.size() != n)
    throw std::invalid_argument(
        fmt::format("sos::refine_solution: z has {} entries, the problem has {} unknowns", z.size(), n));
  if (!z.allFinite()) throw std::invalid_argument("sos::refine_solution: z has non-finite entries");
  const auto t0 = core::Clock::now();
  const double scale = diagonal_scale(p);
  RefineReport out;
  project_rotations(p, z);
  double cost = polynomial_cost(p, z);
  out.initial_cost = cost;
  // Parameters: θ_i in the slot of c_i (the slot of s_i is unused and held by a unit diagonal), the other
  // unknowns as they are. With g = Aᵀ(Az + r) and λ_i = c_i g_{c_i} + s_i g_{s_i} (the multipliers of the
  // certificate), the exact Hessian in θ is 2 DᵀAᵀA D − 2 diag(λ_i): Newton's method on the circle, which
  // converges quadratically where the Gauss–Newton of problem.hpp's refine() (which omits the λ term) is only
  // linear for a non-zero residual. Where that Hessian is not positive definite, the Gauss–Newton step is
  // used.
  Eigen::SimplicialLLT<SpMat, Eigen::Lower, Eigen::AMDOrdering<int>> llt;
  Eigen::VectorXd gp(n), lam = Eigen::VectorXd::Zero(n);
  std::vector<Triplet> dt, lt;
  while (true) {
    const Eigen::VectorXd g = p.a.transpose() * (p.a * z + p.r);
    dt.clear(), lt.clear();
    for (int v = 0; v < n; ++v) {
      if (!p.is_rotation(v)) {
        gp(v) = 2.0 * g(v);
        dt.emplace_back(v, v, 1.0);
      } else if (v % 4 == 0) {
        gp(v) = 2.0 * (-z(v + 1) * g(v) + z(v) * g(v + 1));
        gp(v + 1) = 0.0;
        dt.emplace_back(v, v, -z(v + 1)), dt.emplace_back(v + 1, v, z(v));
        lam(v) = z(v) * g(v) + z(v + 1) * g(v + 1);
        lt.emplace_back(v + 1, v + 1, 1.0);  // the unused s slot
      }
    }
    out.gradient = gp.cwiseAbs().maxCoeff() / scale;
    if (out.gradient <= o.gradient_tolerance || out.iterations >= o.max_iterations) break;
    SpMat d(n, n);
    d.setFromTriplets(dt.begin(), dt.end());
    const SpMat j = p.a * d;
    SpMat unit(n, n);
    unit.setFromTriplets(lt.begin(), lt.end());
    const SpMat gn = 2.0 * SpMat(j.transpose() * j) + unit;
    std::vector<Triplet> mt;
    for (int v = 0; v < n; v += 1)
      if (p.is_rotation(v) && v % 4 == 0) mt.emplace_back(v, v, -2.0 * lam(v));
    SpMat multipliers(n, n);
    multipliers.setFromTriplets(mt.begin(), mt.end());
    const SpMat newton = gn + multipliers;
    llt.compute(newton);
    if (llt.info() != Eigen::Success) llt.compute(gn);
    if (llt.info() != Eigen::Success) break;
    const Eigen::VectorXd step = llt.solve(-gp);
    // Backtracking: accept the first step that does not raise the cost beyond its rounding.
    double alpha = 1.0, trial_cost = cost;
    Eigen::VectorXd trial = z;
    bool accepted = false;
    for (int k = 0; k < 30 && !accepted; ++k, alpha *= 0.5) {
      for (int v = 0; v < n; ++v) {
        if (!p.is_rotation(v)) {
          trial(v) = z(v) + alpha * step(v);
        } else if (v % 4 == 0) {
          const double th = std::atan2(z(v + 1), z(v)) + alpha * step(v);
          trial(v) = std::cos(th), trial(v + 1) = std::sin(th);
        }
      }
      trial_cost = polynomial_cost(p, trial);
      accepted = trial_cost <= cost + 1e-14 * std::abs(cost);
    }
    if (!accepted) break;
    z = trial, cost = trial_cost, ++out.iterations;
  }
  out.final_cost = cost;
  out.time_s = core::seconds_since(t0);
  return out;
}

}  // namespace keel::sos
