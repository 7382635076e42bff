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
#include "study/ch4/robust_backend.hpp"
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

// What the experiments' drivers run (every study) and what the benchmarks and the facade tests call besides
// (their inputs: the data sets of Tables 2.1-2.2, the alignment problem of a world, the Monte Carlo of ch.
// 5); everything else of engine/study is internal to it.

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
// used by the benchmarks and the facade tests
using keel::study::ch2::dataset_consistency_matrices;
using keel::study::ch2::load_scenario_2d;
using keel::study::ch2::load_scenario_3d;
using keel::study::ch2::solve_local_pair;
}  // namespace keel::study::ch2

// Chapter 3: trajectory alignment without data association.
export namespace keel::study::ch3 {
using keel::study::ch3::AlignmentComparison;
using keel::study::ch3::Example;
using keel::study::ch3::HullSubstitute;
using keel::study::ch3::RegimeGrid;
using keel::study::ch3::Sensitivity;
using keel::study::ch3::TerrainComparison;
// used by the benchmarks and the facade tests
using keel::study::ch3::problem_of;
}  // namespace keel::study::ch3

// Chapter 4: certifiable planar SLAM.
export namespace keel::study::ch4 {
using keel::study::ch4::CertifiedBenchmark;
using keel::study::ch4::CertifiedNoiseSweep;
using keel::study::ch4::Exactness;
using keel::study::ch4::FirstSegment;
using keel::study::ch4::RobustBackend;
using keel::study::ch4::Segments;
using keel::study::ch4::WholeDataCertificate;
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
// used by the benchmarks and the facade tests
using keel::study::ch5::CompositionSetup;
using keel::study::ch5::convert_ssc_prediction;
using keel::study::ch5::relative_pose_setup;
using keel::study::ch5::simulate_composition;
using keel::study::ch5::simulate_relative_pose;
}  // namespace keel::study::ch5
