// keel.repro — the curated facade of engine/repro, the reproduction tier (docs/DESIGN.md "Tiers"): an
// experiment's config, main and results, figures, baselines, the report, and sharded trial loops. Facade
// rules as every area; it imports no other facade (consumers import keel.core beside it).
module;
#include "repro/archive.hpp"
#include "repro/baseline.hpp"
#include "repro/experiment.hpp"
#include "repro/experiment_config.hpp"
#include "repro/prose.hpp"
#include "repro/report.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "repro/shard.hpp"
export module keel.repro;

export namespace keel::repro {
// the run a study gets, and the main() of an experiment that runs one study
using keel::repro::run_context;
using keel::repro::RunContext;
using keel::repro::Study;
using keel::repro::study_main;
// sharded trial loops (--slice / --merge) and their per-trial records
using keel::repro::load;
using keel::repro::Reader;
using keel::repro::save;
using keel::repro::trial_loop;
using keel::repro::Writer;
// an experiment's configuration
using keel::repro::ExperimentConfig;
using keel::repro::fnv1a64;
using keel::repro::Tolerance;
// results, figures, experiment main
using keel::repro::Check;
using keel::repro::clean_commit;
using keel::repro::code_changed_since;
using keel::repro::ecdf_layer;
using keel::repro::Experiment;
using keel::repro::experiment_main;
using keel::repro::ExperimentBody;
using keel::repro::Figure;
using keel::repro::git_describe;
using keel::repro::histogram_layer;
using keel::repro::hline_layer;
using keel::repro::KeyPath;
using keel::repro::Layer;
using keel::repro::level_tag;
using keel::repro::line_layer;
using keel::repro::Panel;
using keel::repro::path;
using keel::repro::Results;
using keel::repro::round_significant;
using keel::repro::scatter_layer;
using keel::repro::Scope;
using keel::repro::write_file_atomic;
// baselines and report
using keel::repro::baseline_path;
using keel::repro::bless;
using keel::repro::diff_against_baseline;
using keel::repro::DiffResult;
using keel::repro::DiffRow;
using keel::repro::format_diff;
using keel::repro::latest_path;
using keel::repro::list_experiments;
using keel::repro::prose_number_problems;
using keel::repro::ReportOptions;
using keel::repro::same_results;
using keel::repro::write_report;
}  // namespace keel::repro
