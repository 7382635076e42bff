// keel.sos — the curated facade of engine/sos: certifiable planar SLAM (thesis ch. 4). Facade rules
// (docs/DESIGN.md) as every area.
module;
#include "sos/certify.hpp"
#include "sos/config.hpp"
#include "sos/problem.hpp"
#include "sos/relaxation.hpp"
#include "sos/studies.hpp"
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
// SDP solvers and the recomputed checks
// certified solutions
using keel::sos::CertifiedSolution;
using keel::sos::CertifyOptions;
using keel::sos::solve_certified;
using keel::sos::to_string;
// the chapter-4 studies (§4.6, the exactness test) and their config readers
using keel::sos::exactness_counterexample;
using keel::sos::ExactnessFamily;
using keel::sos::ExactnessOptions;
using keel::sos::ExactnessOutcome;
using keel::sos::ExactnessTrial;
using keel::sos::load_planar_dataset;
using keel::sos::MethodOutcome;
using keel::sos::PlanarDataset;
using keel::sos::read_certify_options;
using keel::sos::read_exactness_options;
using keel::sos::read_segment_study_options;
using keel::sos::run_exactness_study;
using keel::sos::run_segment_study;
using keel::sos::SegmentOutcome;
using keel::sos::SegmentStudyOptions;
using keel::sos::SegmentStudyOutcome;
// a dual certificate for a given solution of a whole data set (beyond the thesis) and its study
using keel::sos::certify_solution;
using keel::sos::GlobalCertificate;
using keel::sos::GlobalCertificateDataset;
using keel::sos::GlobalCertificateOptions;
using keel::sos::GlobalCertificateOutcome;
using keel::sos::GlobalCertificateRun;
using keel::sos::GlobalCertificateStudyOptions;
using keel::sos::GlobalCertificateStudyOutcome;
using keel::sos::load_global_certificate_datasets;
using keel::sos::read_global_certificate_study_options;
using keel::sos::refine_solution;
using keel::sos::RefineOptions;
using keel::sos::RefineReport;
using keel::sos::run_global_certificate_study;
}  // namespace keel::sos
