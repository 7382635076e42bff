// keel.study — the curated facade of engine/study, the studies tier (docs/DESIGN.md "Tiers"): every study of
// the thesis's tables and figures in one shape (repro/run.hpp), by chapter. Facade rules as every area; it
// imports no facade (drivers import keel.repro beside it for study_main).
module;
#include "study/ch2/clique_scale.hpp"
#include "study/ch2/config.hpp"
#include "study/ch2/merge_eval.hpp"
#include "study/ch2/city_table.hpp"
#include "study/ch2/noise_regimes.hpp"
#include "study/ch2/substitute_3d.hpp"
#include "study/ch2/threshold_sweep.hpp"
#include "study/ch2/two_robot.hpp"
#include "study/ch2/world1d.hpp"
#include "study/ch2/density_sweep.hpp"
#include "study/ch2/timing.hpp"
#include "study/ch2/world1d_comparison.hpp"
#include "study/ch2/world1d_study_common.hpp"
#include "study/ch4/certified_noise.hpp"
#include "study/ch4/certified_pgo.hpp"
#include "study/ch4/segments.hpp"
#include "study/ch4/exactness.hpp"
#include "study/ch4/first_segment.hpp"
#include "study/ch4/segments_study.hpp"
#include "study/ch4/whole_data_certificate.hpp"
#include "study/ch3/comparison.hpp"
#include "study/ch3/config.hpp"
#include "study/ch3/alignment_comparison.hpp"
#include "study/ch3/example.hpp"
#include "study/ch3/hull_substitute.hpp"
#include "study/ch3/regime_grid.hpp"
#include "study/ch3/sensitivity.hpp"
#include "study/ch3/terrain_comparison.hpp"
#include "study/ch5/composition.hpp"
#include "study/ch5/composition_setup.hpp"
#include "study/ch5/length_sweep.hpp"
#include "study/ch5/noise_sweep.hpp"
#include "study/ch5/relative_pose.hpp"
#include "study/ch5/unscented_ssc.hpp"
#include "study/ch5/pair_simulation.hpp"
#include "study/ch5/pair_correlation.hpp"
#include "study/ch5/pair_sample_size.hpp"
#include "study/ch5/pairs.hpp"
#include "study/ch5/pairs_vs_ssc.hpp"
#include "study/ch5/simulate.hpp"
export module keel.study;

// Chapter 2: pairwise consistency maximization.
export namespace keel::study::ch2 {
using keel::study::ch2::CityTable;
using keel::study::ch2::CliqueScale;
using keel::study::ch2::DensitySweep;
using keel::study::ch2::NoiseRegimes;
using keel::study::ch2::Substitute3D;
using keel::study::ch2::ThresholdSweep;
using keel::study::ch2::Timing;
using keel::study::ch2::World1DComparison;
// the machinery behind them: metrics and data sets of Tables 2.1–2.2, the two-robot studies, the 1D world,
// the clique search at scale, and the config readers
using keel::study::ch2::absolute_error;
using keel::study::ch2::apply_regime;
using keel::study::ch2::Classification;
using keel::study::ch2::classify;
using keel::study::ch2::compare_clique_methods;
using keel::study::ch2::compare_to_combinatorial;
using keel::study::ch2::dataset_consistency_matrices;
using keel::study::ch2::evaluate_merge;
using keel::study::ch2::load_scenario_2d;
using keel::study::ch2::load_scenario_3d;
using keel::study::ch2::LocalPair;
using keel::study::ch2::MeasurementRegime;
using keel::study::ch2::MergeDataset;
using keel::study::ch2::MergeDataset2;
using keel::study::ch2::MergeDataset3;
using keel::study::ch2::MergeMetrics;
using keel::study::ch2::method_index;
using keel::study::ch2::MethodOutcome;
using keel::study::ch2::methods_of;
using keel::study::ch2::MethodSummary;
using keel::study::ch2::pool_calibration;
using keel::study::ch2::pool_chi2_at_truth;
using keel::study::ch2::proven_optimal;
using keel::study::ch2::read_candidate_options;
using keel::study::ch2::read_methods;
using keel::study::ch2::read_world1d_options;
using keel::study::ch2::relative_error;
using keel::study::ch2::rotation_error;
using keel::study::ch2::run_merge_dataset;
using keel::study::ch2::run_merge_datasets;
using keel::study::ch2::run_method_sweep;
using keel::study::ch2::run_planted_clique_study;
using keel::study::ch2::run_timing_sweep;
using keel::study::ch2::run_world1d_study;
using keel::study::ch2::same_selections;
using keel::study::ch2::ScenarioFiles;
using keel::study::ch2::Selector1D;
using keel::study::ch2::selector1d_from_string;
using keel::study::ch2::solve_local_pair;
using keel::study::ch2::StudyMethod;
using keel::study::ch2::summarize_method;
using keel::study::ch2::to_string;
using keel::study::ch2::TrajectoryError;
using keel::study::ch2::World1DStudy;
using keel::study::ch2::World1DStudyOptions;
}  // namespace keel::study::ch2

// Chapter 3: trajectory alignment without data association.
export namespace keel::study::ch3 {
using keel::study::ch3::AlignmentComparison;
using keel::study::ch3::Example;
using keel::study::ch3::HullSubstitute;
using keel::study::ch3::RegimeGrid;
using keel::study::ch3::Sensitivity;
using keel::study::ch3::TerrainComparison;
// the machinery behind them and its config readers
using keel::study::ch3::AlignmentStudyOptions;
using keel::study::ch3::AlignmentStudyOutcome;
using keel::study::ch3::CertificateOutcome;
using keel::study::ch3::compare_methods;
using keel::study::ch3::ComparisonOptions;
using keel::study::ch3::fenced_summary;
using keel::study::ch3::FencedSummary;
using keel::study::ch3::HullStudyOptions;
using keel::study::ch3::HullStudyOutcome;
using keel::study::ch3::MethodOutcome;
using keel::study::ch3::problem_of;
using keel::study::ch3::read_align_options;
using keel::study::ch3::read_alignment_world_options;
using keel::study::ch3::read_certificate_options;
using keel::study::ch3::read_comparison_options;
using keel::study::ch3::read_hull_world_options;
using keel::study::ch3::read_methods;
using keel::study::ch3::reference_feature_scales;
using keel::study::ch3::run_alignment_study;
using keel::study::ch3::run_hull_study;
using keel::study::ch3::score_alignment;
using keel::study::ch3::SdpCheck;
using keel::study::ch3::standardized_problem_of;
using keel::study::ch3::WorldTruth;
using keel::study::ch4::CertifiedGraphFile;
using keel::study::ch4::CertifiedGraphOutcome;
}  // namespace keel::study::ch3

// Chapter 4: certifiable planar SLAM.
export namespace keel::study::ch4 {
using keel::study::ch4::CertifiedBenchmark;
using keel::study::ch4::CertifiedNoiseSweep;
using keel::study::ch4::Exactness;
using keel::study::ch4::FirstSegment;
using keel::study::ch4::Segments;
using keel::study::ch4::WholeDataCertificate;
// the machinery behind them and its config readers
using keel::study::ch4::ExactnessFamily;
using keel::study::ch4::ExactnessOptions;
using keel::study::ch4::ExactnessOutcome;
using keel::study::ch4::ExactnessTrial;
using keel::study::ch4::GlobalCertificateDataset;
using keel::study::ch4::GlobalCertificateOutcome;
using keel::study::ch4::GlobalCertificateRun;
using keel::study::ch4::GlobalCertificateStudyOptions;
using keel::study::ch4::GlobalCertificateStudyOutcome;
using keel::study::ch4::load_global_certificate_datasets;
using keel::study::ch4::load_planar_dataset;
using keel::study::ch4::MethodOutcome;
using keel::study::ch4::PlanarDataset;
using keel::study::ch4::PlanarDatasetFiles;
using keel::study::ch4::read_certify_options;
using keel::study::ch4::read_exactness_options;
using keel::study::ch4::read_global_certificate_files;
using keel::study::ch4::read_global_certificate_study_options;
using keel::study::ch4::read_segment_study_options;
using keel::study::ch4::run_exactness_study;
using keel::study::ch4::run_global_certificate_study;
using keel::study::ch4::run_segment_study;
using keel::study::ch4::SegmentOutcome;
using keel::study::ch4::SegmentStudyOptions;
using keel::study::ch4::SegmentStudyOutcome;
}  // namespace keel::study::ch4

// Chapter 5: uncertainty of jointly correlated poses.
export namespace keel::study::ch5 {
using keel::study::ch5::Composition;
using keel::study::ch5::LengthSweep;
using keel::study::ch5::NoiseSweep;
using keel::study::ch5::PairCorrelation;
using keel::study::ch5::PairSampleSize;
using keel::study::ch5::PairsVsSsc;
using keel::study::ch5::RelativePose;
using keel::study::ch5::UnscentedSsc;
// the Monte Carlo behind them
using keel::study::ch5::composition_step_covariance;
using keel::study::ch5::CompositionOutcome;
using keel::study::ch5::CompositionPrediction;
using keel::study::ch5::CompositionSetup;
using keel::study::ch5::convert_ssc_prediction;
using keel::study::ch5::pair_statistics;
using keel::study::ch5::PairRecord;
using keel::study::ch5::PairStatistics;
using keel::study::ch5::PairStudySetup;
using keel::study::ch5::relative_pose_setup;
using keel::study::ch5::RelativePoseOutcome;
using keel::study::ch5::RelativePoseSetup;
using keel::study::ch5::simulate_composition;
using keel::study::ch5::simulate_pairs_2d;
using keel::study::ch5::simulate_relative_pose;
using keel::study::ch5::SscConversion;
}  // namespace keel::study::ch5
