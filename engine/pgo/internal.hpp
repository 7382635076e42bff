// keel::pgo — internals shared by evaluate.cpp, initial.cpp and solve.cpp (no Ceres here; not part of the
// facade).
//
// Single-robot problems are handled as multi-robot problems with one robot and no anchors: a RobotsView
// points at the robots' graphs (nothing is copied) and the estimates use the multi-robot layout.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "graph/pose_graph.hpp"
#include "graph/residuals.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/types.hpp"
#include "pgo/multi_robot.hpp"
#include "pgo/optimize.hpp"
#include "pgo/options.hpp"
#include "pgo/robust.hpp"
#include "pgo/types.hpp"

namespace keel::pgo::detail {

// The types of each dimension (pgo/types.hpp).
using D2 = Types<lie::SE2>;
using D3 = Types<lie::SE3>;

template <class D>
struct RobotsView {
  std::vector<const typename D::Graph*> robots;
  const std::vector<typename D::Inter>* inter = nullptr;  // null for a single robot
  bool with_anchors = false;                              // a multi-robot problem (anchor per robot)
};

// Counts implied by a graph: max(stored, 1 + largest index used).
int pose_count(const graph::PoseGraph2D& g);
int pose_count(const graph::PoseGraph3D& g);
int landmark_count(const graph::PoseGraph2D& g);

// Where a measurement came from, for error messages: "edge 12 (line 40 of 'file')".
std::string edge_label(const char* kind, std::size_t index, int line, const std::string& source);

// Throws std::invalid_argument for negative indices, self-edges, inter-robot edges with bad robot/pose
// indices.
template <class D>
void validate_graph(const RobotsView<D>& view);

// Upper-triangular (or general) U with UᵀU = Ω, Ω symmetrized first. Cholesky when Ω is positive definite,
// otherwise the symmetric square root from the eigen-decomposition (Ω positive semi-definite). Throws
// std::invalid_argument naming `what` when Ω has a non-finite entry or a clearly negative eigenvalue.
lie::Mat2 sqrt_information(const lie::Mat2& omega, const std::string& what);
lie::Mat3 sqrt_information(const lie::Mat3& omega, const std::string& what);
lie::Mat6 sqrt_information(const lie::Mat6& omega, const std::string& what);

// Residuals of pose_graph.hpp (not whitened), defined once in keel::graph.
using graph::edge_residual;
using graph::landmark_residual;

// Whether the kernel applies (kernel ≠ none and the measurement is in scope).
bool robust_edge(const Options& o, int i, int j);  // intra-robot edge (i, j)
bool robust_landmark(const Options& o);
bool robust_inter_robot(const Options& o);

// Report of a measurement with χ² under the options' kernel (weight 1 when robust == false).
EdgeReport edge_report(const Options& o, bool robust, double chi2);

// Normalized χ² as documented in Summary: 2 cost / (residual − free), NaN when that is ≤ 0.
double normalized_chi2(double cost, int residual_dimension, int free_dimension);

// Multi-robot evaluation of `at` (the engine of every evaluate(); also used after a solve for the reports).
template <class D>
typename D::MultiEvaluation evaluate_view(const RobotsView<D>& view, const typename D::MultiEstimate& at,
                                          const Options& o);

// Initial estimate in the multi-robot layout. For a single robot (view.with_anchors false) anchors has one
// identity entry. `supplied` may be null unless o.initial_guess == supplied.
template <class D>
typename D::MultiEstimate initial_view(const RobotsView<D>& view,
                                       const std::vector<typename D::Pose>& given_anchors, const Options& o,
                                       const typename D::MultiEstimate* supplied);

// Views of the public graph types.
RobotsView<D2> view_of(const graph::PoseGraph2D& g);
RobotsView<D3> view_of(const graph::PoseGraph3D& g);
RobotsView<D2> view_of(const MultiRobotGraph2D& g);
RobotsView<D3> view_of(const MultiRobotGraph3D& g);

}  // namespace keel::pgo::detail
