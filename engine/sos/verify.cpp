#include "sos/verify.hpp"

#include <fmt/format.h>

#include "sos/eigen_sparse.hpp"
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/timing.hpp"
#include "graph/io.hpp"
#include "linalg/double_double.hpp"
#include "pgo/optimize.hpp"
#include "linalg/psd_proof.hpp"

namespace keel::sos {

namespace {

using SpMat = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

// B = [r | A]: f(z) = ‖B [1; z]‖².
SpMat augmented(const PlanarProblem& p) {
  std::vector<Triplet> t;
  t.reserve(static_cast<std::size_t>(p.a.nonZeros() + p.r.size()));
  for (Eigen::Index k = 0; k < p.r.size(); ++k)
    if (p.r(k) != 0.0) t.emplace_back(static_cast<int>(k), 0, p.r(k));
  for (int c = 0; c < p.a.outerSize(); ++c)
    for (SpMat::InnerIterator it(p.a, c); it; ++it)
      t.emplace_back(static_cast<int>(it.row()), c + 1, it.value());
  SpMat b(p.a.rows(), p.a.cols() + 1);
  b.setFromTriplets(t.begin(), t.end());
  return b;
}

// Q = Bᵀ B: the homogenized cost matrix, f(z) = [1; z]ᵀ Q [1; z].
SpMat homogenized_cost(const SpMat& b) {
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
  if (!(stationarity_tolerance > 0))
    throw std::invalid_argument(fmt::format(
        "sos::GlobalCertificateOptions.stationarity_tolerance must be > 0 (got {})", stationarity_tolerance));
  if (bound_factorizations < 0)
    throw std::invalid_argument(fmt::format(
        "sos::GlobalCertificateOptions.bound_factorizations must be >= 0 (got {})", bound_factorizations));
  if (!(gap_tolerance > 0 && gap_tolerance < 1))
    throw std::invalid_argument(
        fmt::format("sos::GlobalCertificateOptions.gap_tolerance must be in (0, 1) (got {})", gap_tolerance));
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
  const SpMat b_cols = augmented(p);
  const SpMat q = homogenized_cost(b_cols);
  Eigen::VectorXd v(n + 1);
  v(0) = 1.0;
  v.tail(n) = z;
  const Eigen::VectorXd qv = q * v;
  out.bound.upper = v.dot(qv);
  out.scale = q.diagonal().maxCoeff();

  // Multipliers (first-order conditions Q v = Λ v; least squares on each (c_i, s_i) pair). Any λ gives a
  // valid bound below; these make it tight at a stationary point.
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(n + 1);  // Λ's diagonal
  lambda(0) = qv(0);
  out.multiplier_sum = lambda(0);
  double multiplier_abs = std::abs(lambda(0));
  out.min_rotation_multiplier = std::numeric_limits<double>::infinity();
  for (int i = 1; i < p.poses; ++i) {
    const int c = 1 + 4 * (i - 1);
    const double li = v(c) * qv(c) + v(c + 1) * qv(c + 1);
    lambda(c) = lambda(c + 1) = li;
    out.multiplier_sum += li;
    multiplier_abs = core::round_up(multiplier_abs + std::abs(li));  // an upper bound on Σ|λ|
    out.min_rotation_multiplier = std::min(out.min_rotation_multiplier, li);
  }
  if (p.poses < 2) out.min_rotation_multiplier = 0.0;
  const Eigen::VectorXd sv = qv - lambda.cwiseProduct(v);
  out.stationarity = sv.cwiseAbs().maxCoeff() / (out.scale * v.cwiseAbs().maxCoeff());
  out.stationary = out.stationarity <= o.stationarity_tolerance;

  // S = Q − Λ in double-double on the upper triangle of Q's pattern (linalg/psd_proof.hpp): Q = BᵀB, B = [r |
  // A], accumulated row by row of B with exact products (fma). Each addition errs by at most 4u²·Σ|terms| of
  // its entry, so an entry of m terms is within 4(m + 1)u²·Σ|terms| of the exact value (the +1: −λ's term).
  linalg::DoubleDoubleSymmetric S;
  S.n = n + 1;
  {
    const Eigen::SparseMatrix<double, Eigen::RowMajor> b = b_cols;
    std::vector<std::vector<int>> rows_of(static_cast<std::size_t>(n + 1));
    for (int j = 0; j <= n; ++j) rows_of[static_cast<std::size_t>(j)].push_back(j);  // every diagonal
    for (int r = 0; r < b.outerSize(); ++r)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator a1(b, r); a1; ++a1)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator a2(b, r); a2; ++a2)
          if (a1.col() < a2.col())
            rows_of[static_cast<std::size_t>(a2.col())].push_back(static_cast<int>(a1.col()));
    S.col_start.assign(static_cast<std::size_t>(n + 2), 0);
    for (int j = 0; j <= n; ++j) {
      auto& rows = rows_of[static_cast<std::size_t>(j)];
      std::sort(rows.begin(), rows.end());
      rows.erase(std::unique(rows.begin(), rows.end()), rows.end());  // ascending: the diagonal last
      S.row_index.insert(S.row_index.end(), rows.begin(), rows.end());
      S.col_start[static_cast<std::size_t>(j) + 1] = static_cast<int>(S.row_index.size());
    }
    const std::size_t nnz = S.row_index.size();
    S.hi.assign(nnz, 0.0);
    S.lo.assign(nnz, 0.0);
    std::vector<double> abs_terms(nnz, 0.0);
    std::vector<int> terms(nnz, 0);
    auto index = [&](int i, int j) {
      const auto first = S.row_index.begin() + S.col_start[static_cast<std::size_t>(j)];
      const auto last = S.row_index.begin() + S.col_start[static_cast<std::size_t>(j) + 1];
      return static_cast<std::size_t>(std::lower_bound(first, last, i) - S.row_index.begin());
    };
    auto add = [&](std::size_t at, linalg::DD value) {
      const linalg::DD sum = linalg::dd_add(linalg::DD{S.hi[at], S.lo[at]}, value);
      S.hi[at] = sum.hi;
      S.lo[at] = sum.lo;
      abs_terms[at] += std::abs(value.hi) + std::abs(value.lo);
      ++terms[at];
    };
    for (int r = 0; r < b.outerSize(); ++r)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator a1(b, r); a1; ++a1)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator a2(b, r); a2; ++a2)
          if (a1.col() <= a2.col())
            add(index(static_cast<int>(a1.col()), static_cast<int>(a2.col())),
                linalg::dd_prod(a1.value(), a2.value()));
    for (int k = 0; k <= n; ++k)
      if (lambda(k) != 0.0) add(index(k, k), linalg::DD{-lambda(k), 0.0});
    S.error.resize(nnz);
    constexpr double u = std::numeric_limits<double>::epsilon() / 2;
    for (std::size_t k = 0; k < nnz; ++k) S.error[k] = 4.0 * (terms[k] + 1.0) * u * u * abs_terms[k];
  }
  // D: 1 on v₀ and the rotations, 0 on translations and landmarks. Every feasible v' has v'ᵀ D v' = poses, so
  // S + ηD ⪰ 0 proves f(v') = v'ᵀ S v' + Σλ ≥ Σλ − η · poses for every feasible v' — a lower bound on the
  // minimum, whatever the translations. (S's translation block AᵀA is positive definite for a connected
  // graph, so the shift is needed only where the circles are.)
  std::vector<char> shifted(static_cast<std::size_t>(n + 1), 0);
  shifted[0] = 1;
  for (int k = 0; k < n; ++k)
    if (p.is_rotation(k)) shifted[static_cast<std::size_t>(k) + 1] = 1;
  const auto tf = core::Clock::now();
  linalg::ShiftedPsdProver prover(std::move(S), std::move(shifted));
  const double poses = static_cast<double>(p.poses);
  const double f = out.bound.upper;
  // The decisive shift: the largest the gap tolerance allows, η* = (gap·max(f, 1) − (f − Σλ)) / poses. The
  // proof is tried at η*/33 and η*/2 with a double factor, then with a double-double one
  // (linalg/psd_proof.hpp).
  out.eta = (o.gap_tolerance * std::max(f, 1.0) - (f - out.multiplier_sum)) / poses;
  const linalg::ShiftSearch search =
      prover.shift_search(out.eta, o.gap_tolerance * std::max(f, 1.0) / poses, o.bound_factorizations);
  out.factorizations = search.attempts;
  out.failed_shift = search.largest_failed;
  out.psd = search.within_tolerance;
  if (search.proven) {
    out.rounding_margin = search.proof.margin;
    out.residual = search.proof.residual;
    out.extended_precision = search.proof.extended_precision;
  }
  const double best = search.proven ? search.shift : std::numeric_limits<double>::infinity();
  out.factor_nonzeros = static_cast<long>(prover.cholesky().factor_nonzeros());
  out.factor_time_s = core::seconds_since(tf);
  out.lambda_min_bound = std::isfinite(best) ? -best : -std::numeric_limits<double>::infinity();
  // The lower bound Σλ − γ_{poses+1}·Σ|λ| − η·poses (the sum of the multipliers errs by at most
  // γ_{poses}·Σ|λ|), every operation rounded outward: the subtracted terms up, the differences down.
  constexpr double u = std::numeric_limits<double>::epsilon() / 2;
  const double k_u = (poses + 1.0) * u;  // exact: an integer times a power of two
  const double trace_error =
      core::round_up(core::round_up(k_u / core::round_down(1.0 - k_u)) * multiplier_abs);
  out.bound.lower = std::isfinite(best)
                        ? core::round_down(core::round_down(out.multiplier_sum - trace_error) -
                                           core::round_up(best * poses))
                        : -std::numeric_limits<double>::infinity();
  out.status =
      out.relative_gap() <= o.gap_tolerance ? core::SearchStatus::optimal : core::SearchStatus::unproven;
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
  // The pattern llt was last analyzed for (outer starts and inner indices of a compressed matrix).
  std::vector<int> analyzed_outer, analyzed_inner;
  auto factorize = [&](const SpMat& m) {
    const std::span<const int> outer(m.outerIndexPtr(), static_cast<std::size_t>(m.outerSize()) + 1);
    const std::span<const int> inner(m.innerIndexPtr(), static_cast<std::size_t>(m.nonZeros()));
    if (!m.isCompressed() || !std::ranges::equal(outer, analyzed_outer) ||
        !std::ranges::equal(inner, analyzed_inner)) {
      llt.analyzePattern(m);
      analyzed_outer.assign(outer.begin(), outer.end());
      analyzed_inner.assign(inner.begin(), inner.end());
    }
    llt.factorize(m);
  };
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
    // The same pattern every iteration (every triplet above is inserted whatever its value): the
    // fill-reducing ordering is computed once per pattern and each iteration only factorizes, which is what
    // compute() does after its own analyzePattern, so the factor is the same to the bit.
    factorize(newton);
    if (llt.info() != Eigen::Success) factorize(gn);
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
