// Robust multi-robot map merging (thesis §2.6), and the outlier-rejection methods of §2.7 behind one
// MergeMethod.
//
// The four steps of §2.6:
//   i)   individual map generation — solve_local(): each robot's graph is solved once (keel::pgo batch
//   maximum
//        likelihood, odometry initial guess, pose 0 fixed) and its information matrix, linearized in the left
//        perturbation at the solution (keel::cov, gauge = pose 0 fixed), is factorized once;
//   ii)  consistency calculation — local_maps() extracts, per candidate set, the joint marginal covariance of
//   the
//        poses the candidates touch (MarginalCovariance::joint; "we extract the covariance for every pair of
//        nodes on a given local map that are associated with an inter-robot constraint"), which
//        consistency_matrix() needs;
//   iii) pairwise consistency maximization — selection.hpp (run_merge_dataset below calls it);
//   iv)  constraint insertion and full map generation — merge_maps(): one batch solve of the two-robot graph
//   with
//        anchors (Kim et al. 2010, eq. 2.2) holding both local graphs and the selected candidates as
//        inter-robot edges (thesis: "for SE(2) it was sufficient to add the inter-robot factors directly to
//        the already existing graph and run a batch optimization"). The local poses start from the local
//        solutions and b's anchor from the first selected edge (pgo::AnchorGuess::inter_robot_edges), or from
//        the identity.
// The baseline DCS (Agarwal et al. 2013, φ = 5) is merge_maps() with every candidate, the DCS kernel on the
// loop closures (inter-robot edges included) and b's anchor at the identity: the thesis's DCS has no initial
// alignment.
//
// Frames: the global frame is robot a's frame (a's anchor is the identity and held constant), so merged poses
// of both robots and b's anchor T_ab are expressed there, like the scenario's ground truth (scenario.hpp).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <variant>
#include <vector>

#include "cov/marginal_covariance.hpp"
#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "pcm/clique.hpp"
#include "pcm/consistency.hpp"
#include "pcm/densest.hpp"
#include "pcm/selection.hpp"
#include "pgo/optimize.hpp"
#include "pgo/options.hpp"
#include "core/fields.hpp"

namespace keel::merge {

struct LocalSolveOptions {
  // The local solve: pgo's defaults with initial_guess = odometry (as_read is the other valid choice;
  // supplied and random are not) and one solver thread (keep 1 where result files are compared across thread
  // counts).
  pgo::Options solver = default_solver();
  static pgo::Options default_solver();
  // Throws std::invalid_argument naming the violated constraint (including solver.validate()'s).
  void validate() const;
};

// One robot's solved local map: the solution and the factorized information matrix it came from (§2.6 step
// i).
template <class G>
struct LocalSolution {
  graph::PoseGraphOf<G> graph;  // the local graph as given
  std::vector<G> poses;         // the maximum-likelihood solution in the robot's frame (pose 0 fixed)
  pgo::Summary summary;         // of the local solve
  std::shared_ptr<const cov::MarginalCovariance> covariance;  // immutable, safe to query from several threads
  double solve_time_s = 0.0;                                  // local solve
  double factorization_time_s = 0.0;                          // information matrix + CHOLMOD factorization
};
using LocalSolution2 = LocalSolution<lie::SE2>;
using LocalSolution3 = LocalSolution<lie::SE3>;

// Solves the graph and factorizes its information at the solution (gauge: pose 0 fixed). Throws
// std::invalid_argument for invalid options or graphs, std::runtime_error when the solver fails or the
// information matrix is not positive definite (a graph that is not connected).
[[nodiscard]] LocalSolution2 solve_local(const graph::PoseGraph2D& graph,
                                         const LocalSolveOptions& options = {});
[[nodiscard]] LocalSolution3 solve_local(const graph::PoseGraph3D& graph,
                                         const LocalSolveOptions& options = {});

// LocalMap (consistency.hpp) of both robots for one candidate set: ids = the distinct poses the candidates
// touch (ascending), joint = their joint marginal covariance. Throws std::invalid_argument naming the
// candidate when one touches a pose that its robot does not have.
template <class G>
struct LocalMaps {
  pcm::LocalMap<G> a, b;
  double time_s = 0.0;  // covariance extraction (both robots)
};
using LocalMaps2 = LocalMaps<lie::SE2>;
using LocalMaps3 = LocalMaps<lie::SE3>;
[[nodiscard]] LocalMaps2 local_maps(const LocalSolution2& a, const LocalSolution2& b,
                                    const std::vector<pcm::InterRobotMeasurement2>& candidates);
[[nodiscard]] LocalMaps3 local_maps(const LocalSolution3& a, const LocalSolution3& b,
                                    const std::vector<pcm::InterRobotMeasurement3>& candidates);

// Initial value of b's anchor T_ab in the merged solve.
enum class AnchorInit {
  selected_edges,  // from the first selected edge and the local solutions
                   // (pgo::AnchorGuess::inter_robot_edges); identity when nothing is selected
  identity,        // no initial alignment (the thesis's DCS)
};
std::string_view to_string(AnchorInit a);
AnchorInit anchor_init_from_string(std::string_view s);  // "selected_edges" | "identity"; else throws

struct MergeOptions {
  // The merged solve: kernel (none, or dcs for the DCS baseline with robust_parameter = φ), scope (loop
  // closures, inter-robot edges included), iterations and threads. merge_maps sets initial_guess (supplied:
  // the local solutions) and anchor_guess (from anchor_init) itself.
  pgo::Options solver;
  AnchorInit anchor_init = AnchorInit::selected_edges;
  // The DCS baseline of §2.7: DCS with φ = dcs_phi on the loop closures, anchor at the identity.
  static MergeOptions dcs(double dcs_phi = 5.0);
  // Throws std::invalid_argument naming the violated constraint (including solver.validate()'s).
  void validate() const;
};

template <class G>
struct MergeResult {
  std::vector<int> selected;        // the candidates inserted (as given)
  std::vector<G> poses_a, poses_b;  // merged poses of both robots in a's frame
  G anchor_b;                       // estimated T_ab (pose of b's local frame in a's frame)
  pgo::Summary summary;             // of the merged solve (normalized_chi2 = the thesis's "Chi2")
  // Σ over all edges (both local graphs and the inserted candidates) of weight·χ²: the χ² of the merged graph
  // as the solver weighs it (= Σ χ² without a kernel; with DCS each χ² scaled by s², the "scaled residual").
  double residual = 0.0;
  double chi2 = 0.0;                         // Σ χ² over all edges, unweighted
  std::vector<pgo::EdgeReport> inter_robot;  // one per selected candidate (order of `selected`)
  double time_s = 0.0;                       // wall time of the merged solve
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(selected, poses_a, poses_b, anchor_b, summary, residual, chi2, inter_robot, time_s)
};
using MergeResult2 = MergeResult<lie::SE2>;
using MergeResult3 = MergeResult<lie::SE3>;

// §2.6 step iv. The selected candidates become inter-robot edges with the residual information of their left
// covariance (pcm::information_from_left_covariance). Throws std::invalid_argument for a selected index out
// of range or repeated, a candidate touching a missing pose, or invalid options; std::runtime_error when the
// solver fails.
[[nodiscard]] MergeResult2 merge_maps(const LocalSolution2& a, const LocalSolution2& b,
                                      const std::vector<pcm::InterRobotMeasurement2>& candidates,
                                      const std::vector<int>& selected, const MergeOptions& options = {});
[[nodiscard]] MergeResult3 merge_maps(const LocalSolution3& a, const LocalSolution3& b,
                                      const std::vector<pcm::InterRobotMeasurement3>& candidates,
                                      const std::vector<int>& selected, const MergeOptions& options = {});

// The candidates a robust solve kept: selected[k] with inter_robot[k].scale ≥ min_scale (every selected
// candidate when no kernel applied). For DCS, scale is s = min(1, 2φ/(φ + χ²)); 0.5 means χ² ≤ 3φ.
[[nodiscard]] std::vector<int> accepted_candidates(const MergeResult2& result, double min_scale);
[[nodiscard]] std::vector<int> accepted_candidates(const MergeResult3& result, double min_scale);

// ---------------------------------------------------------------------------------------------------------------
// The outlier-rejection methods of §2.7 (Tables 2.1 and 2.2), each with the options of its kind.

struct NoOutliers {
};  // the inlier candidates only (NO-OUT): the reference solve; the caller knows the inliers
struct Dcs {         // every candidate, DCS on the loop closures, no initial alignment (Agarwal et al. 2013)
  double phi = 5.0;  // DCS φ (> 0)
  double accept_scale = 0.5;  // a candidate counts as accepted when its final DCS scaling
                              // s = min(1, 2φ/(φ + χ²)) ≥ this (in (0, 1]; 0.5 ⇔ χ² ≤ 3φ)
};
struct Scgp {                                              // select_scgp(Q) (Olson et al. 2005)
  pcm::Composition composition = pcm::Composition::joint;  // the relative-pose covariance used in Q
  pcm::ScgpOptions options;
};
struct Ransac {     // select_ransac(Q, γ(p))
  double p = 0.11;  // γ = consistency_threshold(p, dof), p in (0, 1)
  pcm::Composition composition = pcm::Composition::joint;
};
struct Pcm {  // select_pcm(Q, γ(p), algorithm): exact is PCM-Exact, heuristic the thesis's PCM-HeuPatt
  double p = 0.11;
  pcm::Composition composition = pcm::Composition::joint;
  pcm::CliqueAlgorithm algorithm = pcm::CliqueAlgorithm::exact;
};
struct Densest {  // select_densest(Q, γ(p)): CLIPPER's densest-subgraph relaxation, repaired to a clique
  double p = 0.11;
  pcm::Composition composition = pcm::Composition::joint;
  pcm::DensestSelectOptions options;
};
using MethodOptions = std::variant<NoOutliers, Dcs, Scgp, Ransac, Pcm, Densest>;

// The kinds, as configs name them.
enum class MergeMethodKind { no_outliers, dcs, scgp, ransac, pcm_exact, pcm_heuristic, densest };
std::string_view to_string(MergeMethodKind k);
// "no_outliers" | "dcs" | "scgp" | "ransac" | "pcm_exact" | "pcm_heuristic" | "densest"; else throws
// std::invalid_argument.
MergeMethodKind merge_method_kind_from_string(std::string_view s);

struct MergeMethod {
  std::string name;  // key of the method's metrics (e.g. "pcm_exact_11"), non-empty
  MethodOptions options = Pcm{};
  [[nodiscard]] MergeMethodKind kind() const;
  // The threshold probability p of ransac, pcm and densest; nullopt for the others.
  [[nodiscard]] std::optional<double> p() const;
  // The composition of Q (scgp, ransac, pcm, densest); nullopt for NO-OUT and DCS, which use no Q.
  [[nodiscard]] std::optional<pcm::Composition> composition() const;
  // A method of the given kind with p and composition where the kind has them, other options at their
  // defaults.
  static MergeMethod make(std::string name, MergeMethodKind kind, double p = 0.11,
                          pcm::Composition composition = pcm::Composition::joint);
  // Throws std::invalid_argument naming the method and the violated constraint.
  void validate() const;
};

// The selection of a method that works on the consistency matrix (scgp, ransac, pcm, densest), its
// candidates ascending; γ = consistency_threshold(p, Q.dof). Throws std::invalid_argument for NO-OUT and DCS
// (NO-OUT is the caller's inliers; DCS selects by merging: accepted_candidates of merge_maps with
// MergeOptions::dcs) and for an invalid method.
[[nodiscard]] pcm::Selection select(const MergeMethod& method, const pcm::ConsistencyMatrix& Q);

}  // namespace keel::merge
