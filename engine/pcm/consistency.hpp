// Pairwise consistency of inter-robot loop closures (thesis §2.4.1, eq. 2.4, and §2.6).
//
// Two robots a and b have solved their local pose graphs independently. A candidate inter-robot measurement
// z_ik ≈ (T^a_i)⁻¹ T^b_k is the pose of robot b's pose k in the frame of robot a's pose i. Two candidates
// u = z_ik and v = z_jl close the loop  b_k → a_i → a_j → b_l → b_k:
//
//     L_uv = z_ik⁻¹ · x̂^a_ij · z_jl · x̂^b_lk,      ε_uv = Log(L_uv)                          (eq. 2.4)
//
// where x̂^a_ij = (T^a_i)⁻¹ T^a_j and x̂^b_lk = (T^b_l)⁻¹ T^b_k are relative poses from the local solutions.
// With no noise L_uv is the identity. Every uncertain quantity X here is a left perturbation in the Lie
// algebra, X = exp(δ) X̄ with δ ~ N(0, Σ) (thesis eq. 5.14), so to first order
//
//     ε_uv ≈ J_l⁻¹(ε) [ −Ad(z_ik⁻¹) δ_u + Ad(z_ik⁻¹) δ_ij + Ad(z_ik⁻¹ x̂_ij) δ_v + Ad(z_ik⁻¹ x̂_ij z_jl) δ_lk ]
//
// and Σ_uv = J Σ Jᵀ with Σ = blockdiag(Σ_u, Σ_ij, Σ_v, Σ_lk) (§2.6; the four are independent: the two
// measurements are independent of each other and of the maps, and the two maps were solved separately).
// The relative poses take their covariance from the joint marginal of (ξ_i, ξ_j) (thesis ch. 5,
// eq. 5.48/5.51):
//
//     x̂_ij perturbed = T_i⁻¹ exp(−ξ_i) exp(ξ_j) T_j  ⇒  δ_ij = Ad(T_i⁻¹)(ξ_j − ξ_i),
//     Σ_ij = Ad(T_i⁻¹) (Σ_ii + Σ_jj − Σ_ij − Σ_ji) Ad(T_i⁻¹)ᵀ            (Composition::joint)
//     Σ_ij = Ad(T_i⁻¹) (Σ_ii + Σ_jj) Ad(T_i⁻¹)ᵀ                          (Composition::independent)
//
// The independent variant composes the two poses as if uncorrelated (the cross-covariance dropped); it is
// kept as an ablation so the difference can be measured (ch2_table2_1_city and ch2_fig2_4_threshold_sweep).
//
// The consistency measure stored in Q is the SQUARED Mahalanobis distance q_uv = ε_uvᵀ Σ_uv⁻¹ ε_uv (the
// thesis writes the norm ‖ε‖_Σ; squaring keeps the χ² scale). For inlier pairs q_uv ~ χ²(dof), dof = 3
// (SE(2)) or 6 (SE(3)). The loop traced from v, L_vu = x̂_lk L_uv⁻¹ x̂_lk⁻¹, gives the same distance to first
// order in ε but not exactly (J_l⁻¹(−ε) ≠ J_l⁻¹(ε)), so both q_uv and q_vu are computed and Q is in general
// slightly asymmetric; the consistency graph keeps {u, v} only if both are within the threshold (thesis §2.5
// and Fig. 2.1 D).
//
// Threshold (documented reading of the thesis's "γ corresponding to 11 % likelihood"): a pair is consistent
// when the χ² tail probability of q_uv is at least p, i.e.  q_uv ≤ γ(p) = F⁻¹_χ²(dof)(1 − p). p is kept in
// each experiment's config; a sweep over p covers the other reading (cdf ≤ p) as well, since that is 1 − p
// here.
#pragma once

#include <limits>
#include <tuple>
#include <string>
#include <string_view>
#include <vector>

#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"
#include "core/fields.hpp"

namespace keel::pcm {

enum class Composition {
  joint,        // relative poses from the joint marginal, cross-covariance included (thesis ch. 5)
  independent,  // cross-covariance dropped (the poses composed as if independent)
};
std::string_view to_string(Composition c);
Composition composition_from_string(
    std::string_view s);  // "joint" | "independent"; throws std::invalid_argument

// A candidate inter-robot loop closure z ≈ (T^a_i)⁻¹ T^b_k with the covariance of its left perturbation
// (z = exp(n) z̄, n ~ N(0, covariance)).
template <class G>
struct InterRobotMeasurement {
  int pose_a = 0;  // i, index into robot a's poses
  int pose_b = 0;  // k, index into robot b's poses
  G z;
  typename G::Jacobian covariance = G::Jacobian::Identity();
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(pose_a, pose_b, z, covariance)
};
using InterRobotMeasurement2 = InterRobotMeasurement<lie::SE2>;
using InterRobotMeasurement3 = InterRobotMeasurement<lie::SE3>;

// Left-perturbation covariance of a measurement whose noise is given, as in every pose-graph file, by the
// information Ω of the residual r = ρ(z⁻¹ T_i⁻¹ T_j) (graph/pose_graph.hpp). To first order z = exp(−Ad(z) r)
// z̄, so Σ = Ad(z) Ω⁻¹ Ad(z)ᵀ. Throws std::invalid_argument if Ω is not symmetric positive definite.
// Residual information Ω of r = ρ(z⁻¹ T_i⁻¹ T_j) from the left-perturbation covariance Σ of z: the inverse of
// left_covariance_from_information, Ω = (Ad(z)⁻¹ Σ Ad(z)⁻ᵀ)⁻¹. Throws std::invalid_argument
// if Σ is not finite, symmetric and positive definite.
lie::Mat3 information_from_left_covariance(const lie::SE2& z, const lie::Mat3& covariance);
lie::Mat6 information_from_left_covariance(const lie::SE3& z, const lie::Mat6& covariance);

lie::Mat3 left_covariance_from_information(const lie::SE2& z, const lie::Mat3& information);
lie::Mat6 left_covariance_from_information(const lie::SE3& z, const lie::Mat6& information);

// One robot's solved local map as the metric needs it: the solution poses and the joint marginal covariance
// (left perturbation, as keel::cov::MarginalCovariance::joint returns it) of the poses in `ids`, blocks in
// the order of `ids`. Only the poses that some candidate touches need to be listed.
template <class G>
struct LocalMap {
  std::vector<G> poses;  // the local solution, all poses
  std::vector<int> ids;  // distinct pose indices covered by `joint`
  lie::MatX joint;       // (dof·ids.size())² joint covariance of (ξ_ids[0], ξ_ids[1], …)
};
using LocalMap2 = LocalMap<lie::SE2>;
using LocalMap3 = LocalMap<lie::SE3>;

// Loop error of one pair and what it is made of (for tests and diagnostics).
template <class G>
struct LoopError {
  typename G::Tangent epsilon;                // ε_uv = Log(L_uv)
  typename G::Jacobian covariance;            // Σ_uv = J Σ Jᵀ
  typename G::Jacobian J_u, J_ij, J_v, J_lk;  // ∂ε/∂δ of each of the four inputs
  double q = 0.0;                             // ε ᵀ Σ_uv⁻¹ ε
};

// The loop error of eq. 2.4 for known inputs. Covariances must be symmetric PSD and Σ_uv positive definite;
// otherwise (or for non-finite entries) throws std::invalid_argument naming the input.
template <class G>
LoopError<G> loop_error(const G& z_u, const typename G::Jacobian& cov_u, const G& x_ij,
                        const typename G::Jacobian& cov_ij, const G& z_v, const typename G::Jacobian& cov_v,
                        const G& x_lk, const typename G::Jacobian& cov_lk);

// x̂_ij = T_i⁻¹ T_j and its left-perturbation covariance from the joint marginal blocks (see the header
// comment).
template <class G>
struct RelativePose {
  G x;
  typename G::Jacobian covariance;
};
template <class G>
RelativePose<G> relative_pose(const G& T_i, const G& T_j, const typename G::Jacobian& cov_ii,
                              const typename G::Jacobian& cov_jj, const typename G::Jacobian& cov_ij,
                              Composition composition);

// The n×n matrix Q of consistency measures (thesis §2.5), row-major, q_uv = squared Mahalanobis distance.
struct ConsistencyMatrix {
  int n = 0;
  int dof = 0;            // degrees of freedom of one loop error (1: 1D world, 3: SE(2), 6: SE(3))
  std::vector<double> q;  // n·n, zero diagonal; q[u·n + v] = q_uv (loop traced from u), ≈ q_vu
  double at(int u, int v) const { return q[static_cast<std::size_t>(u) * n + v]; }
};

// γ(p) = F⁻¹_χ²(dof)(1 − p): the largest squared distance whose χ² tail probability is at least p. p in (0,
// 1); throws std::invalid_argument otherwise.
double consistency_threshold(double p, int dof);

struct ConsistencyOptions {
  Composition composition = Composition::joint;
  unsigned threads = 1;  // 0 = keel::core::default_threads(); the result does not depend on it
  // +∞: every ordered pair is evaluated. Finite (a consistency threshold γ, > 0): q_vu (v > u) is not
  // evaluated where q_uv > cutoff, and is set to +∞ there. The pair is inconsistent at every γ ≤ cutoff
  // either way (the graph keeps {u, v} only if q_uv ≤ γ and q_vu ≤ γ), so the consistency graph at such a γ,
  // and every selection made from it, are those of the full matrix; an unevaluated loop's covariance is not
  // checked.
  double cutoff = std::numeric_limits<double>::infinity();
};

// Q for every ordered pair of candidates (eq. 2.4 for each u ≠ v). Throws std::invalid_argument for an empty
// candidate list, a candidate touching a pose outside its map or not in the map's `ids`, a joint covariance
// of the wrong size, non-finite or non-symmetric covariances, or a loop covariance that is not positive
// definite (the message names the candidate(s)).
ConsistencyMatrix consistency_matrix(const LocalMap2& a, const LocalMap2& b,
                                     const std::vector<InterRobotMeasurement2>& candidates,
                                     const ConsistencyOptions& options = {});
ConsistencyMatrix consistency_matrix(const LocalMap3& a, const LocalMap3& b,
                                     const std::vector<InterRobotMeasurement3>& candidates,
                                     const ConsistencyOptions& options = {});

// Q for candidate loop closures of ONE robot (Kimera-RPGO's single-robot case, issue: a robust back end):
// each candidate's pose_a (i) and pose_b (k) both index `map`, z ≈ T_i⁻¹ T_k. The loop of eq. 2.4 is the
// same, L_uv = z_u⁻¹ x̂_ij z_v x̂_lk, but both relative poses now come from one solved map, so they are
// correlated:
//
//     Cov(δ_ij, δ_lk) = Ad(T_i⁻¹) (Σ_jk − Σ_jl − Σ_ik + Σ_il) Ad(T_l⁻¹)ᵀ =: C                (thesis
//     eq. 5.48) Σ_uv = J_u Σ_u J_uᵀ + J_v Σ_v J_vᵀ + J_ij Σ_ij J_ijᵀ + J_lk Σ_lk J_lkᵀ + J_ij C J_lkᵀ + J_lk
//     Cᵀ J_ijᵀ
//
// with Σ_ab the blocks of the map's joint marginal. Composition::independent drops C with the other
// cross-covariances. `map.ids` must cover both ends of every candidate. Throws as the two-map form.
ConsistencyMatrix consistency_matrix(const LocalMap2& map,
                                     const std::vector<InterRobotMeasurement2>& candidates,
                                     const ConsistencyOptions& options = {});
ConsistencyMatrix consistency_matrix(const LocalMap3& map,
                                     const std::vector<InterRobotMeasurement3>& candidates,
                                     const ConsistencyOptions& options = {});

}  // namespace keel::pcm
