// keel.pcm — the curated facade of engine/pcm (thesis ch. 2): pairwise consistency maximisation. The PCM problem of
// eq. 2.5 is solved as a maximum clique of the consistency graph (§2.5) — exact branch and bound in the spirit of
// Pattabiraman et al. (2015), their greedy heuristic, and a brute-force reference for validation.
// Facade rules (docs/DESIGN.md): includes in the global module fragment, using-declarations in the export block,
// no import of another facade.
module;
#include "pcm/clique.hpp"
#include "pcm/consistency.hpp"
#include "pcm/merge.hpp"
#include "pcm/scenario.hpp"
#include "pcm/selection.hpp"
#include "pcm/world1d.hpp"
export module keel.pcm;

export namespace keel::pcm {
// consistency metric (eq. 2.4) and the matrix Q (lead)
using keel::pcm::Composition;
using keel::pcm::composition_from_string;
using keel::pcm::consistency_matrix;
using keel::pcm::consistency_threshold;
using keel::pcm::ConsistencyMatrix;
using keel::pcm::ConsistencyOptions;
using keel::pcm::InterRobotMeasurement;
using keel::pcm::InterRobotMeasurement2;
using keel::pcm::InterRobotMeasurement3;
using keel::pcm::left_covariance_from_information;
using keel::pcm::LocalMap;
using keel::pcm::LocalMap2;
using keel::pcm::LocalMap3;
using keel::pcm::loop_error;
using keel::pcm::LoopError;
using keel::pcm::relative_pose;
using keel::pcm::RelativePose;
// consistency graph
using keel::pcm::ConsistencyGraph;
using keel::pcm::core_numbers;
using keel::pcm::random_graph;
// maximum clique
using keel::pcm::clique_algorithm_from_string;
using keel::pcm::CliqueAlgorithm;
using keel::pcm::CliqueOptions;
using keel::pcm::CliqueResult;
using keel::pcm::kBruteForceMaxVertices;
using keel::pcm::maximum_clique;
using keel::pcm::maximum_clique_brute_force;
using keel::pcm::maximum_clique_exact;
using keel::pcm::maximum_clique_heuristic;
using keel::pcm::to_string;
// selection, 1D world (helper A)
using keel::pcm::combinatorial_method_from_string;
using keel::pcm::CombinatorialMethod;
using keel::pcm::CombinatorialResult;
using keel::pcm::count_inconsistent_pairs;
using keel::pcm::generate_world1d;
using keel::pcm::kCombinatorialExhaustiveMax;
using keel::pcm::kCombinatorialPrunedMax;
using keel::pcm::max_consistent_set_combinatorial;
using keel::pcm::MeasurementLabel;
using keel::pcm::scgp;
using keel::pcm::scgp_discretization_from_string;
using keel::pcm::ScgpDiscretization;
using keel::pcm::ScgpOptions;
using keel::pcm::ScgpResult;
using keel::pcm::selector1d_from_string;
using keel::pcm::Selector1D;
using keel::pcm::select_pcm;
using keel::pcm::select_ransac;
using keel::pcm::select_scgp;
using keel::pcm::Selection;
using keel::pcm::validate_consistency_matrix;
using keel::pcm::run_world1d_study;
using keel::pcm::World1D;
using keel::pcm::world1d_consistency_matrix;
using keel::pcm::world1d_options_with_total;
using keel::pcm::World1DOptions;
using keel::pcm::World1DOutcome;
using keel::pcm::World1DStudy;
using keel::pcm::World1DStudyOptions;
// scenarios and map merging (helper B)
using keel::pcm::resample_measurements;
using keel::pcm::absolute_error;
using keel::pcm::accepted_candidates;
using keel::pcm::anchor_init_from_string;
using keel::pcm::AnchorInit;
using keel::pcm::CandidateLabel;
using keel::pcm::CandidateOptions;
using keel::pcm::CandidateSet;
using keel::pcm::CandidateSet2;
using keel::pcm::CandidateSet3;
using keel::pcm::Classification;
using keel::pcm::classify;
using keel::pcm::evaluate_merge;
using keel::pcm::generate_candidates;
using keel::pcm::information_from_left_covariance;
using keel::pcm::local_maps;
using keel::pcm::LocalMaps;
using keel::pcm::LocalMaps2;
using keel::pcm::LocalMaps3;
using keel::pcm::LocalSolution;
using keel::pcm::LocalSolution2;
using keel::pcm::LocalSolution3;
using keel::pcm::LocalSolveOptions;
using keel::pcm::merge_maps;
using keel::pcm::merge_method_kind_from_string;
using keel::pcm::MergeDataset;
using keel::pcm::MergeDataset2;
using keel::pcm::MergeDataset3;
using keel::pcm::MergeMethod;
using keel::pcm::MergeMethodKind;
using keel::pcm::MergeMetrics;
using keel::pcm::MergeOptions;
using keel::pcm::MergeResult;
using keel::pcm::MergeResult2;
using keel::pcm::MergeResult3;
using keel::pcm::MethodOutcome;
using keel::pcm::PoseGraphFor;
using keel::pcm::PoseGraphOf;
using keel::pcm::relative_error;
using keel::pcm::rotation_error;
using keel::pcm::run_merge_dataset;
using keel::pcm::solve_local;
using keel::pcm::split_two_robots;
using keel::pcm::SplitOptions;
using keel::pcm::TrajectoryError;
using keel::pcm::TwoRobotScenario;
using keel::pcm::TwoRobotScenario2;
using keel::pcm::TwoRobotScenario3;
}  // namespace keel::pcm
