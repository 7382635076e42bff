// keel.sos — the curated facade of engine/sos: certifiable planar SLAM (thesis ch. 4). Facade rules
// (docs/DESIGN.md) as every area.
module;
#include "sos/certify.hpp"
#include "sos/problem.hpp"
#include "sos/relaxation.hpp"
#include "sos/verify.hpp"
export module keel.sos;

export namespace keel::sos {
// the polynomial problem (§4.3) and segments of a data set
using keel::sos::estimate_of;
using keel::sos::extract_segment;
using keel::sos::planar_problem;
using keel::sos::PlanarEstimate;
using keel::sos::PlanarProblem;
using keel::sos::polynomial_cost;
using keel::sos::Segment;
using keel::sos::unknowns_of;
// relaxations (§4.4–4.5)
using keel::sos::chordal_cliques;
using keel::sos::moment_count;
using keel::sos::relax;
using keel::sos::RelaxationOptions;
using keel::sos::RelaxationResult;
using keel::sos::Structure;
using keel::sos::structure_from_string;
// certified solutions, and the counterexample to Theorem 4.5.3
using keel::sos::CertifiedSolution;
using keel::sos::CertifyOptions;
using keel::sos::exactness_counterexample;
using keel::sos::solve_certified;
using keel::sos::to_string;
// a dual certificate for a given solution of a whole data set (beyond the thesis)
using keel::sos::certify_solution;
using keel::sos::GlobalCertificate;
using keel::sos::GlobalCertificateOptions;
using keel::sos::refine_solution;
using keel::sos::RefineOptions;
using keel::sos::RefineReport;
}  // namespace keel::sos
