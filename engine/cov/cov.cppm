// keel.cov — the curated facade of engine/cov (thesis §5.8.2): the information matrix of a pose graph at a
// solution, linearized in the Lie algebra (left perturbation T = exp(ξ^) T̄, eq. 5.14), and the joint marginal
// covariances of any sets of poses / landmarks from its sparse Cholesky factorization (CHOLMOD, inside the
// .cpp files only). Facade rules (docs/DESIGN.md): includes in the global module fragment (public headers
// only: graph/lie headers and the standard library, never CHOLMOD), using-declarations in the export block,
// no import of another facade. Consumers also import keel.lie (SE2, Mat6, ...) and keel.graph (PoseGraph2D,
// readers) themselves.
module;
#include "cov/chain.hpp"
#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
export module keel.cov;

export namespace keel::cov {
// residuals and their Lie-algebra Jacobians
using keel::cov::chain_joint;
using keel::cov::EdgeLinearization2;
using keel::cov::EdgeLinearization3;
using keel::cov::LandmarkLinearization2;
using keel::cov::linearize_edge;
using keel::cov::linearize_landmark;
// gauge and the sparse information matrix
using keel::cov::Gauge;
using keel::cov::gauge_from_string;
using keel::cov::GaugeOptions;
using keel::cov::information_matrix;
using keel::cov::SparseInformation;
using keel::cov::to_string;
// marginal covariances
using keel::cov::CovarianceOptions;
using keel::cov::Extraction;
using keel::cov::extraction_from_string;
using keel::cov::FactorSummary;
using keel::cov::linear_map_covariances;
using keel::cov::LinearMap;
using keel::cov::MarginalCovariance;
using keel::cov::Ordering;
using keel::cov::ordering_from_string;
using keel::cov::pair_marginals;
using keel::cov::pair_marginals_2d;
using keel::cov::pair_marginals_3d;
}  // namespace keel::cov
