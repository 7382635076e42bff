// Every enum <-> string name table of the engine (core/names.hpp, docs/DESIGN.md "Naming and errors") through
// one check, keel::testkit::check_name_table (tests/kit/name_tables.hpp): each enumerator round-trips through
// to_string and <e>_from_string, the names are unique, and an unknown name throws std::invalid_argument
// listing the valid names. It lives in study, the one area whose tests see the headers of every area with a
// name table (the algorithms, the data tier's sim and study's own). A new name table gets a line here.
#include <doctest/doctest.h>

#include "align/align.hpp"
#include "convex/sdp.hpp"
#include "core/bound.hpp"
#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "graph/io.hpp"
#include "kit/name_tables.hpp"
#include "lie/fourth_order_joint.hpp"
#include "merge/merge.hpp"
#include "merge/robust.hpp"
#include "pcm/clique.hpp"
#include "pcm/combinatorial.hpp"
#include "pcm/consistency.hpp"
#include "pcm/selection.hpp"
#include "pgo/options.hpp"
#include "sim/loop_closures.hpp"
#include "sim/world1d.hpp"
#include "sos/relaxation.hpp"
#include "study/ch2/clique_scale.hpp"
#include "study/ch2/world1d.hpp"

using keel::testkit::check_name_table;

TEST_CASE(
    "every name table: enumerators round-trip, names are unique, an unknown name lists the valid ones") {
  namespace core = keel::core;
  namespace lie = keel::lie;
  namespace graph = keel::graph;
  namespace pgo = keel::pgo;
  namespace cov = keel::cov;
  namespace pcm = keel::pcm;
  namespace convex = keel::convex;
  namespace merge = keel::merge;
  namespace align = keel::align;
  namespace sos = keel::sos;
  namespace sim = keel::sim;
  namespace ch2 = keel::study::ch2;

  // foundation
  using core::SearchStatus;
  check_name_table(
      "core::SearchStatus",
      {SearchStatus::optimal, SearchStatus::unproven, SearchStatus::node_limit, SearchStatus::time_limit},
      core::search_status_from_string);

  // algorithms
  check_name_table("lie::ChainCrossOrder", {lie::ChainCrossOrder::first, lie::ChainCrossOrder::fourth},
                   lie::chain_cross_order_from_string);
  check_name_table("graph::GraphFormat", {graph::GraphFormat::g2o, graph::GraphFormat::isam},
                   graph::graph_format_from_string);
  check_name_table("pgo::Method", {pgo::Method::levenberg_marquardt, pgo::Method::dogleg},
                   pgo::method_from_string);
  using pgo::LinearSolver;
  check_name_table(
      "pgo::LinearSolver",
      {LinearSolver::sparse_normal_cholesky, LinearSolver::sparse_schur, LinearSolver::dense_normal_cholesky,
       LinearSolver::dense_qr, LinearSolver::dense_schur, LinearSolver::cgnr, LinearSolver::iterative_schur},
      pgo::linear_solver_from_string);
  using pgo::SparseLibrary;
  check_name_table("pgo::SparseLibrary",
                   {SparseLibrary::suite_sparse, SparseLibrary::eigen_sparse, SparseLibrary::cx_sparse},
                   pgo::sparse_library_from_string);
  using pgo::InitialGuess;
  check_name_table(
      "pgo::InitialGuess",
      {InitialGuess::as_read, InitialGuess::odometry, InitialGuess::supplied, InitialGuess::random},
      pgo::initial_guess_from_string);
  using pgo::RobustKernel;
  check_name_table("pgo::RobustKernel",
                   {RobustKernel::none, RobustKernel::huber, RobustKernel::cauchy, RobustKernel::dcs},
                   pgo::robust_kernel_from_string);
  using pgo::RobustScope;
  check_name_table("pgo::RobustScope",
                   {RobustScope::all_edges, RobustScope::loop_closures, RobustScope::inter_robot},
                   pgo::robust_scope_from_string);
  check_name_table("pgo::AnchorGuess", {pgo::AnchorGuess::as_given, pgo::AnchorGuess::inter_robot_edges},
                   pgo::anchor_guess_from_string);
  using pgo::Termination;
  check_name_table("pgo::Termination",
                   {Termination::converged, Termination::no_convergence, Termination::failure},
                   pgo::termination_from_string);
  using cov::Ordering;
  check_name_table("linalg::Ordering",
                   {Ordering::automatic, Ordering::amd, Ordering::metis, Ordering::nesdis, Ordering::natural},
                   cov::ordering_from_string);
  using cov::Extraction;
  check_name_table("cov::Extraction", {Extraction::automatic, Extraction::forward, Extraction::solve},
                   cov::extraction_from_string);
  check_name_table("cov::Gauge", {cov::Gauge::fix_pose, cov::Gauge::prior}, cov::gauge_from_string);
  using pcm::CliqueAlgorithm;
  check_name_table("pcm::CliqueAlgorithm",
                   {CliqueAlgorithm::exact, CliqueAlgorithm::heuristic, CliqueAlgorithm::brute_force},
                   pcm::clique_algorithm_from_string);
  check_name_table("pcm::ScgpDiscretization",
                   {pcm::ScgpDiscretization::dot_product, pcm::ScgpDiscretization::rayleigh},
                   pcm::scgp_discretization_from_string);
  check_name_table("pcm::Composition", {pcm::Composition::joint, pcm::Composition::independent},
                   pcm::composition_from_string);
  check_name_table("pcm::CombinatorialMethod",
                   {pcm::CombinatorialMethod::exhaustive, pcm::CombinatorialMethod::pruned},
                   pcm::combinatorial_method_from_string);
  check_name_table("convex::SdpSolver", {convex::SdpSolver::dsdp, convex::SdpSolver::sdpa},
                   convex::sdp_solver_from_string);
  check_name_table("merge::AnchorInit", {merge::AnchorInit::selected_edges, merge::AnchorInit::identity},
                   merge::anchor_init_from_string);
  using merge::MergeMethodKind;
  check_name_table(
      "merge::MergeMethodKind",
      {MergeMethodKind::no_outliers, MergeMethodKind::dcs, MergeMethodKind::scgp, MergeMethodKind::ransac,
       MergeMethodKind::pcm_exact, MergeMethodKind::pcm_heuristic, MergeMethodKind::densest},
      merge::merge_method_kind_from_string);
  using merge::RobustSelector;
  check_name_table(
      "merge::RobustSelector",
      {RobustSelector::automatic, RobustSelector::exact, RobustSelector::heuristic, RobustSelector::densest},
      merge::robust_selector_from_string);
  check_name_table("merge::RobustGnc",
                   {merge::RobustGnc::off, merge::RobustGnc::after_pcm, merge::RobustGnc::only},
                   merge::robust_gnc_from_string);
  check_name_table("merge::RobustResidualTest",
                   {merge::RobustResidualTest::edge, merge::RobustResidualTest::snooping,
                    merge::RobustResidualTest::groups},
                   merge::robust_residual_test_from_string);
  using align::Method;
  check_name_table("align::Method",
                   {Method::proposed, Method::so_conv_hull, Method::symmetric, Method::affine},
                   align::method_from_string);
  check_name_table("sos::Structure", {sos::Structure::dense, sos::Structure::cliques},
                   sos::structure_from_string);

  // data
  check_name_table("sim::WrongClosureKind", {sim::WrongClosureKind::random, sim::WrongClosureKind::aliased},
                   sim::wrong_closure_kind_from_string);
  using sim::MeasurementLabel;
  check_name_table("sim::MeasurementLabel",
                   {MeasurementLabel::inlier, MeasurementLabel::aliased, MeasurementLabel::random},
                   sim::measurement_label_from_string);

  // studies
  using ch2::Selector1D;
  check_name_table("ch2::Selector1D",
                   {Selector1D::combinatorial, Selector1D::pcm_exact, Selector1D::pcm_heuristic,
                    Selector1D::scgp, Selector1D::ransac},
                   ch2::selector1d_from_string);
  using ch2::CliqueScaleMethod;
  check_name_table("ch2::CliqueScaleMethod",
                   {CliqueScaleMethod::exact, CliqueScaleMethod::heuristic, CliqueScaleMethod::densest},
                   ch2::clique_scale_method_from_string);
}
