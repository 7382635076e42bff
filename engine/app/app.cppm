// keel.app — keel on a researcher's own files (see app/files.hpp).
module;
#include "app/files.hpp"
export module keel.app;

export namespace keel::app {
using keel::app::graph_dimension;
using keel::app::GraphSummary;
using keel::app::inter_robot_candidates;
using keel::app::merged_graph;
using keel::app::PcmOptions;
using keel::app::PcmRun;
using keel::app::PcmRun2;
using keel::app::PcmRun3;
using keel::app::Progress;
using keel::app::read_labels;
using keel::app::run_pcm;
using keel::app::solve_options;
using keel::app::split_files;
using keel::app::SplitFilesOptions;
using keel::app::summarize;
}  // namespace keel::app
