// keel.sim — the curated facade of engine/sim: data fabricated for experiments. The 1D world of §2.7.1,
// two-robot scenarios split from a single-robot dataset with candidate inter-robot loop closures (inliers
// from the dataset, perceptually aliased groups, random outliers; §2.7.2–2.7.3), measurement resampling about
// the ground truth, random consistency graphs, the alignment worlds of chapter 3 (§3.7) and
// a synthetic ship hull surveyed by an HAUV's DVL (substitute for the field data of §3.8). Facade rules
// (docs/DESIGN.md) as every area.
module;
#include "sim/alignment_world.hpp"
#include "sim/terrain.hpp"
#include "sim/hull_world.hpp"
#include "sim/loop_closures.hpp"
#include "sim/random_graph.hpp"
#include "sim/two_robot.hpp"
#include "sim/world1d.hpp"
export module keel.sim;

export namespace keel::sim {
// 1D world (§2.7.1)
using keel::sim::generate_world1d;
using keel::sim::MeasurementLabel;
using keel::sim::to_string;
using keel::sim::World1D;
using keel::sim::world1d_consistency_matrix;
using keel::sim::world1d_options_with_total;
using keel::sim::World1DOptions;
// two-robot scenarios (§2.7.2–2.7.3)
using keel::sim::CandidateLabel;
using keel::sim::CandidateOptions;
using keel::sim::CandidateSet;
using keel::sim::CandidateSet2;
using keel::sim::CandidateSet3;
using keel::sim::generate_candidates;
using keel::sim::resample_measurements;
using keel::sim::split_two_robots;
using keel::sim::SplitOptions;
using keel::sim::TwoRobotScenario;
using keel::sim::TwoRobotScenario2;
using keel::sim::TwoRobotScenario3;
// alignment worlds (§3.7)
using keel::sim::AlignmentWorld;
using keel::sim::AlignmentWorldOptions;
using keel::sim::FeatureField;
using keel::sim::FeatureFunction;
using keel::sim::kEarthRadius;
using keel::sim::lawn_mower;
using keel::sim::LawnMower;
using keel::sim::make_alignment_world;
using keel::sim::make_terrain_world;
using keel::sim::read_terrain_grid;
using keel::sim::TerrainField;
using keel::sim::TerrainGrid;
using keel::sim::TerrainWorld;
using keel::sim::to_length_units;
// ship-hull substitute (§3.8, Fig. 3.5)
using keel::sim::DvlOptions;
using keel::sim::fit_surface_curvature;
using keel::sim::graph_curvature;
using keel::sim::HullSurface;
using keel::sim::HullSurfaceOptions;
using keel::sim::HullWorld;
using keel::sim::HullWorldOptions;
using keel::sim::make_hull_world;
using keel::sim::SurfaceCurvature;
// random consistency graphs
using keel::sim::planted_clique_graph;
using keel::sim::PlantedClique;
using keel::sim::random_graph;
// corrupted loop closures (inputs for the certified solver beyond the thesis)
using keel::sim::add_wrong_loop_closures;
using keel::sim::corrupt_loop_closures;
using keel::sim::CorruptedGraph;
using keel::sim::CorruptedGraph2;
using keel::sim::CorruptedGraph3;
using keel::sim::LoopClosureCorruption;
using keel::sim::robot_of_pose;
using keel::sim::RobotSplit;
using keel::sim::split_into_robots;
using keel::sim::wrong_closure_kind_from_string;
using keel::sim::WrongClosureKind;
using keel::sim::WrongClosures;
}  // namespace keel::sim
