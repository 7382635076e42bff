// keel::merge — a robust back end for one or several robots (Kimera-RPGO's setting, with the thesis's
// guarantees): each robot's odometry (every edge between consecutive poses, i → i + 1, of its own graph) is
// trusted, and every other edge is a candidate loop closure: a robot's own non-consecutive edges
// (intra-robot) and the inter-robot candidates given apart. Candidates are grouped by the robots they join
// (one group per robot and per pair of robots); in each group their pairwise consistency is measured in the
// robots' odometry maps with the joint marginals (thesis eq. 2.4: two maps for a pair of robots,
// pcm::consistency_matrix; one map, whose two relative poses per loop are correlated, for a robot's own
// closures) and the largest consistent set is selected (eq. 2.5). All robots' odometry and the kept closures
// are then solved together by the certified solver (pgo::solve_certified), whose certificate or proven gap
// comes with the answer. `keel robust`, the Python module (app::robust) and the ext_robust_backend study run
// it.
#pragma once

#include <functional>
#include <limits>
#include <string_view>
#include <vector>

#include "graph/pose_graph.hpp"
#include "merge/merge.hpp"
#include "pcm/clique.hpp"
#include "pcm/consistency.hpp"
#include "pcm/selection.hpp"
#include "pgo/certified.hpp"

namespace keel::merge {

/// How each group's consistent set is chosen: the exact maximum clique (proven, or stopped at the time limit
/// with its bound), the greedy heuristic (pcm::CliqueAlgorithm::heuristic), the densest-subgraph selector
/// (pcm::select_densest, CLIPPER's relaxation; its bound the heuristic's degeneracy bound), or by size:
/// exact up to RobustOptions::exact_up_to candidates in the group, densest beyond.
enum class RobustSelector { automatic, exact, heuristic, densest };
[[nodiscard]] std::string_view to_string(RobustSelector s);
[[nodiscard]] RobustSelector robust_selector_from_string(std::string_view text);  // "auto" | "exact" | …

/// The residual check's statistic for a kept closure at the solution.
///  - edge: χ² = rᵀΩr against F⁻¹_χ²(dof)(1 − residual_p).
///  - snooping: data snooping (Baarda 1968; the test of an observation vector, Teunissen, "Testing Theory",
///    2000, §4): T = rᵀ Q⁻¹ r with Q = Ω⁻¹ − J P Jᵀ the covariance of the least-squares residual (P the joint
///    marginal of the closure's two poses at the maximum-likelihood solution, J = ∂r/∂(ξ_i, ξ_j)), against
///    F⁻¹_χ²(dof)(1 − residual_p / m) with m the closures tested in that round (Bonferroni: at most
///    residual_p chance of removing a true closure per round under the model). T is the drop of Σ rᵀΩr when
///    that closure alone is left out (to first order), and χ² ≤ T always: a wrong closure that bends the map
///    until it fits (small χ², large drop) is caught. A closure whose Q is not positive definite (nothing but
///    it constrains its relative pose) cannot be tested and is left as it is.
///  - groups: data snooping, and the same test of a group of closures (Teunissen §4, the observation vector
///    being the group's residuals): T_G = r_Gᵀ Q_G⁻¹ r_G, Q_G = blockdiag(Ω⁻¹) − J_G P J_Gᵀ over the joint
///    marginal of every pose the group touches, with m·dof degrees of freedom. A group is a closure and the
///    kept closures whose ends both lie within RobustOptions::group_window poses of its own. Wrong closures
///    that agree with one another (perceptual aliasing, §2.7.2) mask one another in the one-closure test: the
///    map bends to fit them all, and leaving one out changes little. Left out together they drop Σ rᵀΩr by
///    T_G. Each round the test most in excess of its own threshold F⁻¹_χ²(its dof)(1 − residual_p / m), m
///    counting every single and group test of the round, removes one closure (a group's: its member with the
///    largest single T). The default: chosen over edge by a pre-registered comparison on ext_robust_backend's
///    grid drawn fresh, 1, 2 and 4 robots (docs/measurements/2026-12-07-robust-default.md: a quarter of the
///    wrong closures kept, higher recall, lower ATE, more answers certified, time within 1.5×).
enum class RobustResidualTest { edge, snooping, groups };
[[nodiscard]] std::string_view to_string(RobustResidualTest t);
[[nodiscard]] RobustResidualTest robust_residual_test_from_string(
    std::string_view text);  // "edge" | "snooping" | "groups"

/// Graduated non-convexity for truncated least squares (pgo/robust.hpp: Yang et al. 2020) over the candidate
/// loop closures, the odometry trusted: after the consistency selection, over the closures it kept (the
/// order of Kimera-RPGO: PCM, then GNC), or instead of it, over every candidate. It replaces the residual
/// check.
enum class RobustGnc { off, after_pcm, only };
[[nodiscard]] std::string_view to_string(RobustGnc g);
[[nodiscard]] RobustGnc robust_gnc_from_string(std::string_view text);  // "off" | "after" | "only"

struct RobustOptions {
  double p =
      0.11;  // γ = F⁻¹_χ²(dof)(1 − p), the consistency threshold (thesis §2.7: PCM-Exact-11 %), in (0, 1)
  pcm::Composition composition = pcm::Composition::joint;  // the relative poses from the joint marginals
  RobustSelector selector = RobustSelector::automatic;
  int exact_up_to = 2000;     // automatic: the exact clique for groups of at most this many candidates (>= 1)
  double time_limit_s = 0.0;  // per group's exact clique search (s, >= 0); 0: none (the result says if it
                              // stopped)
  LocalSolveOptions local;    // each robot's odometry map (odometry initial guess, pose 0 fixed)
  pgo::CertifiedOptions solve;  // the certified solve of all odometry and the kept closures
  unsigned threads = 1;         // consistency matrices; 0 = keel::core::default_threads()
  // The residual check after the selection: the kept closure (or group, residual_test) most above its
  // threshold at the solution is removed (the threshold from residual_p: RobustResidualTest) and the rest
  // re-solved (Levenberg–Marquardt from the estimate), up to max_residual_rounds times; then the certified
  // solve of what is left. residual_p = 0: no check.
  double residual_p = 0.01;
  int max_residual_rounds = 50;
  RobustResidualTest residual_test = RobustResidualTest::groups;
  // The residual check's first estimate: the certified solve (false), or the certified solver's local optimum
  // at rank d, without the staircase (true, the default). Where it is certified it is the certified solve's
  // answer; where not (wrong closures left make the relaxation inexact, and the staircase is the slow part),
  // the check starts from it and the certified solve of what is left comes at the end, as after any removal.
  // The default by a pre-registered comparison (docs/measurements/2026-12-07-robust-first-solve.md: 0.64× the
  // time, fewer wrong closures kept, more answers certified, recall and ATE unchanged by sign test).
  bool first_solve_rank_d = true;
  int group_window = 5;  // groups: a closure's group holds the kept closures whose ends lie within this many
                         // poses of its own (>= 1)
  // GNC (instead of the residual check when not off): TLS with the inlier threshold c̄² = F⁻¹_χ²(dof)(1 −
  // gnc_p) on each closure's χ² = rᵀΩr, μ₀ from the largest χ² at the certified solve of what it weighs, μ ←
  // gnc_mu_factor·μ each round, at most gnc_max_rounds weighted solves. Each weighted solve is the certified
  // solver's (gnc_certified_inner, started from the round before; its certificate or gap recorded) or
  // Levenberg–Marquardt's; the closures of weight ≥ ½ at the end are kept, and the answer is the certified
  // solve of the odometry and them.
  RobustGnc gnc = RobustGnc::off;
  double gnc_p = 0.01;
  double gnc_mu_factor = 1.4;
  int gnc_max_rounds = 100;
  bool gnc_certified_inner = true;
  // Throws std::invalid_argument naming the field (including the nested options' own checks).
  void validate() const;
};

/// One candidate loop closure: z ≈ (T^{robot_a}_{pose_a})⁻¹ T^{robot_b}_{pose_b}, robot_a ≤ robot_b (an
/// inter-robot candidate given the other way round is inverted), poses local to their robots.
template <class G>
struct RobustCandidate {
  int robot_a = 0, pose_a = 0, robot_b = 0, pose_b = 0;
  int source = -1;  // r: an edge of robot r's graph; −1: the inter-robot candidate list
  int edge = 0;     // index of that edge in its source
  int line = 0;     // its source line (0 when built in memory)
  int group = 0;    // index into RobustRun::groups
  G z;
  typename G::Jacobian covariance;  // of the left perturbation of z (pcm::left_covariance_from_information)
  bool kept = false;
  int inconsistent_with_kept = 0;  // kept candidates of its group it contradicts (q above γ either way)
  int removed_in_round =
      0;  // > 0: kept by its group's selection, removed by that round of the residual check
  // rᵀΩr at the final solution (kept), or at its removal; NaN for one never kept.
  double residual_chi2 = std::numeric_limits<double>::quiet_NaN();
  // Data snooping's T at its removal (RobustResidualTest::snooping and groups); NaN otherwise.
  double snooping_t = std::numeric_limits<double>::quiet_NaN();
  // RobustResidualTest::groups, when a group's test removed it: that group's T, its degrees of freedom and
  // its closures (this one the member with the largest single T); NaN, 0, 0 otherwise.
  double residual_group_t = std::numeric_limits<double>::quiet_NaN();
  int residual_group_dof = 0, residual_group_size = 0;
  // GNC's last weight (the weight of the last weighted solve; kept when ≥ ½); NaN when GNC did not weigh it.
  double gnc_weight = std::numeric_limits<double>::quiet_NaN();
  bool joins_robots = false;  // kept only because without it a robot would have no common frame
};

/// One round of GNC: the weights at μ, then the weighted solve.
struct RobustGncRound {
  double mu = 0.0;
  int inliers = 0;            // weights ≥ ½
  int zero = 0;               // weights 0 (left out of the solve, unless one joins robots: weight 1e-3)
  double weight_sum = 0.0;    // Σ w
  double tls_cost = 0.0;      // Σ min(χ², c̄²) over the weighed closures at the round's solution
  bool certified = false;     // the weighted solve carried a certificate (always false for LM solves)
  double relative_gap = 0.0;  // its proven relative gap (+inf when nothing was proven; NaN for LM solves)
  double time_s = 0.0;
};

/// The candidates joining one robot (robot_a == robot_b) or one pair of robots, and their selection.
struct RobustGroup {
  int robot_a = 0, robot_b = 0;
  RobustSelector selector = RobustSelector::exact;  // the one that chose (never automatic)
  std::vector<int> members;                         // indices into RobustRun::candidates, in the order of Q
  pcm::ConsistencyMatrix q;  // with ConsistencyOptions::cutoff = γ: q_vu is +∞ (not evaluated) where q_uv > γ
  pcm::Selection selection;  // indices into `members`; selection.search holds the clique search
  double consistency_time_s = 0.0;
};

/// Called with a short description of each stage as it starts; may be empty.
using RobustProgress = std::function<void(std::string_view stage)>;

template <class G>
struct RobustRun {
  RobustOptions options;                        // what the run was asked
  std::vector<int> offsets;                     // robot r's pose k is pose offsets[r] + k of the solved graph
  std::vector<graph::PoseGraphOf<G>> odometry;  // per robot: its poses and odometry edges
  std::vector<RobustCandidate<G>> candidates;   // robots' own closures (robot by robot), then the list's
  std::vector<RobustGroup> groups;              // nonempty groups: each robot's own, then pairs (a < b)
  double gamma = 0.0;
  int kept = 0;                    // candidates kept, over all groups
  graph::PoseGraphOf<G> selected;  // all odometry and the kept closures, robots' poses one after another
  pgo::CertifiedSolution<graph::PoseGraphOf<G>> solved;  // `selected` solved with its certificate
  double odometry_time_s = 0.0, marginals_time_s = 0.0, consistency_time_s = 0.0, selection_time_s = 0.0;
  double residual_threshold = 0.0;  // F⁻¹_χ²(dof)(1 − residual_p); 0 without the check (snooping: of the
                                    // first round, with its Bonferroni correction)
  int residual_rounds = 0;          // closures the residual check removed
  double residual_time_s = 0.0;     // the residual check: the first certified solve and the re-solves
  double gnc_threshold = 0.0;       // c̄²; 0 without GNC
  int gnc_weighed = 0;              // closures GNC weighed
  std::vector<RobustGncRound> gnc_rounds;
  bool gnc_converged = false;  // the last solve's weights, all 0 or 1, are the weights at its solution
  double gnc_time_s = 0.0;     // GNC: the first certified solve and the weighted solves (the answer's not)
};
using RobustRun2 = RobustRun<lie::SE2>;
using RobustRun3 = RobustRun<lie::SE3>;

/// The pipeline above on `robots` (one graph each, at least one) and `inter_robot` candidates whose ids are
/// global: robot r's pose k is id offsets[r] + k, the robots' poses numbered one after another in the order
/// given. Throws std::invalid_argument for invalid options, a robot whose odometry does not chain every pose
/// (naming the robot and the pose), a candidate id beyond the last robot's poses or a loop closure whose
/// information is not positive definite (naming the candidate and its line), robots that no kept closure
/// joins (naming one), a candidate group whose dense joint marginal would not fit in memory ((dof · poses
/// touched)² numbers over 2 GiB), or, with RobustResidualTest::groups, a closure group whose Q_G and the
/// blocks of P behind it could take more than 2 GiB together (naming group_window); std::runtime_error when a
/// solve fails.
[[nodiscard]] RobustRun2 robust(const std::vector<graph::PoseGraph2D>& robots,
                                const std::vector<graph::Edge2>& inter_robot = {},
                                const RobustOptions& options = {}, const RobustProgress& progress = {});
[[nodiscard]] RobustRun3 robust(const std::vector<graph::PoseGraph3D>& robots,
                                const std::vector<graph::Edge3>& inter_robot = {},
                                const RobustOptions& options = {}, const RobustProgress& progress = {});

/// Data snooping's T = rᵀ Q⁻¹ r (RobustResidualTest::snooping) of each edge of `tested` (edges of `graph`,
/// ids those of its poses) at `poses`, a maximum-likelihood solution of `graph` (pgo::optimize's): Q = Ω⁻¹ −
/// J P Jᵀ, P the joint marginal of the edge's two poses (left perturbations, thesis eq. 5.14;
/// graph.gauge_pose fixed) and J = ∂r/∂(ξ_i, ξ_j). NaN for an edge whose Q is not positive definite (to 1e-10
/// of its largest eigenvalue): nothing else constrains its relative pose. Throws as cov::MarginalCovariance
/// when the information matrix is not positive definite.
[[nodiscard]] std::vector<double> snooping_statistics(const graph::PoseGraph2D& graph,
                                                      const std::vector<lie::SE2>& poses,
                                                      const std::vector<graph::Edge2>& tested);
[[nodiscard]] std::vector<double> snooping_statistics(const graph::PoseGraph3D& graph,
                                                      const std::vector<lie::SE3>& poses,
                                                      const std::vector<graph::Edge3>& tested);

/// RobustResidualTest::groups' statistic of `tested` as one group (edges of `graph`, ids those of its poses)
/// at `poses`, a maximum-likelihood solution of `graph`: T_G = r_Gᵀ Q_G⁻¹ r_G and its degrees of freedom
/// (m·dof when Q_G is well conditioned; otherwise the eigenvalues of Q_G above 1e-10 of its largest, T over
/// them; NaN and 0 when there are none). Throws std::invalid_argument, before forming them, when Q_G and the
/// blocks of P behind it could take more than 2 GiB together ((dof · edges)² + (dof · poses touched)²
/// numbers).
struct GroupStatistic {
  double t = 0.0;
  int dof = 0;
};
[[nodiscard]] GroupStatistic group_snooping_statistic(const graph::PoseGraph2D& graph,
                                                      const std::vector<lie::SE2>& poses,
                                                      const std::vector<graph::Edge2>& tested);
[[nodiscard]] GroupStatistic group_snooping_statistic(const graph::PoseGraph3D& graph,
                                                      const std::vector<lie::SE3>& poses,
                                                      const std::vector<graph::Edge3>& tested);

}  // namespace keel::merge
