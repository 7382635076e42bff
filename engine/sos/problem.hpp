// keel::sos — planar pose-graph and landmark SLAM as a polynomial optimization problem (thesis §4.3).
//
// Unknowns: per pose i ≥ 1 the rotation as (c_i, s_i) with c_i² + s_i² = 1 (eq. 4.4) and the translation
// (x_i, y_i) (eq. 4.5); per landmark ℓ its position (l_ℓ^x, l_ℓ^y). Pose 0 is held at the identity: the cost
// of eq. 4.3 is invariant to a global rigid motion, and without a gauge the relaxation's optimum is a mixture
// of rotated copies of the solution (a moment matrix of rank > 1 at zero gap).
//
// Cost (eq. 4.6–4.10 and 4.12–4.13) as a sum of squares of residuals that are linear in the unknowns:
//   rotation of edge (i, j):    ω_R² ‖R_j − R_i R̄_ij‖_F² = Ω_θ ‖(c_j, s_j) − R_i (c̄_ij, s̄_ij)‖² (eq. 4.8–4.9)
//     with ω_R² = Ω_θ / 2, so that the term is 2 Ω_θ (1 − cos θ_E) ≈ Ω_θ θ_E², keel.pgo's χ² term;
//   translation of edge (i, j): ω_x² (x_j − x_i − (R_i t̄_ij)_x)² + ω_y² (y_j − y_i − (R_i t̄_ij)_y)²
//   (eq. 4.10) landmark ℓ seen from i:    ω_x² (l^x − x_i − (R_i z̄)_x)² + ω_y² (l^y − y_i − (R_i z̄)_y)²
//   (eq. 4.13)
//     with ω_x² = Ω_xx and ω_y² = Ω_yy. Eq. 4.10 weighs the world axes; for isotropic translation information
//     (every benchmark file here) this is exactly keel.pgo's translation χ², whose residual lives in the
//     measurement frame. Information with cross terms (Ω_xy, Ω_xθ, Ω_yθ ≠ 0) has no such form and is refused.
// So f(z) = Σ_k (a_kᵀ z + r_k)² = ‖A z + r‖² ≈ χ² = 2 × keel.pgo's cost.
//
// Scaling (the thesis warns of ill-conditioning, §4.5.3): translations are unknowns in units of
// `length_scale` (the RMS distance of the initial poses from pose 0, at least 1), and the cost is divided by
// nothing: every reported cost is in the original units.
#pragma once

#include <Eigen/Dense>
#include "sos/eigen_sparse.hpp"
#include <vector>

#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"

namespace keel::sos {

// One measurement's residual rows, for the relaxations' sparsity: the nodes it couples (node −1 = the
// anchor).
struct Term {
  int node_a = -1, node_b = -1;
  int first_row = 0, rows = 0;
};

struct PlanarProblem {
  int poses = 0;      // n, pose 0 held at the identity
  int landmarks = 0;  // L
  double length_scale = 1.0;
  // Nodes: pose i ≥ 1 is node i − 1 with unknowns [c, s, x, y] at 4 (i − 1); landmark ℓ is node n − 1 + ℓ
  // with unknowns [l^x, l^y] at 4 (n − 1) + 2ℓ.
  Eigen::SparseMatrix<double> a;  // residual rows × unknowns (weights folded in)
  Eigen::VectorXd r;              // constant part of every residual row
  std::vector<Term> terms;        // one per edge, then one per landmark measurement

  [[nodiscard]] int pose_nodes() const { return poses - 1; }
  [[nodiscard]] int nodes() const { return poses - 1 + landmarks; }
  [[nodiscard]] int unknowns() const { return 4 * (poses - 1) + 2 * landmarks; }
  [[nodiscard]] int node_offset(int node) const {
    return node < poses - 1 ? 4 * node : 4 * (poses - 1) + 2 * (node - poses + 1);
  }
  [[nodiscard]] int node_size(int node) const { return node < poses - 1 ? 4 : 2; }
  // Rotation unknowns: c_i at 4(i − 1), s_i at 4(i − 1) + 1 for poses i = 1 … n − 1.
  [[nodiscard]] bool is_rotation(int v) const { return v < 4 * (poses - 1) && v % 4 < 2; }
};

// eq. 4.11 (no landmarks) or eq. 4.12 from a planar graph: its poses, edges and landmark measurements. The
// initial poses only set the length scale. Throws std::invalid_argument for fewer than two poses, an index
// out of range, information that is not symmetric positive definite or has cross terms, a landmark no pose
// sees, and a graph that is not connected (the message names the first unreachable pose or landmark).
[[nodiscard]] PlanarProblem planar_problem(const graph::PoseGraph2D& graph);

// f(z) = ‖A z + r‖² in the original units (z as laid out above, translations in units of length_scale).
[[nodiscard]] double polynomial_cost(const PlanarProblem& p, const Eigen::VectorXd& z);

// The unknowns of poses and landmarks given in any frame: re-expressed in the frame of pose 0 and scaled.
[[nodiscard]] Eigen::VectorXd unknowns_of(const PlanarProblem& p, const std::vector<lie::SE2>& poses,
                                          const std::vector<lie::Vec2>& landmarks = {});

// Poses (pose 0 = identity) and landmarks of z in the original units; rotations are projected to the circle.
struct PlanarEstimate {
  std::vector<lie::SE2> poses;
  std::vector<lie::Vec2> landmarks;
};
[[nodiscard]] PlanarEstimate estimate_of(const PlanarProblem& p, const Eigen::VectorXd& z);

// Every (c_i, s_i) of z replaced by its projection on the unit circle ((1, 0) when it is 0).
void project_rotations(const PlanarProblem& p, Eigen::VectorXd& z);

// For fixed rotations, the translations and landmarks that minimise f (a linear least-squares solve; exact).
void solve_translations(const PlanarProblem& p, Eigen::VectorXd& z);

// The columns `cols` of A (in that order) as a sparse matrix: A · S with the selection matrix S(cols[k], k)
// = 1.
[[nodiscard]] Eigen::SparseMatrix<double> columns_of(const Eigen::SparseMatrix<double>& a,
                                                     const std::vector<int>& cols);

// Gauss–Newton on f over (θ_i, translations, landmarks) from z, with a backtracking step: the local minimum
// of the thesis's own cost near z (keel.pgo minimizes the geodesic χ², whose minimum differs from f's by
// O(θ⁴)).
struct RefineResult {
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;
  double gradient_norm = 0.0;  // ‖∇f‖∞ at the end, in the (θ, scaled translation) coordinates
};
RefineResult refine(const PlanarProblem& p, Eigen::VectorXd& z, int max_iterations = 20);

// A segment of a planar data set: poses first … first + count − 1 renumbered from 0, the edges between them,
// the landmarks they see (renumbered in order of first sight) and their measurements; initial poses are the
// chained odometry (i, i + 1) from the identity. Ground truth, when given, is re-expressed in the frame of
// the first pose. Throws std::invalid_argument for an empty or out-of-range segment or a missing odometry
// edge.
struct Segment {
  graph::PoseGraph2D graph;
  std::vector<lie::SE2> truth_poses;       // empty without ground truth
  std::vector<lie::Vec2> truth_landmarks;  // empty without ground truth
  int first = 0;
};
[[nodiscard]] Segment extract_segment(const graph::PoseGraph2D& graph, int first, int count,
                                      const std::vector<lie::SE2>& truth_poses = {},
                                      const std::vector<lie::Vec2>& truth_landmarks = {});

}  // namespace keel::sos
