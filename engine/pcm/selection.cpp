#include "pcm/selection.hpp"

#include <fmt/format.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Spectra/MatOp/DenseSymMatProd.h>
#include <Spectra/SymEigsSolver.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "core/names.hpp"
#include "core/timing.hpp"

namespace keel::pcm {

namespace {

using core::Clock;
using core::seconds_since;

// SCGP's pairwise affinity exp(−max(q_uv, q_vu) / s), symmetric by construction; the weighted densest
// subgraph uses the same weights on consistent pairs.
double pair_affinity(const ConsistencyMatrix& Q, int u, int v, double scale) {
  return std::exp(-std::max(Q.at(u, v), Q.at(v, u)) / scale);
}

// The two largest eigenvalues of the symmetric A (λ₁ ≥ λ₂; λ₂ = 0 when n = 1) and λ₁'s unit eigenvector.
// Implicitly restarted Lanczos (Spectra's SymEigsSolver) for n ≥ 3: SCGP needs two eigenpairs, not all n, and
// each iteration is one product with A (O(n²)) instead of the full decomposition's O(n³) (at n = 1,000 about
// 4 ms against 0.75 s, eigenvectors equal to ~1e-16). Converged means each Ritz pair's residual
// ‖A x − θ x‖ ≤ 1e-14·|θ|, which puts λ₁ and v₁ at the accuracy of the dense solver on these matrices. Where
// it does not converge within its restarts, or n < 3 (Lanczos needs nev = 2 < ncv ≤ n), the full
// decomposition (Eigen's SelfAdjointEigenSolver) gives them.
struct TopEigenpairs {
  double lambda1 = 0.0, lambda2 = 0.0;
  Eigen::VectorXd v1;
};
TopEigenpairs top_eigenpairs(const Eigen::MatrixXd& A) {
  const auto n = A.rows();
  TopEigenpairs out;
  if (n >= 3) {
    Spectra::DenseSymMatProd<double> op(A);
    Spectra::SymEigsSolver<Spectra::DenseSymMatProd<double>> lanczos(op, 2, std::min<Eigen::Index>(n, 20));
    lanczos.init();
    lanczos.compute(Spectra::SortRule::LargestAlge, 50, 1e-14);
    if (lanczos.info() == Spectra::CompInfo::Successful) {
      const Eigen::VectorXd values = lanczos.eigenvalues();  // descending
      out.lambda1 = values(0);
      out.lambda2 = values(1);
      out.v1 = lanczos.eigenvectors().col(0);
      return out;
    }
  }
  // eigenvalues sorted ascending
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
  if (eig.info() != Eigen::Success)
    throw std::runtime_error("scgp: the eigen decomposition of A did not converge");
  out.lambda1 = eig.eigenvalues()(n - 1);
  out.lambda2 = n >= 2 ? eig.eigenvalues()(n - 2) : 0.0;
  out.v1 = eig.eigenvectors().col(n - 1);
  return out;
}
}  // namespace

void validate_gamma(double gamma, const char* who) {
  if (!(gamma > 0.0) || !std::isfinite(gamma))
    throw std::invalid_argument(
        fmt::format("{}: the consistency threshold gamma must be > 0 and finite (got {:g})", who, gamma));
}

void validate_consistency_matrix(const ConsistencyMatrix& Q, const char* who) {
  if (Q.n <= 0) {
    throw std::invalid_argument(
        fmt::format("{}: the consistency matrix has n = {} candidates (need at least 1)", who, Q.n));
  }
  const std::size_t n = static_cast<std::size_t>(Q.n);
  if (Q.q.size() != n * n) {
    throw std::invalid_argument(
        fmt::format("{}: the consistency matrix has {} entries, expected n*n = {} "
                    "(n = {})",
                    who, Q.q.size(), n * n, Q.n));
  }
  for (std::size_t u = 0; u < n; ++u) {
    for (std::size_t v = 0; v < n; ++v) {
      const double x = Q.q[u * n + v];
      if (std::isnan(x) || (u != v && x < 0.0))
        throw std::invalid_argument(
            fmt::format("{}: q[{}][{}] = {:g} is {}", who, u, v, x,
                        std::isnan(x) ? "NaN" : "negative (a squared Mahalanobis distance is >= 0)"));
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------
// PCM (eq. 2.5 solved as a maximum clique, §2.5)

Selection select_pcm(const ConsistencyMatrix& Q, double gamma, CliqueAlgorithm algorithm,
                     const CliqueOptions& options) {
  validate_consistency_matrix(Q, "select_pcm");
  validate_gamma(gamma, "select_pcm");
  const auto t0 = Clock::now();
  // Consistency graph of §2.5: edge {u, v} iff q_uv <= γ and q_vu <= γ; a clique is a pairwise internally
  // consistent set (eq. 2.3), and the maximum clique solves eq. 2.5.
  const ConsistencyGraph g = ConsistencyGraph::from_threshold(Q.n, Q.q, gamma);
  const CliqueResult r = maximum_clique(g, algorithm, options);
  Selection s;
  s.time_s = seconds_since(t0);
  s.selected = r.clique;
  s.search = r;
  return s;
}

void DensestSelectOptions::validate() const {
  if (!(affinity_scale == 0.0 || (std::isfinite(affinity_scale) && affinity_scale > 0.0)))
    throw std::invalid_argument(
        fmt::format("DensestSelectOptions: affinity_scale must be 0 (binary) or > 0 and finite (got {:g})",
                    affinity_scale));
  solver.validate();
}

Selection select_densest(const ConsistencyMatrix& Q, double gamma, const DensestSelectOptions& options) {
  validate_consistency_matrix(Q, "select_densest");
  validate_gamma(gamma, "select_densest");
  options.validate();
  const auto t0 = Clock::now();
  const ConsistencyGraph g = ConsistencyGraph::from_threshold(Q.n, Q.q, gamma);
  DensestResult r;
  if (options.affinity_scale == 0.0) {
    r = densest_subgraph(g, options.solver);
  } else {
    const auto n = static_cast<std::size_t>(Q.n);
    std::vector<double> affinity(n * n, 0.0);
    for (std::size_t u = 0; u < n; ++u)
      for (std::size_t v = 0; v < n; ++v)
        if (u != v && g.adjacent(static_cast<int>(u), static_cast<int>(v)))
          affinity[u * n + v] =
              pair_affinity(Q, static_cast<int>(u), static_cast<int>(v), options.affinity_scale);
    r = densest_subgraph(g, affinity, options.solver);
  }
  Selection s;
  s.time_s = seconds_since(t0);
  s.selected = r.selection;
  s.raw_size = static_cast<int>(r.raw.size());
  s.violations = r.violations;
  return s;
}

// ---------------------------------------------------------------------------------------------------------------
// RANSAC (§2.7): every candidate is tried as the single-sample model; its support is the set of candidates
// likely given it. No pairwise check among the supporters.

Selection select_ransac(const ConsistencyMatrix& Q, double gamma) {
  validate_consistency_matrix(Q, "select_ransac");
  validate_gamma(gamma, "select_ransac");
  const auto t0 = Clock::now();
  const int n = Q.n;
  int best_u = 0, best_count = -1;
  for (int u = 0; u < n; ++u) {
    const double* row = Q.q.data() + static_cast<std::size_t>(u) * n;
    int count = 1;  // u itself
    for (int v = 0; v < n; ++v) count += (v != u && row[v] <= gamma) ? 1 : 0;
    if (count > best_count) {  // strict: ties keep the smallest u
      best_count = count;
      best_u = u;
    }
  }
  Selection s;
  const double* row = Q.q.data() + static_cast<std::size_t>(best_u) * n;
  for (int v = 0; v < n; ++v)
    if (v == best_u || row[v] <= gamma) s.selected.push_back(v);
  s.time_s = seconds_since(t0);
  return s;
}

// ---------------------------------------------------------------------------------------------------------------
// SCGP (Olson et al. 2005)

namespace {
constexpr core::NameTable<ScgpDiscretization, 2> kScgpDiscretizationNames{
    "pcm::ScgpDiscretization",
    {{{ScgpDiscretization::dot_product, "dot_product"}, {ScgpDiscretization::rayleigh, "rayleigh"}}}};
}  // namespace

std::string_view to_string(ScgpDiscretization v) { return kScgpDiscretizationNames.name(v); }
ScgpDiscretization scgp_discretization_from_string(std::string_view s) {
  return kScgpDiscretizationNames.parse(s);
}

void ScgpOptions::validate() const {
  if (!(affinity_scale > 0.0) || !std::isfinite(affinity_scale))
    throw std::invalid_argument(
        fmt::format("ScgpOptions::affinity_scale must be > 0 and finite (got {:g})", affinity_scale));
  if (discretization != ScgpDiscretization::dot_product && discretization != ScgpDiscretization::rayleigh) {
    throw std::invalid_argument("ScgpOptions::discretization is not a ScgpDiscretization value");
  }
  if (!(min_eigen_ratio == 0.0 || (min_eigen_ratio >= 1.0 && std::isfinite(min_eigen_ratio))))
    throw std::invalid_argument(
        fmt::format("ScgpOptions::min_eigen_ratio must be 0 (test off) or a finite ratio >= 1 (got {:g})",
                    min_eigen_ratio));
}

ScgpResult scgp(const ConsistencyMatrix& Q, const ScgpOptions& options) {
  validate_consistency_matrix(Q, "scgp");
  options.validate();
  const auto t0 = Clock::now();
  const int n = Q.n;

  // Pairwise affinity (the "consistency" entries of Olson's adjacency matrix), symmetric by construction.
  Eigen::MatrixXd A(n, n);
  for (int u = 0; u < n; ++u) {
    A(u, u) = 1.0;
    for (int v = u + 1; v < n; ++v) {
      const double a = pair_affinity(Q, u, v, options.affinity_scale);
      A(u, v) = a;
      A(v, u) = a;
    }
  }

  ScgpResult out;
  // λ(v) = vᵀAv / vᵀv is maximised over real v by the dominant eigenvector.
  auto top = top_eigenpairs(A);
  Eigen::VectorXd& v1 = top.v1;
  if (v1.sum() < 0.0) v1 = -v1;  // A >= 0 elementwise: the Perron vector can be taken non-negative
  out.lambda1 = top.lambda1;
  out.lambda2 = top.lambda2;
  out.eigen_ratio = out.lambda2 > 0.0 ? out.lambda1 / out.lambda2 : std::numeric_limits<double>::infinity();
  out.eigenvector.assign(v1.data(), v1.data() + n);

  // Threshold sets S_k: the k largest entries of v₁ (ties: lower index first).
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  // std::sort with the index as tie-break = a stable sort of 0..n-1 (std::stable_sort trips clang-19's
  // deprecation of libstdc++ 12's get_temporary_buffer under -Werror, docs/TOOLCHAIN.md).
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return v1(a) > v1(b) || (v1(a) == v1(b) && a < b); });

  int best_k = 1;
  double best_score = -std::numeric_limits<double>::infinity();
  double prefix = 0.0;  // dot product: Σ v₁ over S_k; rayleigh: wᵀAw over S_k
  for (int k = 1; k <= n; ++k) {
    const int i = order[k - 1];
    double score;
    if (options.discretization == ScgpDiscretization::dot_product) {
      prefix += v1(i);
      score = prefix / std::sqrt(static_cast<double>(k));
    } else {
      double cross = 0.0;
      for (int j = 0; j < k - 1; ++j) cross += A(i, order[j]);
      prefix += 2.0 * cross + A(i, i);
      score = prefix / static_cast<double>(k);
    }
    if (score > best_score) {  // strict: ties keep the smaller cluster
      best_score = score;
      best_k = k;
    }
  }
  std::vector<int> cluster(order.begin(), order.begin() + best_k);
  std::sort(cluster.begin(), cluster.end());
  out.cluster_size = best_k;
  out.confident = options.min_eigen_ratio == 0.0 || out.eigen_ratio >= options.min_eigen_ratio;
  if (out.confident) out.selection.selected = cluster;
  out.selection.time_s = seconds_since(t0);

  // Diagnostics (not timed): the average affinity λ(w) of the discretised cluster.
  double w = 0.0;
  for (int a : cluster)
    for (int b : cluster) w += A(a, b);
  out.objective = w / static_cast<double>(best_k);
  return out;
}

Selection select_scgp(const ConsistencyMatrix& Q, const ScgpOptions& options) {
  return scgp(Q, options).selection;
}

}  // namespace keel::pcm
