// keel.pgo — the curated facade of engine/pgo: batch maximum-likelihood pose-graph SLAM (thesis eq. 2.1),
// several robots with anchor nodes (Kim et al. 2010; thesis §2.3, eq. 2.2), robust kernels including Dynamic
// Covariance Scaling (Agarwal et al. 2013; thesis §2.7), and the residual/cost of a graph at given poses.
// Facade rules (docs/DESIGN.md): includes in the global module fragment (the public headers only: they
// include the graph/lie headers and the standard library, never Ceres), using-declarations in the export
// block, no import of another facade. Consumers also import keel.lie (SE2, SE3, ...) and keel.graph
// (PoseGraph2D, readers) themselves.
module;
#include "pgo/certified.hpp"
#include "pgo/multi_robot.hpp"
#include "pgo/optimize.hpp"
#include "pgo/options.hpp"
#include "pgo/robust.hpp"
#include "pgo/types.hpp"
export module keel.pgo;

export namespace keel::pgo {
// options and their enums (to_string / <enum>_from_string)
using keel::pgo::anchor_guess_from_string;
using keel::pgo::AnchorGuess;
using keel::pgo::initial_guess_from_string;
using keel::pgo::InitialGuess;
using keel::pgo::linear_solver_from_string;
using keel::pgo::LinearSolver;
using keel::pgo::Method;
using keel::pgo::method_from_string;
using keel::pgo::Options;
using keel::pgo::robust_kernel_from_string;
using keel::pgo::robust_scope_from_string;
using keel::pgo::RobustKernel;
using keel::pgo::RobustScope;
using keel::pgo::sparse_library_from_string;
using keel::pgo::SparseLibrary;
using keel::pgo::Termination;
using keel::pgo::termination_from_string;
using keel::pgo::to_string;
// the types of a dimension, by group
using keel::pgo::Types;
// robust kernels
using keel::pgo::dcs_scale;
using keel::pgo::Rho;
using keel::pgo::robust_rho;
using keel::pgo::tls_gnc_initial_mu;
using keel::pgo::tls_gnc_weight;
using keel::pgo::tls_surrogate;
// multi-robot graphs
using keel::pgo::InterRobotEdge2;
using keel::pgo::InterRobotEdge3;
using keel::pgo::MultiRobotGraph2D;
using keel::pgo::MultiRobotGraph3D;
// estimates, results, evaluation
using keel::pgo::EdgeReport;
using keel::pgo::Estimate2D;
using keel::pgo::Estimate3D;
using keel::pgo::Evaluation;
using keel::pgo::Evaluation2D;
using keel::pgo::Evaluation3D;
using keel::pgo::IterationRecord;
using keel::pgo::MultiRobotEstimate2D;
using keel::pgo::MultiRobotEstimate3D;
using keel::pgo::MultiRobotEvaluation2D;
using keel::pgo::MultiRobotEvaluation3D;
using keel::pgo::MultiRobotResult2D;
using keel::pgo::MultiRobotResult3D;
using keel::pgo::Result2D;
using keel::pgo::Result3D;
using keel::pgo::Summary;
// one call each
using keel::pgo::evaluate;
using keel::pgo::global_landmarks;
using keel::pgo::global_poses;
using keel::pgo::initial_estimate;
using keel::pgo::optimize;
// certified solve of the isotropic model (certified.hpp)
using keel::pgo::Certificate;
using keel::pgo::certified_solution;
using keel::pgo::CertifiedOptions;
using keel::pgo::CertifiedResult2D;
using keel::pgo::CertifiedResult3D;
using keel::pgo::CertifiedSolution;
using keel::pgo::CertifiedSummary;
using keel::pgo::CertifiedTermination;
using keel::pgo::certify;
using keel::pgo::isotropic_cost;
using keel::pgo::isotropic_weights;
using keel::pgo::IsotropicWeights;
using keel::pgo::RankRecord;
using keel::pgo::solve_certified;
using keel::pgo::trust_region_preconditioner_from_string;
using keel::pgo::TrustRegionPreconditioner;
}  // namespace keel::pgo
