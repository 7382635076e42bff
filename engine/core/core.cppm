// keel.core — the curated facade of engine/core (DESIGN.md, facade rules 1–3): the global module fragment
// includes the area's ordinary headers, and the export block re-exports names with using-declarations.
// Nothing here imports another facade. Consumers: `import keel.core;` before any #include that reaches Eigen
// or Ceres.
module;
#include "core/baseline.hpp"
#include "core/config.hpp"
#include "core/experiment.hpp"
#include "core/names.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "core/random.hpp"
#include "core/prose.hpp"
#include "core/report.hpp"
#include "core/shard.hpp"
#include "core/results.hpp"
#include "core/statistics.hpp"
#include "core/timing.hpp"
export module keel.core;

export namespace keel::core {
// enum <-> string name tables (docs/DESIGN.md "Naming and errors")
using keel::core::NameTable;
using keel::core::throw_unknown_name;
using keel::core::throw_unnamed_value;
// random streams
using keel::core::Rng;
using keel::core::splitmix64;
// parallel loop and progress
using keel::core::default_threads;
using keel::core::format_duration;
using keel::core::parallel_for;
using keel::core::Progress;
// sharded trial loops (--slice / --merge) and their per-trial records
using keel::core::load;
using keel::core::Reader;
using keel::core::save;
using keel::core::trial_loop;
using keel::core::Writer;
// strict configuration
using keel::core::config_type_name;
using keel::core::ConfigError;
using keel::core::ConfigTable;
using keel::core::ConfigValue;
using keel::core::ExperimentConfig;
using keel::core::fnv1a64;
using keel::core::load_toml;
using keel::core::Tolerance;
// results, figures, experiment main
using keel::core::Check;
using keel::core::code_changed_since;
using keel::core::ecdf_layer;
using keel::core::Experiment;
using keel::core::experiment_main;
using keel::core::ExperimentBody;
using keel::core::Figure;
using keel::core::git_describe;
using keel::core::histogram_layer;
using keel::core::hline_layer;
using keel::core::Layer;
using keel::core::level_tag;
using keel::core::line_layer;
using keel::core::Panel;
using keel::core::Results;
using keel::core::round_significant;
using keel::core::scatter_layer;
using keel::core::write_file_atomic;
// baselines and report
using keel::core::baseline_path;
using keel::core::bless;
using keel::core::diff_against_baseline;
using keel::core::DiffResult;
using keel::core::DiffRow;
using keel::core::format_diff;
using keel::core::latest_path;
using keel::core::list_experiments;
using keel::core::prose_number_problems;
using keel::core::ReportOptions;
using keel::core::same_results;
using keel::core::write_report;
// summary statistics and wall-clock durations
using keel::core::Clock;
using keel::core::mean_std;
using keel::core::MeanStd;
using keel::core::median;
using keel::core::seconds_since;
}  // namespace keel::core
