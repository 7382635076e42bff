// keel.pcm — the curated facade of engine/pcm (thesis ch. 2): pairwise consistency maximisation. The PCM problem of
// eq. 2.5 is solved as a maximum clique of the consistency graph (§2.5) — exact branch and bound in the spirit of
// Pattabiraman et al. (2015), their greedy heuristic, and a brute-force reference for validation.
// Facade rules (docs/DESIGN.md): includes in the global module fragment, using-declarations in the export block,
// no import of another facade.
module;
#include "pcm/clique.hpp"
#include "pcm/consistency.hpp"
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
}  // namespace keel::pcm
