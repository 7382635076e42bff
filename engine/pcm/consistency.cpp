// Pairwise consistency measure of eq. 2.4 (thesis §2.4.1) and the matrix Q of §2.5/§2.6. See consistency.hpp
// for the derivation of the first-order loop covariance.
#include "pcm/consistency.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/names.hpp"
#include "core/parallel.hpp"
#include "lie/metrics.hpp"

namespace keel::pcm {

namespace {

template <class M>
bool all_finite(const M& m) {
  return m.allFinite();
}

// Finite and symmetric up to a tolerance relative to the largest entry.
template <class M>
void check_covariance(const M& c, const std::string& what) {
  if (!all_finite(c)) throw std::invalid_argument(fmt::format("{}: covariance has a non-finite entry", what));
  const double scale = c.cwiseAbs().maxCoeff();
  if ((c - c.transpose()).cwiseAbs().maxCoeff() > 1e-9 * std::max(scale, 1e-300))
    throw std::invalid_argument(fmt::format("{}: covariance is not symmetric", what));
}

template <class G>
void check_pose(const G& T, const std::string& what) {
  if (!T.matrix().allFinite())
    throw std::invalid_argument(fmt::format("{}: pose has a non-finite entry", what));
}

}  // namespace

namespace {
constexpr core::NameTable<Composition, 2> kCompositionNames{
    "pcm::Composition", {{{Composition::joint, "joint"}, {Composition::independent, "independent"}}}};
}  // namespace

std::string_view to_string(Composition v) { return kCompositionNames.name(v); }
Composition composition_from_string(std::string_view s) { return kCompositionNames.parse(s); }

template <class G>
static typename G::Jacobian left_covariance_impl(const G& z, const typename G::Jacobian& information) {
  using J = typename G::Jacobian;
  check_covariance(information, "left_covariance_from_information: information");
  const Eigen::LLT<J> llt(information);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("left_covariance_from_information: information is not positive definite");
  const J sigma_r = llt.solve(J::Identity());
  const J ad = z.adjoint();
  const J sigma = ad * sigma_r * ad.transpose();
  return 0.5 * (sigma + sigma.transpose());
}

template <class G>
static typename G::Jacobian info_from_left(const G& z, const typename G::Jacobian& covariance) {
  using J = typename G::Jacobian;
  if (!all_finite(covariance))
    throw std::invalid_argument("information_from_left_covariance: the covariance has non-finite entries");
  const double scale = std::max(1.0, covariance.cwiseAbs().maxCoeff());
  if ((covariance - covariance.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale)
    throw std::invalid_argument("information_from_left_covariance: the covariance is not symmetric");
  const J Ad_inv = z.inverse().adjoint();  // Ad(z)⁻¹ = Ad(z⁻¹)
  J residual_cov = Ad_inv * covariance * Ad_inv.transpose();
  residual_cov = (0.5 * (residual_cov + residual_cov.transpose())).eval();
  Eigen::LLT<J> llt(residual_cov);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("information_from_left_covariance: the covariance is not positive definite");
  J info = llt.solve(J::Identity());
  return (0.5 * (info + info.transpose())).eval();
}

lie::Mat3 information_from_left_covariance(const lie::SE2& z, const lie::Mat3& covariance) {
  return info_from_left(z, covariance);
}
lie::Mat6 information_from_left_covariance(const lie::SE3& z, const lie::Mat6& covariance) {
  return info_from_left(z, covariance);
}

lie::Mat3 left_covariance_from_information(const lie::SE2& z, const lie::Mat3& information) {
  return left_covariance_impl(z, information);
}
lie::Mat6 left_covariance_from_information(const lie::SE3& z, const lie::Mat6& information) {
  return left_covariance_impl(z, information);
}

// relative_pose with T_i⁻¹ and Ad(T_i⁻¹) given: the consistency matrix's loops share them along a row (and
// along a column for the other relative pose), so they are computed once per candidate, not once per loop.
// The same operations in the same order as relative_pose: the same numbers, bit for bit.
template <class G>
RelativePose<G> relative_pose_from(const G& Ti_inv, const typename G::Jacobian& A, const G& T_j,
                                   const typename G::Jacobian& cov_ii, const typename G::Jacobian& cov_jj,
                                   const typename G::Jacobian& cov_ij, Composition composition) {
  typename G::Jacobian S = cov_ii + cov_jj;
  if (composition == Composition::joint) S -= cov_ij + cov_ij.transpose();
  const typename G::Jacobian C = A * S * A.transpose();
  return {Ti_inv * T_j, 0.5 * (C + C.transpose())};  // (a separate target: C = ½(C + Cᵀ) would alias)
}

template <class G>
RelativePose<G> relative_pose(const G& T_i, const G& T_j, const typename G::Jacobian& cov_ii,
                              const typename G::Jacobian& cov_jj, const typename G::Jacobian& cov_ij,
                              Composition composition) {
  // δ_ij = Ad(T_i⁻¹)(ξ_j − ξ_i)  (eq. 5.48/5.51 with the signs of keel::lie::relative).
  const G Ti_inv = T_i.inverse();
  const typename G::Jacobian A = Ti_inv.adjoint();
  typename G::Jacobian S = cov_ii + cov_jj;
  if (composition == Composition::joint) S -= cov_ij + cov_ij.transpose();
  const typename G::Jacobian C = A * S * A.transpose();
  return {Ti_inv * T_j, 0.5 * (C + C.transpose())};  // (a separate target: C = ½(C + Cᵀ) would alias)
}

namespace {

// The loop L = z_u⁻¹ x_ij z_v x_lk (eq. 2.4) and the poses its perturbations pass through: left perturbations
// of the four factors enter L as exp(−Ad(P1) δ_u), exp(Ad(P1) δ_ij), exp(Ad(P2) δ_v), exp(Ad(P3) δ_lk) with
// P1 = z_u⁻¹, P2 = z_u⁻¹ x_ij, P3 = z_u⁻¹ x_ij z_v, and Log(exp(w) L) ≈ Log L + J_l⁻¹(Log L) w.
template <class G>
struct Loop {
  G P1, P2, P3, L;
  Loop(const G& z_u, const G& x_ij, const G& z_v, const G& x_lk)
      : P1(z_u.inverse()), P2(P1 * x_ij), P3(P2 * z_v), L(P3 * x_lk) {}
};

// εᵀ C⁻¹ ε, or NaN with *ok false when the LLT of C fails (C not positive definite).
template <class G>
double mahalanobis(const typename G::Jacobian& C, const typename G::Tangent& epsilon, bool* ok) {
  const Eigen::LLT<typename G::Jacobian> llt(C);
  *ok = llt.info() == Eigen::Success;
  return *ok ? epsilon.dot(llt.solve(epsilon)) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

// q = εᵀ C⁻¹ ε of the loop, for the consistency matrix, without its Jacobians. With
// w = −Ad(P1) δ_u + Ad(P1) δ_ij + Ad(P2) δ_v + Ad(P3) δ_lk the loop's covariance is
// C = J_l⁻¹(ε) M J_l⁻ᵀ(ε), M = Cov(w), and J_l⁻¹(ε)⁻¹ ε = J_l(ε) ε = ε (the left Jacobian is
// Σ ad_ε^n / (n + 1)! and ad_ε ε = 0), so q = εᵀ M⁻¹ ε: neither J_l⁻¹ nor the four Jacobians are formed.
// Equal to loop_error's q up to rounding; C is positive definite exactly when M is (congruent).
template <class G>
static double loop_q_unchecked(const G& z_u, const typename G::Jacobian& cov_u, const G& x_ij,
                               const typename G::Jacobian& cov_ij, const G& z_v,
                               const typename G::Jacobian& cov_v, const G& x_lk,
                               const typename G::Jacobian& cov_lk, bool* ok,
                               const typename G::Jacobian* cross_ij_lk = nullptr) {
  using J = typename G::Jacobian;
  const Loop<G> loop(z_u, x_ij, z_v, x_lk);
  const J A1 = loop.P1.adjoint(), A2 = loop.P2.adjoint(), A3 = loop.P3.adjoint();
  J M = A1 * (cov_u + cov_ij) * A1.transpose() + A2 * cov_v * A2.transpose() + A3 * cov_lk * A3.transpose();
  if (cross_ij_lk != nullptr) {  // Cov(δ_ij, δ_lk) of two relative poses of one map (consistency.hpp)
    const J K = A1 * *cross_ij_lk * A3.transpose();
    M += K + K.transpose();
  }
  const J Ms = 0.5 * (M + M.transpose());
  return mahalanobis<G>(Ms, loop.L.log(), ok);
}

template <class G>
LoopError<G> loop_error(const G& z_u, const typename G::Jacobian& cov_u, const G& x_ij,
                        const typename G::Jacobian& cov_ij, const G& z_v, const typename G::Jacobian& cov_v,
                        const G& x_lk, const typename G::Jacobian& cov_lk) {
  check_pose(z_u, "loop_error: z_u");
  check_pose(x_ij, "loop_error: x_ij");
  check_pose(z_v, "loop_error: z_v");
  check_pose(x_lk, "loop_error: x_lk");
  check_covariance(cov_u, "loop_error: z_u");
  check_covariance(cov_ij, "loop_error: x_ij");
  check_covariance(cov_v, "loop_error: z_v");
  check_covariance(cov_lk, "loop_error: x_lk");
  using J = typename G::Jacobian;
  const Loop<G> loop(z_u, x_ij, z_v, x_lk);
  LoopError<G> e;
  e.epsilon = loop.L.log();
  const J Jinv = G::left_jacobian_inverse(e.epsilon);
  const J A1 = Jinv * loop.P1.adjoint();
  e.J_u = -A1;
  e.J_ij = A1;
  e.J_v = Jinv * loop.P2.adjoint();
  e.J_lk = Jinv * loop.P3.adjoint();
  const J C = e.J_u * cov_u * e.J_u.transpose() + e.J_ij * cov_ij * e.J_ij.transpose() +
              e.J_v * cov_v * e.J_v.transpose() + e.J_lk * cov_lk * e.J_lk.transpose();
  e.covariance = 0.5 * (C + C.transpose());
  bool ok = false;
  e.q = mahalanobis<G>(e.covariance, e.epsilon, &ok);
  if (!ok) throw std::invalid_argument("loop_error: the loop covariance J Σ Jᵀ is not positive definite");
  return e;
}

double consistency_threshold(double p, int dof) {
  if (!(p > 0.0 && p < 1.0))
    throw std::invalid_argument(fmt::format("consistency_threshold: p must be in (0, 1) (got {:g})", p));
  if (dof < 1)
    throw std::invalid_argument(fmt::format("consistency_threshold: dof must be >= 1 (got {})", dof));
  return lie::chi2_quantile(1.0 - p, static_cast<double>(dof));
}

namespace {

// Index of every pose of a local map inside its `ids` list (−1 if absent), after validating the map.
template <class G>
std::vector<int> index_map(const LocalMap<G>& m, const char* name) {
  constexpr int d = G::DoF;
  const std::string who =
      *name ? fmt::format("consistency_matrix: map {}", name) : "consistency_matrix: the map";
  std::vector<int> index(m.poses.size(), -1);
  for (std::size_t s = 0; s < m.ids.size(); ++s) {
    const int id = m.ids[s];
    if (id < 0 || static_cast<std::size_t>(id) >= m.poses.size())
      throw std::invalid_argument(
          fmt::format("{}: covered pose id {} is outside its {} poses", who, id, m.poses.size()));
    if (index[id] != -1)
      throw std::invalid_argument(fmt::format("{}: pose id {} listed twice in ids", who, id));
    index[id] = static_cast<int>(s);
    check_pose(m.poses[id], fmt::format("{} pose {}", who, id));
  }
  const auto need = static_cast<Eigen::Index>(d * m.ids.size());
  if (m.joint.rows() != need || m.joint.cols() != need)
    throw std::invalid_argument(
        fmt::format("{}: joint covariance is {}x{}, expected {}x{} ({} per covered "
                    "pose)",
                    who, m.joint.rows(), m.joint.cols(), need, need, d));
  check_covariance(m.joint, fmt::format("{} joint marginal", who));
  return index;
}

// `same_map`: a and b are one robot's map (both ends of every candidate in it), so the two relative poses
// of a loop are correlated and Σ_uv carries their cross-covariance (consistency.hpp, the one-map form).
template <class G>
ConsistencyMatrix consistency_matrix_impl(const LocalMap<G>& a, const LocalMap<G>& b,
                                          const std::vector<InterRobotMeasurement<G>>& candidates,
                                          const ConsistencyOptions& options, bool same_map) {
  using J = typename G::Jacobian;
  constexpr int d = G::DoF;
  if (candidates.empty()) throw std::invalid_argument("consistency_matrix: the candidate set is empty");
  if (!(options.cutoff > 0.0))
    throw std::invalid_argument(fmt::format(
        "consistency_matrix: ConsistencyOptions::cutoff must be > 0 (+inf: none; got {})", options.cutoff));
  const auto ia = index_map(a, same_map ? "" : "a");
  const auto ib = same_map ? ia : index_map(b, "b");
  const char* robot_a = same_map ? "the map (its end i)" : "robot a";
  const char* robot_b = same_map ? "the map (its end k)" : "robot b";
  const int n = static_cast<int>(candidates.size());
  for (int u = 0; u < n; ++u) {
    const auto& c = candidates[u];
    const std::string who = fmt::format("consistency_matrix: candidate {}", u);
    if (c.pose_a < 0 || static_cast<std::size_t>(c.pose_a) >= a.poses.size())
      throw std::invalid_argument(fmt::format("{} touches pose {} of {}, which has {} poses", who, c.pose_a,
                                              robot_a, a.poses.size()));
    if (c.pose_b < 0 || static_cast<std::size_t>(c.pose_b) >= b.poses.size())
      throw std::invalid_argument(fmt::format("{} touches pose {} of {}, which has {} poses", who, c.pose_b,
                                              robot_b, b.poses.size()));
    if (ia[c.pose_a] < 0)
      throw std::invalid_argument(fmt::format(
          "{}: pose {} of {} has no joint marginal (not in LocalMap::ids)", who, c.pose_a, robot_a));
    if (ib[c.pose_b] < 0)
      throw std::invalid_argument(fmt::format(
          "{}: pose {} of {} has no joint marginal (not in LocalMap::ids)", who, c.pose_b, robot_b));
    check_pose(c.z, fmt::format("{} measurement", who));
    check_covariance(c.covariance, who);
  }
  auto block = [](const LocalMap<G>& m, int s, int t) -> J {
    return m.joint.template block<d, d>(d * s, d * t);
  };

  ConsistencyMatrix Q;
  Q.n = n;
  Q.dof = d;
  Q.q.assign(static_cast<std::size_t>(n) * n, 0.0);
  // Every ordered pair (u, v), u ≠ v, traces its own loop from u (thesis Fig. 2.1 D: the graph keeps an edge
  // only if q_uv and q_vu are both within the threshold). Rows are independent and processed in parallel.
  std::vector<int> failed(static_cast<std::size_t>(n) * n, 0);
  // T_l⁻¹ and Ad(T_l⁻¹) of each candidate's end l in map b: the second relative pose of every loop through
  // it.
  std::vector<G> Tl_inv(static_cast<std::size_t>(n));
  std::vector<J> Al(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) {
    Tl_inv[v] = b.poses[candidates[v].pose_b].inverse();
    Al[v] = Tl_inv[v].adjoint();
  }
  // Two passes, each row by row: q_uv for v > u, then q_uv for v < u, skipped (+∞) where q_vu exceeds the
  // cutoff (ConsistencyOptions::cutoff). With no cutoff both passes evaluate every pair, as one pass would.
  const bool cut = std::isfinite(options.cutoff);
  for (const bool upper : {true, false})
    core::parallel_for(
        static_cast<std::size_t>(n),
        [&](std::size_t row) {
          const int u = static_cast<int>(row);
          const auto& cu = candidates[u];
          const int i = cu.pose_a, k = cu.pose_b;
          const int si = ia[i], sk = ib[k];
          const J Sii = block(a, si, si), Skk = block(b, sk, sk);
          const G Ti_inv = a.poses[i].inverse();
          const J Ai = Ti_inv.adjoint();
          for (int v = upper ? u + 1 : 0; v < (upper ? n : u); ++v) {
            const std::size_t at = static_cast<std::size_t>(u) * n + v;
            if (!upper && cut && Q.q[static_cast<std::size_t>(v) * n + u] > options.cutoff) {
              Q.q[at] = std::numeric_limits<double>::infinity();
              continue;
            }
            const auto& cv = candidates[v];
            const int j = cv.pose_a, l = cv.pose_b;
            const int sj = ia[j], sl = ib[l];
            const auto xij = relative_pose_from(Ti_inv, Ai, a.poses[j], Sii, block(a, sj, sj),
                                                block(a, si, sj), options.composition);
            const auto xlk = relative_pose_from(Tl_inv[v], Al[v], b.poses[k], block(b, sl, sl), Skk,
                                                block(b, sl, sk), options.composition);
            bool ok = false;
            J cross;
            const bool correlated = same_map && options.composition == Composition::joint;
            if (correlated)  // Ad(T_i⁻¹)(Σ_jk − Σ_jl − Σ_ik + Σ_il)Ad(T_l⁻¹)ᵀ (one map: b is a)
              cross = Ai * (block(a, sj, sk) - block(a, sj, sl) - block(a, si, sk) + block(a, si, sl)) *
                      Al[v].transpose();
            const double q = loop_q_unchecked(cu.z, cu.covariance, xij.x, xij.covariance, cv.z, cv.covariance,
                                              xlk.x, xlk.covariance, &ok, correlated ? &cross : nullptr);
            if (!ok) failed[at] = 1;
            Q.q[at] = q;
          }
        },
        options.threads);
  for (int u = 0; u < n; ++u)
    for (int v = 0; v < n; ++v)
      if (failed[static_cast<std::size_t>(u) * n + v])
        throw std::invalid_argument(
            fmt::format("consistency_matrix: candidates {} and {}: the loop covariance J Σ Jᵀ is not "
                        "positive definite (zero or degenerate measurement covariances?)",
                        u, v));
  return Q;
}

}  // namespace

ConsistencyMatrix consistency_matrix(const LocalMap2& a, const LocalMap2& b,
                                     const std::vector<InterRobotMeasurement2>& candidates,
                                     const ConsistencyOptions& options) {
  return consistency_matrix_impl(a, b, candidates, options, false);
}
ConsistencyMatrix consistency_matrix(const LocalMap3& a, const LocalMap3& b,
                                     const std::vector<InterRobotMeasurement3>& candidates,
                                     const ConsistencyOptions& options) {
  return consistency_matrix_impl(a, b, candidates, options, false);
}
ConsistencyMatrix consistency_matrix(const LocalMap2& map,
                                     const std::vector<InterRobotMeasurement2>& candidates,
                                     const ConsistencyOptions& options) {
  return consistency_matrix_impl(map, map, candidates, options, true);
}
ConsistencyMatrix consistency_matrix(const LocalMap3& map,
                                     const std::vector<InterRobotMeasurement3>& candidates,
                                     const ConsistencyOptions& options) {
  return consistency_matrix_impl(map, map, candidates, options, true);
}

template LoopError<lie::SE2> loop_error(const lie::SE2&, const lie::Mat3&, const lie::SE2&, const lie::Mat3&,
                                        const lie::SE2&, const lie::Mat3&, const lie::SE2&, const lie::Mat3&);
template LoopError<lie::SE3> loop_error(const lie::SE3&, const lie::Mat6&, const lie::SE3&, const lie::Mat6&,
                                        const lie::SE3&, const lie::Mat6&, const lie::SE3&, const lie::Mat6&);
template RelativePose<lie::SE2> relative_pose(const lie::SE2&, const lie::SE2&, const lie::Mat3&,
                                              const lie::Mat3&, const lie::Mat3&, Composition);
template RelativePose<lie::SE3> relative_pose(const lie::SE3&, const lie::SE3&, const lie::Mat6&,
                                              const lie::Mat6&, const lie::Mat6&, Composition);

}  // namespace keel::pcm
