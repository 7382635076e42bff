// keel.core — the curated facade of engine/core, the foundation tier (docs/DESIGN.md "Tiers"): numerics that
// every area shares, random streams, names, strict TOML, timing, parallel loops and progress. Facade rules
// 1–3 of DESIGN.md: the global module fragment includes the area's ordinary headers, and the export block
// re-exports names with using-declarations. Nothing here imports another facade. Consumers: `import
// keel.core;` before any #include that reaches Eigen or Ceres.
module;
#include "core/bound.hpp"
#include "core/config.hpp"
#include "core/names.hpp"
#include "core/parallel.hpp"
#include "core/parse.hpp"
#include "core/progress.hpp"
#include "core/random.hpp"
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
using keel::core::Streams;
// the bound and status of every search that can stop early and every certificate
using keel::core::Bound;
using keel::core::format_lower;
using keel::core::format_upper;
using keel::core::round_down;
using keel::core::round_up;
using keel::core::search_status_from_string;
using keel::core::SearchStatus;
using keel::core::to_string;
// parallel loop and progress
using keel::core::default_threads;
using keel::core::format_duration;
using keel::core::parallel_for;
using keel::core::Progress;
// strict configuration
using keel::core::config_type_name;
using keel::core::ConfigError;
using keel::core::ConfigTable;
using keel::core::ConfigValue;
using keel::core::load_toml;
// the one parser of integers, reals, id ranges and whole files (core/parse.hpp)
using keel::core::IdRange;
using keel::core::is_header_field;
using keel::core::NumericCsv;
using keel::core::parse_id_list;
using keel::core::parse_id_range;
using keel::core::parse_integer;
using keel::core::parse_numeric_csv;
using keel::core::parse_real;
using keel::core::quote_token;
using keel::core::read_text_file;
using keel::core::read_whole_file;
using keel::core::split_fields;
using keel::core::to_integer;
using keel::core::to_real;
// summary statistics and wall-clock durations
using keel::core::Clock;
using keel::core::mean_std;
using keel::core::MeanStd;
using keel::core::median;
using keel::core::Proportion;
using keel::core::quantile_sorted;
using keel::core::seconds_since;
using keel::core::wilson_interval;
}  // namespace keel::core
