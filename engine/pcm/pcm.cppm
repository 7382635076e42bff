// keel.pcm — the curated facade of engine/pcm (thesis ch. 2): pairwise consistency maximisation. The
// consistency metric of eq. 2.4 and the matrix Q, the consistency graph and its maximum clique (§2.5: exact
// branch and bound, Pattabiraman et al.'s heuristic, a brute-force reference), and the selection methods PCM,
// SCGP and RANSAC. Facade rules (docs/DESIGN.md): includes in the global module fragment, using-declarations
// in the export block, no import of another facade.
module;
#include "pcm/clique.hpp"
#include "pcm/combinatorial.hpp"
#include "pcm/consistency.hpp"
#include "pcm/densest.hpp"
#include "pcm/selection.hpp"
export module keel.pcm;

export namespace keel::pcm {
// consistency metric (eq. 2.4) and the matrix Q
using keel::pcm::Composition;
using keel::pcm::composition_from_string;
using keel::pcm::consistency_matrix;
using keel::pcm::consistency_threshold;
using keel::pcm::ConsistencyMatrix;
using keel::pcm::ConsistencyOptions;
using keel::pcm::information_from_left_covariance;
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
// consistency graph and maximum clique
using keel::pcm::clique_algorithm_from_string;
using keel::pcm::CliqueAlgorithm;
using keel::pcm::CliqueOptions;
using keel::pcm::CliqueResult;
using keel::pcm::ConsistencyGraph;
using keel::pcm::densest_subgraph;
using keel::pcm::DensestOptions;
using keel::pcm::DensestResult;
using keel::pcm::DensestSelectOptions;
using keel::pcm::maximum_clique;
using keel::pcm::SearchStatus;
using keel::pcm::select_densest;
using keel::pcm::to_string;
// selection methods
using keel::pcm::scgp;
using keel::pcm::scgp_discretization_from_string;
using keel::pcm::ScgpDiscretization;
using keel::pcm::ScgpOptions;
using keel::pcm::ScgpResult;
using keel::pcm::select_pcm;
using keel::pcm::select_ransac;
using keel::pcm::select_scgp;
using keel::pcm::Selection;
// the combinatorial reference of eq. 2.5 (independent of the clique code)
using keel::pcm::combinatorial_method_from_string;
using keel::pcm::CombinatorialMethod;
using keel::pcm::CombinatorialResult;
using keel::pcm::count_inconsistent_pairs;
using keel::pcm::kCombinatorialExhaustiveMax;
using keel::pcm::kCombinatorialPrunedMax;
using keel::pcm::max_consistent_set_combinatorial;
}  // namespace keel::pcm
