// keel.eval — the curated facade of engine/eval: evaluation of outlier-rejection methods (thesis §2.6–2.7).
// The map-merging pipeline of §2.6 (local solves and marginals, selection, merged solve), its metrics
// (TPR/FPR, trajectory errors, normalized χ²), the combinatorial reference of eq. 2.5, and the chapter-2
// studies the experiments run. Facade rules (docs/DESIGN.md) as every area.
module;
#include "eval/clique_scale.hpp"
#include "eval/config.hpp"
#include "eval/merge.hpp"
#include "eval/studies.hpp"
#include "eval/world1d_study.hpp"
export module keel.eval;

export namespace keel::eval {
// map merging (§2.6)
using keel::eval::accepted_candidates;
using keel::eval::AnchorInit;
using keel::eval::local_maps;
using keel::eval::LocalMaps;
using keel::eval::LocalSolution;
using keel::eval::LocalSolution2;
using keel::eval::LocalSolution3;
using keel::eval::LocalSolveOptions;
using keel::eval::merge_maps;
using keel::eval::MergeDataset;
using keel::eval::MergeDataset2;
using keel::eval::MergeDataset3;
using keel::eval::MergeMethod;
using keel::eval::MergeMethodKind;
using keel::eval::MergeOptions;
using keel::eval::MergeResult;
using keel::eval::MergeResult2;
using keel::eval::MergeResult3;
using keel::eval::MethodOutcome;
using keel::eval::run_merge_dataset;
using keel::eval::solve_local;
using keel::eval::to_string;
// metrics
using keel::eval::absolute_error;
using keel::eval::Classification;
using keel::eval::classify;
using keel::eval::evaluate_merge;
using keel::eval::MergeMetrics;
using keel::eval::relative_error;
using keel::eval::rotation_error;
using keel::eval::TrajectoryError;
// 1D world study (Figs. 2.2–2.3) and the combinatorial reference of eq. 2.5
using keel::eval::combinatorial_method_from_string;
using keel::eval::CombinatorialComparison;
using keel::eval::CombinatorialMethod;
using keel::eval::CombinatorialResult;
using keel::eval::compare_to_combinatorial;
using keel::eval::count_inconsistent_pairs;
using keel::eval::kCombinatorialExhaustiveMax;
using keel::eval::kCombinatorialPrunedMax;
using keel::eval::max_consistent_set_combinatorial;
using keel::eval::run_timing_sweep;
using keel::eval::run_world1d_study;
using keel::eval::Selector1D;
using keel::eval::selector1d_from_string;
using keel::eval::SelectorComparison;
using keel::eval::TimingCurve;
using keel::eval::TimingSweep;
using keel::eval::TimingSweepOptions;
using keel::eval::World1DOutcome;
using keel::eval::World1DStudy;
using keel::eval::World1DStudyOptions;
// maximum clique at scale (beyond the thesis): exact, heuristic and densest subgraph on the same graphs
using keel::eval::CliqueGraphOutcome;
using keel::eval::CliqueMethodOutcome;
using keel::eval::CliqueMethodSummary;
using keel::eval::CliqueScaleMethod;
using keel::eval::CliqueScaleOptions;
using keel::eval::CliqueScaleTally;
using keel::eval::compare_clique_methods;
using keel::eval::first_moment_clique_number;
using keel::eval::kAllCliqueScaleMethods;
using keel::eval::kCliqueScaleMethods;
using keel::eval::non_adjacent_pairs;
using keel::eval::planted_cell_name;
using keel::eval::planted_clique_figure;
using keel::eval::PlantedCliqueCell;
using keel::eval::PlantedCliqueStudy;
using keel::eval::PlantedCliqueStudyOptions;
using keel::eval::record_clique_group;
using keel::eval::record_planted_clique_study;
using keel::eval::run_planted_clique_study;
using keel::eval::run_two_robot_clique_study;
using keel::eval::run_world1d_clique_study;
using keel::eval::summarize_clique_method;
using keel::eval::World1DCliqueOptions;
// chapter-2 studies: measurement regimes, local pairs, data sets in parallel, summaries, calibration of Q
using keel::eval::apply_regime;
using keel::eval::LocalPair;
using keel::eval::MeasurementRegime;
using keel::eval::method_index;
using keel::eval::methods_of;
using keel::eval::MethodSummary;
using keel::eval::pool_calibration;
using keel::eval::pool_chi2_at_truth;
using keel::eval::PoolCalibration;
using keel::eval::proven_optimal;
using keel::eval::record_dataset_timings;
using keel::eval::record_local_pair;
using keel::eval::run_merge_datasets;
using keel::eval::run_method_sweep;
using keel::eval::same_selections;
using keel::eval::solve_local_pair;
using keel::eval::StudyMethod;
using keel::eval::summarize_method;
// readers of the options structs from an experiment's [params]
using keel::eval::load_scenario_2d;
using keel::eval::load_scenario_3d;
using keel::eval::read_candidate_options;
using keel::eval::read_methods;
using keel::eval::read_range;
using keel::eval::read_regime;
using keel::eval::read_regimes;
using keel::eval::read_scgp_options;
using keel::eval::read_split;
using keel::eval::read_world1d_options;
}  // namespace keel::eval
