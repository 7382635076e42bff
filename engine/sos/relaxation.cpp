#include "sos/relaxation.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include "sos/eigen_sparse.hpp"
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "core/names.hpp"
#include "core/timing.hpp"

namespace keel::sos {

using convex::check_sdp;
using convex::Sdp;
using convex::SdpCheck;
using convex::SdpEntry;
using convex::SdpSolution;
using convex::solve_sdp;

namespace {

constexpr core::NameTable<Structure, 2> kStructureNames{
    "sos::Structure", {{{Structure::dense, "dense"}, {Structure::cliques, "cliques"}}}};

using Mono = std::vector<int>;  // sorted unknown indices, with repetition; {} = 1
using Poly = std::map<Mono, double>;

// Reduction modulo s² = 1 − c² for every pose: while some s appears twice, m = s² m' → m' − c² m'.
class Reducer {
 public:
  explicit Reducer(const std::vector<char>& s_var) : s_var_(s_var) {}

  const Poly& operator()(const Mono& m) {
    if (auto it = cache_.find(m); it != cache_.end()) return it->second;
    Poly out;
    int twice = -1;
    for (std::size_t k = 1; k < m.size(); ++k)
      if (m[k] == m[k - 1] && is_s(m[k])) {
        twice = m[k];
        break;
      }
    if (twice < 0) {
      out[m] = 1.0;
    } else {
      Mono rest = m;
      rest.erase(std::find(rest.begin(), rest.end(), twice));
      rest.erase(std::find(rest.begin(), rest.end(), twice));
      Mono with_c = rest;
      with_c.push_back(twice - 1), with_c.push_back(twice - 1);
      std::sort(with_c.begin(), with_c.end());
      const Poly a = (*this)(rest);  // copies: the cache may rehash
      const Poly b = (*this)(with_c);
      for (const auto& [mono, v] : a) out[mono] += v;
      for (const auto& [mono, v] : b) out[mono] -= v;
    }
    return cache_.emplace(m, std::move(out)).first->second;
  }

  [[nodiscard]] bool is_s(int v) const { return s_var_[static_cast<std::size_t>(v)] != 0; }

 private:
  const std::vector<char>& s_var_;
  std::map<Mono, Poly> cache_;
};

Mono product(const Mono& a, const Mono& b) {
  Mono m(a);
  m.insert(m.end(), b.begin(), b.end());
  std::sort(m.begin(), m.end());
  return m;
}

// Monomials of degree ≤ order in `vars` with no s² factor (the standard monomials modulo the circle).
std::vector<Mono> basis(const std::vector<int>& vars, int order, const Reducer& red) {
  std::vector<Mono> out{Mono{}};
  std::vector<Mono> last{Mono{}};
  for (int d = 1; d <= order; ++d) {
    std::vector<Mono> next;
    for (const Mono& m : last)
      for (int v : vars) {
        if (!m.empty() && v < m.back()) continue;
        if (red.is_s(v) && !m.empty() && m.back() == v) continue;
        Mono n = m;
        n.push_back(v);
        next.push_back(n);
      }
    out.insert(out.end(), next.begin(), next.end());
    last = std::move(next);
  }
  return out;
}

// A quadratic cost ‖a z + r‖² over unknowns z of which some pair up on the circle as (c, s) with s right
// after c, and the unknowns of each moment block.
struct MomentSpec {
  Eigen::SparseMatrix<double> a;
  Eigen::VectorXd r;
  std::vector<char> rotation;  // per unknown: part of a (c, s) pair (|z_v| ≤ 1 on the feasible set)
  std::vector<char> s_var;     // per unknown: the s of a pair
  std::vector<std::vector<int>> blocks;
};

// The full problem (translations and landmarks kept) on the cliques of the chordal extension.
MomentSpec clique_spec(const PlanarProblem& p) {
  MomentSpec m;
  m.a = p.a, m.r = p.r;
  for (int v = 0; v < p.unknowns(); ++v) {
    m.rotation.push_back(p.is_rotation(v) ? 1 : 0);
    m.s_var.push_back(p.is_rotation(v) && v % 4 == 1 ? 1 : 0);
  }
  for (const auto& clique : chordal_cliques(p)) {
    std::vector<int> vars;
    for (int node : clique)
      for (int k = 0; k < p.node_size(node); ++k) vars.push_back(p.node_offset(node) + k);
    std::sort(vars.begin(), vars.end());
    m.blocks.push_back(std::move(vars));
  }
  return m;
}

RelaxationResult relax_moments(const MomentSpec& spec, const RelaxationOptions& o);

struct Eig {
  double top = 0.0, second = 0.0, smallest = 0.0;
  Eigen::VectorXd top_vector;
};
Eig eig(const Eigen::MatrixXd& m) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m);
  const auto n = m.rows();
  Eig e;
  e.top = es.eigenvalues()(n - 1);
  e.second = n > 1 ? es.eigenvalues()(n - 2) : 0.0;
  e.smallest = es.eigenvalues()(0);
  e.top_vector = es.eigenvectors().col(n - 1);
  return e;
}

Eigen::MatrixXd psd_part(const Eigen::MatrixXd& m) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m);
  return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
}

void record(RelaxationResult& out, const SdpSolution& sol, const SdpCheck& chk) {
  out.primal_residual = chk.primal_residual;
  out.relative_gap = chk.relative_gap;
  out.x_min_eigenvalue = chk.x_min_eigenvalue;
  out.s_min_eigenvalue = chk.s_min_eigenvalue;
  out.solver_claims_optimal = sol.claims_optimal;
  out.solver_status = sol.status;
  out.iterations = sol.iterations;
  out.solver_time_s = sol.time_s;
}

// ---- Structure::dense
// ----------------------------------------------------------------------------------------

RelaxationResult relax_dense(const PlanarProblem& p, const RelaxationOptions& o) {
  const auto t0 = core::Clock::now();
  std::vector<int> rot, rest;
  for (int v = 0; v < p.unknowns(); ++v) (p.is_rotation(v) ? rot : rest).push_back(v);
  const auto nk = static_cast<Eigen::Index>(rot.size()) + 1;
  const auto rows = p.a.rows();
  // G = [r, A_rot] (dense), A_T sparse.
  Eigen::MatrixXd g(rows, nk);
  g.col(0) = p.r;
  g.rightCols(nk - 1) = Eigen::MatrixXd(columns_of(p.a, rot));
  Eigen::MatrixXd q = g.transpose() * g;
  if (!rest.empty()) {
    const Eigen::SparseMatrix<double> at = columns_of(p.a, rest);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Eigen::SparseMatrix<double>(at.transpose() * at));
    if (ldlt.info() != Eigen::Success)
      throw std::runtime_error("sos::relax: the translation block is singular (is every pose constrained?)");
    const Eigen::MatrixXd b = at.transpose() * g;
    q -= b.transpose() * ldlt.solve(b);
  }
  q = 0.5 * (q + q.transpose());
  if (o.order > 1) {
    // Higher orders: the moment form over the rotations alone, with the reduced cost written as a sum of
    // squares (q = Lᵀ L from its eigen-decomposition, the rows of L as residuals). Every unknown is on the
    // circle, so the residual correction covers the returned matrices' infeasibility; its sums are evaluated
    // in double without a rounding margin, so the bound is numerical, not proven (linalg/psd_proof.hpp is not
    // used).
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(q);
    const Eigen::MatrixXd l =
        es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
    MomentSpec spec;
    spec.a = l.rightCols(nk - 1).sparseView();
    spec.r = l.col(0);
    spec.blocks.emplace_back();
    for (Eigen::Index k = 0; k + 1 < nk; ++k) {
      spec.rotation.push_back(1);
      spec.s_var.push_back(k % 2 == 1 ? 1 : 0);
      spec.blocks[0].push_back(static_cast<int>(k));
    }
    RelaxationResult out = relax_moments(spec, o);
    // LᵀL ⪰ q when q has (rounding-level) negative eigenvalues: the relaxed cost is then above the true one
    // by at most (1 + Σ (c² + s²)) |λ_min(q)| = poses · |λ_min(q)| on the feasible set.
    const double clipped = es.eigenvalues()(0) < 0.0 ? -es.eigenvalues()(0) : 0.0;
    out.bound_correction += static_cast<double>(p.poses) * clipped;
    out.lower_bound -= static_cast<double>(p.poses) * clipped;
    Eigen::VectorXd z = Eigen::VectorXd::Zero(p.unknowns());
    for (std::size_t k = 0; k < rot.size(); ++k) z(rot[k]) = out.z(static_cast<Eigen::Index>(k));
    out.z = z;
    out.time_s = core::seconds_since(t0);
    return out;
  }
  const double qs = std::max(q.cwiseAbs().maxCoeff(), 1e-300);

  Sdp sdp;
  const int n = static_cast<int>(nk);
  sdp.block_sizes = {n};
  for (int r = 0; r < n; ++r)
    for (int c = 0; c <= r; ++c)
      if (q(r, c) != 0.0) sdp.c.push_back({0, r, c, q(r, c) / qs});
  sdp.a.push_back({{0, 0, 0, 1.0}});
  sdp.b.push_back(1.0);
  for (int i = 1; i < p.poses; ++i) {
    const int ci = 1 + 2 * (i - 1);
    sdp.a.push_back({{0, ci, ci, 1.0}, {0, ci + 1, ci + 1, 1.0}});
    sdp.b.push_back(1.0);
  }
  const SdpSolution sol = solve_sdp(sdp, o.sdp);
  const SdpCheck chk = check_sdp(sdp, sol);

  RelaxationResult out;
  out.structure = Structure::dense;
  out.order = 1;
  record(out, sol, chk);
  out.blocks = 1, out.largest_block = n, out.constraints = sdp.constraints();
  const double trace = static_cast<double>(p.poses);  // X₀₀ + Σ (X_cc + X_ss) at any feasible rank-one X
  // (λ ≥ 0 ? 0 : λ) rather than std::min(0, λ), so that a NaN eigenvalue reaches the bound
  out.bound_correction = -qs * trace * (chk.s_min_eigenvalue >= 0.0 ? 0.0 : chk.s_min_eigenvalue);
  out.lower_bound = qs * chk.dual_objective - out.bound_correction;
  out.value = qs * chk.primal_objective;
  const Eig e = eig(sol.x[0]);
  out.rank_ratio = e.top > 0 ? std::max(0.0, e.second) / e.top : 1.0;
  Eigen::VectorXd u = e.top_vector;
  if (std::abs(u(0)) > 1e-12)
    u /= u(0);
  else
    u = sol.x[0].col(0) / std::max(sol.x[0](0, 0), 1e-300);
  out.z = Eigen::VectorXd::Zero(p.unknowns());
  for (std::size_t k = 0; k < rot.size(); ++k) out.z(rot[k]) = u(static_cast<Eigen::Index>(k) + 1);
  out.time_s = core::seconds_since(t0);
  return out;
}

// ---- Structure::cliques
// --------------------------------------------------------------------------------------

struct MomentProgram {
  Sdp sdp;
  std::vector<Mono> moments;  // moment of SDP variable i
  std::map<Mono, int> index;  // monomial -> SDP variable
};

MomentProgram build_moments(const MomentSpec& spec, int order, bool with_matrices, long max_moments) {
  MomentProgram mp;
  Reducer red(spec.s_var);
  for (std::size_t k = 0; k < spec.blocks.size(); ++k) {
    const std::vector<Mono> bas = basis(spec.blocks[k], order, red);
    const int blk = static_cast<int>(k);
    if (with_matrices) mp.sdp.block_sizes.push_back(static_cast<int>(bas.size()));
    for (std::size_t r = 0; r < bas.size(); ++r)
      for (std::size_t c = 0; c <= r; ++c)
        for (const auto& [mono, coef] : red(product(bas[r], bas[c]))) {
          if (coef == 0.0) continue;
          if (mono.empty()) {
            if (with_matrices) mp.sdp.c.push_back({blk, static_cast<int>(r), static_cast<int>(c), coef});
            continue;
          }
          auto [it, fresh] = mp.index.emplace(mono, static_cast<int>(mp.moments.size()));
          if (fresh) {
            mp.moments.push_back(mono);
            if (static_cast<long>(mp.moments.size()) > max_moments)
              throw std::length_error(fmt::format(
                  "sos::relax: the order-{} moment relaxation has more than {} moments (max_moments)", order,
                  max_moments));
            if (with_matrices) mp.sdp.a.emplace_back();
          }
          // M_k(y) = C_k − Σ y_β A_β with A_β = −(coefficient of y_β)
          if (with_matrices)
            mp.sdp.a[static_cast<std::size_t>(it->second)].push_back(
                {blk, static_cast<int>(r), static_cast<int>(c), -coef});
        }
  }
  return mp;
}

// The moment relaxation of `spec` at `order`; z of the result is over spec's unknowns.
RelaxationResult relax_moments(const MomentSpec& spec, const RelaxationOptions& o) {
  const auto t0 = core::Clock::now();
  MomentProgram mp = build_moments(spec, o.order, true, o.max_moments);
  Reducer red(spec.s_var);
  const auto nu = static_cast<int>(spec.rotation.size());
  // The cost polynomial f = Σ_k (a_kᵀ z + r_k)², reduced.
  Poly f;
  const Eigen::SparseMatrix<double, Eigen::RowMajor> a = spec.a;
  for (Eigen::Index k = 0; k < a.rows(); ++k) {
    std::vector<std::pair<int, double>> row;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(a, k); it; ++it)
      row.emplace_back(static_cast<int>(it.col()), it.value());
    const double rk = spec.r(k);
    f[{}] += rk * rk;
    for (const auto& [u, au] : row) {
      f[{u}] += 2.0 * rk * au;
      for (const auto& [v, av] : row)
        for (const auto& [mono, coef] : red(product({u}, {v}))) f[mono] += au * av * coef;
    }
  }
  double f0 = 0.0, fs = 0.0;
  for (const auto& [mono, v] : f) {
    if (mono.empty())
      f0 = v;
    else
      fs = std::max(fs, std::abs(v));
  }
  fs = std::max(fs, 1e-300);
  mp.sdp.b.assign(mp.moments.size(), 0.0);
  for (const auto& [mono, v] : f) {
    if (mono.empty()) continue;
    auto it = mp.index.find(mono);
    if (it == mp.index.end())
      throw std::logic_error(
          "sos::relax: a cost monomial lies in no moment block (the chordal extension is wrong)");
    mp.sdp.b[static_cast<std::size_t>(it->second)] = -v / fs;
  }
  const SdpSolution sol = solve_sdp(mp.sdp, o.sdp);
  const SdpCheck chk = check_sdp(mp.sdp, sol);

  RelaxationResult out;
  out.structure = o.structure;
  out.order = o.order;
  record(out, sol, chk);
  out.blocks = static_cast<int>(mp.sdp.block_sizes.size());
  out.largest_block = *std::max_element(mp.sdp.block_sizes.begin(), mp.sdp.block_sizes.end());
  out.constraints = mp.sdp.constraints();
  out.moments = static_cast<long>(mp.moments.size());
  out.value = f0 - fs * chk.dual_objective;
  // First-order moments and the monomial bound of the residual correction.
  out.z = Eigen::VectorXd::Zero(nu);
  for (int v = 0; v < nu; ++v)
    if (auto it = mp.index.find(Mono{v}); it != mp.index.end()) out.z(v) = sol.y(it->second);
  double tbound = 1.0;
  for (int v = 0; v < nu; ++v)
    if (!spec.rotation[static_cast<std::size_t>(v)]) tbound = std::max(tbound, 2.0 * std::abs(out.z(v)));
  // SOS side: X projected onto the PSD cone, then f ≥ f₀ − fs ⟨C, X⟩ − fs Σ_β |⟨A_β, X⟩ − b_β| · max|z^β|.
  SdpSolution projected = sol;
  for (auto& x : projected.x) x = psd_part(x);
  double cx = 0.0;
  for (const SdpEntry& e : mp.sdp.c)
    cx +=
        (e.row == e.col ? 1.0 : 2.0) * e.value * projected.x[static_cast<std::size_t>(e.block)](e.row, e.col);
  double correction = 0.0;
  for (std::size_t i = 0; i < mp.moments.size(); ++i) {
    double ax = 0.0;
    for (const SdpEntry& e : mp.sdp.a[i])
      ax += (e.row == e.col ? 1.0 : 2.0) * e.value *
            projected.x[static_cast<std::size_t>(e.block)](e.row, e.col);
    double bound = 1.0;
    for (int v : mp.moments[i])
      if (!spec.rotation[static_cast<std::size_t>(v)]) bound *= tbound;
    correction += std::abs(ax - mp.sdp.b[i]) * bound;
  }
  out.bound_correction = fs * correction;
  out.lower_bound = f0 - fs * cx - out.bound_correction;
  // Rank of every moment block M_k(y) = S_k.
  out.rank_ratio = 0.0;
  for (const auto& s : chk.s) {
    const Eig e = eig(s);
    out.rank_ratio = std::max(out.rank_ratio, e.top > 0 ? std::max(0.0, e.second) / e.top : 1.0);
  }
  out.time_s = core::seconds_since(t0);
  return out;
}

}  // namespace

std::string_view to_string(Structure v) { return kStructureNames.name(v); }
Structure structure_from_string(std::string_view s) { return kStructureNames.parse(s); }

void RelaxationOptions::validate() const {
  if (order < 1 || order > 3)
    throw std::invalid_argument(
        fmt::format("sos::RelaxationOptions: order must be 1, 2 or 3 (got {})", order));
  if (max_moments < 1)
    throw std::invalid_argument(
        fmt::format("sos::RelaxationOptions: max_moments must be >= 1 (got {})", max_moments));
  sdp.validate();
}

std::vector<std::vector<int>> chordal_cliques(const PlanarProblem& p) {
  const int n = p.nodes();
  std::vector<std::set<int>> adj(static_cast<std::size_t>(n));
  for (const Term& t : p.terms)
    if (t.node_a >= 0 && t.node_b >= 0 && t.node_a != t.node_b) {
      adj[static_cast<std::size_t>(t.node_a)].insert(t.node_b);
      adj[static_cast<std::size_t>(t.node_b)].insert(t.node_a);
    }
  // Minimum-degree elimination: the clique of each eliminated node is it and its remaining neighbours.
  std::vector<bool> gone(static_cast<std::size_t>(n), false);
  std::vector<std::vector<int>> cliques;
  for (int step = 0; step < n; ++step) {
    int best = -1;
    for (int v = 0; v < n; ++v)
      if (!gone[static_cast<std::size_t>(v)] &&
          (best < 0 || adj[static_cast<std::size_t>(v)].size() < adj[static_cast<std::size_t>(best)].size()))
        best = v;
    const auto& nb = adj[static_cast<std::size_t>(best)];
    std::vector<int> clique(nb.begin(), nb.end());
    clique.push_back(best);
    std::sort(clique.begin(), clique.end());
    for (int u : nb)
      for (int w : nb)
        if (u != w) adj[static_cast<std::size_t>(u)].insert(w);
    for (int u : nb) adj[static_cast<std::size_t>(u)].erase(best);
    gone[static_cast<std::size_t>(best)] = true;
    cliques.push_back(std::move(clique));
  }
  // Keep the maximal ones.
  std::vector<std::vector<int>> out;
  for (std::size_t i = 0; i < cliques.size(); ++i) {
    bool contained = false;
    for (std::size_t j = 0; j < cliques.size() && !contained; ++j)
      if (i != j && cliques[j].size() >= cliques[i].size() &&
          std::includes(cliques[j].begin(), cliques[j].end(), cliques[i].begin(), cliques[i].end()) &&
          (cliques[j].size() > cliques[i].size() || j < i))
        contained = true;
    if (!contained) out.push_back(cliques[i]);
  }
  return out;
}

long moment_count(const PlanarProblem& p, int order) {
  return static_cast<long>(
      build_moments(clique_spec(p), order, false, std::numeric_limits<long>::max()).moments.size());
}

RelaxationResult relax(const PlanarProblem& p, const RelaxationOptions& o) {
  o.validate();
  if (p.poses < 2) throw std::invalid_argument("sos::relax: the problem has no free pose");
  if (o.structure == Structure::cliques) return relax_moments(clique_spec(p), o);
  return relax_dense(p, o);
}

}  // namespace keel::sos
