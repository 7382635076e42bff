// Readers of the chapter-2 options structs from an experiment's [params] (one reader per struct, written
// once). Each reads its keys strictly (core::ConfigTable: unknown or missing keys are errors naming file,
// table, key and line), validates the struct, and turns a std::invalid_argument from validate() into a
// located core::ConfigError.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "study/ch2/two_robot.hpp"
#include "study/ch2/world1d.hpp"
#include "pcm/selection.hpp"
#include "sim/two_robot.hpp"
#include "sim/world1d.hpp"

namespace keel::study::ch2 {

// `[min, max]`: a pair of numbers.
std::pair<double, double> read_range(const core::ConfigTable& t, std::string_view key);

// `first`, `split`, `last`: robot a = poses [first, split), robot b = [split, last).
sim::SplitOptions read_split(const core::ConfigTable& t);

// `num_inliers`, `aliased_groups`, `aliased_group_size`, `random_outliers`, `random_sigma_translation` and
// `random_sigma_rotation` ([min, max]); optionally `near_miss_translation` and `near_miss_rotation` ([min,
// max], both or neither: near-miss aliased groups, sim::CandidateOptions).
sim::CandidateOptions read_candidate_options(const core::ConfigTable& t);

// `methods = [names]` and one [params.method.<name>] table each: `label`, `kind`, and the optional keys of
// that kind (defaults: merge::MergeMethod::make's): `p` (ransac, pcm_*, densest), `composition` (those and
// scgp), `dcs_phi` and `dcs_accept_scale` (dcs), `scgp_affinity_scale` and `scgp_discretization` (scgp),
// `densest_affinity_scale` (densest). A key of another kind is an unknown key.
std::vector<StudyMethod> read_methods(const core::ConfigTable& t);

// `scgp_affinity_scale`, `scgp_discretization`, `scgp_min_eigen_ratio` (the 1D-world studies).
pcm::ScgpOptions read_scgp_options(const core::ConfigTable& t);

// The world's noise model: `x`, `sigma_inlier`, `outlier_mean_range`, `outlier_sigma_min`,
// `outlier_sigma_max`, and with `with_counts` also `inliers_min/_max`, `aliased_min/_max`, `random_min/_max`.
sim::World1DOptions read_world1d_options(const core::ConfigTable& t, bool with_counts);

// A measurement regime table: `label`, `measurements` ("dataset" or "resampled"; resampled needs
// `noise_scale` and `resample_seed`).
MeasurementRegime read_regime(const core::ConfigTable& t, std::string name);

// Every name of `names` as a regime from [params.<table>.<name>].
std::vector<MeasurementRegime> read_regimes(const core::ConfigTable& p, std::string_view list_key,
                                            std::string_view table_key);

// The two-robot scenario of an experiment: `graph_file` and `ground_truth_file` of data set `dataset`, split
// at `first`, `split`, `last`; loading reads the files (datasets::resolve_dataset_file) and splits them
// (sim::split_two_robots).
struct ScenarioFiles {
  std::string dataset, graph_file, ground_truth_file;
  sim::SplitOptions split;
  static ScenarioFiles read(const core::ConfigTable& t);
};
[[nodiscard]] sim::TwoRobotScenario2 load_scenario_2d(const ScenarioFiles& files);
[[nodiscard]] sim::TwoRobotScenario3 load_scenario_3d(const ScenarioFiles& files);

}  // namespace keel::study::ch2
