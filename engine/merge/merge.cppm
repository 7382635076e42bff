// keel.merge — the curated facade of engine/merge (tier "algorithms", docs/DESIGN.md "Tiers"): robust
// multi-robot map merging (thesis §2.6), the outlier-rejection methods of §2.7 behind one MergeMethod, and
// the robust back end (robust.hpp).
// Facade rules as every area.
module;
#include "merge/merge.hpp"
#include "merge/robust.hpp"
export module keel.merge;

export namespace keel::merge {
// §2.6 steps i, ii and iv
using keel::merge::accepted_candidates;
using keel::merge::anchor_init_from_string;
using keel::merge::AnchorInit;
using keel::merge::local_maps;
using keel::merge::LocalMaps;
using keel::merge::LocalMaps2;
using keel::merge::LocalMaps3;
using keel::merge::LocalSolution;
using keel::merge::LocalSolution2;
using keel::merge::LocalSolution3;
using keel::merge::LocalSolveOptions;
using keel::merge::merge_maps;
using keel::merge::MergeOptions;
using keel::merge::MergeResult;
using keel::merge::MergeResult2;
using keel::merge::MergeResult3;
using keel::merge::solve_local;
// step iii: the methods of §2.7
using keel::merge::Dcs;
using keel::merge::Densest;
using keel::merge::merge_method_kind_from_string;
using keel::merge::MergeMethod;
using keel::merge::MergeMethodKind;
using keel::merge::MethodOptions;
using keel::merge::NoOutliers;
using keel::merge::Pcm;
using keel::merge::Ransac;
using keel::merge::Scgp;
using keel::merge::select;
using keel::merge::to_string;
// a robust back end for one or several robots: PCM per robot and pair, residual check or GNC, certified solve
using keel::merge::robust;
using keel::merge::robust_gnc_from_string;
using keel::merge::robust_residual_test_from_string;
using keel::merge::robust_selector_from_string;
using keel::merge::RobustCandidate;
using keel::merge::RobustGnc;
using keel::merge::RobustGncRound;
using keel::merge::RobustGroup;
using keel::merge::RobustOptions;
using keel::merge::RobustProgress;
using keel::merge::RobustResidualTest;
using keel::merge::RobustRun;
using keel::merge::RobustRun2;
using keel::merge::RobustRun3;
using keel::merge::RobustSelector;
using keel::merge::snooping_statistics;
}  // namespace keel::merge
