// Beyond the thesis: the certified solve (pgo/certified.hpp) where the relaxation need not be exact. Subsets
// of SE-Sync's benchmark graphs (their first poses) with their loop closures corrupted
// (sim/loop_closures.hpp): rotation noise at several levels, and outlier closures. One study,
// CertifiedNoiseSweep, in the study shape of repro/run.hpp; each graph is one certified solve plus one local
// solve from the file's own estimates (a second feasible point that a false certificate or bound would
// contradict).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/random.hpp"
#include "graph/pose_graph.hpp"
#include "pgo/certified.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"

namespace keel::study::ch4 {

// The first `poses` poses of a benchmark file (0: all of them).
struct NoiseSweepSubset {
  std::string name;     // the key in the results
  std::string dataset;  // the manifest's data set
  std::string file;     // relative to the data set's folder
  int dimension = 2;
  int poses = 0;
};

// One corruption level: rotation noise (rad) on every loop closure, or a fraction of outlier closures.
struct NoiseSweepLevel {
  std::string name;  // "rot0p3" for 0.3 rad, "out10" for 10 % outliers
  double rotation_noise = 0.0;
  double outlier_fraction = 0.0;
};

// One generated graph of the sweep: subset k at level l, draw m (stream index k · draws + m of the streams'
// "graphs" child, the same at every level: common random numbers).
struct NoiseSweepGraph {
  std::size_t subset = 0, level = 0;
  int draw = 0;
  repro::KeyPath key;  // <subset>.<level>.d<draw>
  int loop_closures = 0, outliers = 0;
  graph::PoseGraph2D g2;  // the one of the subset's dimension
  graph::PoseGraph3D g3;
};

struct NoiseSweepOutcome {
  repro::KeyPath key;
  std::size_t subset = 0, level = 0;
  int draw = 0, loop_closures = 0, outliers = 0;
  pgo::CertifiedSummary summary;      // the certified solve
  pgo::CertifiedSummary alternative;  // rank d only, from the file's own estimates
};

struct CertifiedNoiseSweep {
  struct Options {
    std::vector<NoiseSweepSubset> subsets;  // in the order of the profile's `datasets`
    std::vector<NoiseSweepLevel> levels;    // the rotation noises, then the outlier fractions
    int draws = 1;                          // graphs per subset and level
    pgo::CertifiedOptions solve;
    // The second solve: CertifiedOptions as `solve` but max_rank = d, no chordal initialization, and this
    // time limit.
    double alternative_time_limit_s = 0.0;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    std::vector<NoiseSweepOutcome> graphs;
  };
  // The sweep's graphs in run order (subset, level, draw), from `streams` (the experiment's seed, base 0):
  // the experiment solves these, and bench/side_by_side/noise_graphs.cpp writes the same ones for SE-Sync.
  static std::vector<NoiseSweepGraph> make_graphs(const Options& options, const core::Streams& streams);
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch4
