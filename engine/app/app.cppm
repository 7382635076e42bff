// keel.app — keel on a researcher's own files, the one door of the `keel` command and the Python module:
// app::solve (solve.hpp), app::marginals (marginals.hpp), app::pcm (pcm.hpp), app::robust (robust.hpp),
// app::align_surveys (align.hpp), what a file holds or a two-robot split writes (files.hpp), and the output
// files of a command, written all or nothing (outputs.hpp).
module;
#include "app/align.hpp"
#include "app/files.hpp"
#include "app/marginals.hpp"
#include "app/outputs.hpp"
#include "app/pcm.hpp"
#include "app/progress.hpp"
#include "app/records.hpp"
#include "app/robust.hpp"
#include "app/solve.hpp"
#include "app/solver_log.hpp"
export module keel.app;

export namespace keel::app {
// align
using keel::app::align_surveys;
using keel::app::AlignSurveysOptions;
using keel::app::Dissimilarity;
using keel::app::dissimilarity_from_string;
using keel::app::read_survey_csv;
using keel::app::Survey;
using keel::app::survey_problem;
using keel::app::SurveyAlignment;
using keel::app::TerrainWorldTruth;
using keel::app::to_string;
using keel::app::WorldTruth;
using keel::app::write_alignment_world;
using keel::app::write_survey_csv;
using keel::app::write_terrain_world;
// files
using keel::app::graph_dimension;
using keel::app::GraphSummary;
using keel::app::read_labels;
using keel::app::split_files;
using keel::app::SplitFilesOptions;
using keel::app::summarize;
// solve
using keel::app::AnyGraph;
using keel::app::Certified;
using keel::app::CertifiedSolution;
using keel::app::CertifiedSolution2;
using keel::app::CertifiedSolution3;
using keel::app::GraphInput;
using keel::app::information_check;
using keel::app::initial_guess_from_name;
using keel::app::MaximumLikelihood;
using keel::app::read_graph;
using keel::app::read_graph_input;
using keel::app::Solution;
using keel::app::Solution2;
using keel::app::Solution3;
using keel::app::solve;
using keel::app::solve_certified;
using keel::app::SolveBackend;
// marginals
using keel::app::factorize;
using keel::app::marginals;
using keel::app::Marginals;
using keel::app::MarginalsRequest;
// pcm
using keel::app::Consistency;
using keel::app::consistency;
using keel::app::inter_robot_candidates;
using keel::app::merged_graph;
using keel::app::pcm;
using keel::app::PcmOptions;
using keel::app::PcmRun;
using keel::app::PcmRun2;
using keel::app::PcmRun3;
using keel::app::Progress;
using keel::app::score_selection;
using keel::app::SelectionScore;
// robust
using keel::app::robust;
using keel::app::robust_selector_from_string;
using keel::app::RobustCandidate;
using keel::app::RobustGroup;
using keel::app::RobustOptions;
using keel::app::RobustRun;
using keel::app::RobustRun2;
using keel::app::RobustRun3;
using keel::app::RobustSelector;
// records
using keel::app::FieldWriter;
using keel::app::proven_figures;
using keel::app::ProvenFigures;
using keel::app::write_record;
// outputs
using keel::app::check_folder_writable;
using keel::app::FolderFile;
using keel::app::OutputError;
using keel::app::OutputKind;
using keel::app::Outputs;
using keel::app::remove_temporaries_on_signals;
using keel::app::split_folder_files;
using keel::app::world_folder_files;
// Ceres's log
using keel::app::route_solver_log;
using keel::app::SolverLogSink;
}  // namespace keel::app
