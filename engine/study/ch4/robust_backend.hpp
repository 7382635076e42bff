// Beyond the thesis: the robust back end (merge/robust.hpp: PCM per robot and pair of robots, the residual
// check, the certified solve) on real graphs with wrong loop closures added (sim::add_wrong_loop_closures:
// random ones, or perceptually aliased groups), one robot or the graph cut into several
// (sim::split_into_robots). Each trial's answer is scored against the truth of its candidates (precision and
// recall of the kept closures) and against the certified optimum of the same robots' outlier-free graph (ATE,
// RPE); its certificate or proven gap, and its time per stage, are recorded. One study, RobustBackend, in the
// study shape of repro/run.hpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/fields.hpp"
#include "core/random.hpp"
#include "graph/pose_graph.hpp"
#include "merge/robust.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "sim/loop_closures.hpp"

namespace keel::study::ch4 {

// The first `poses` poses of a benchmark file (0: all of them) and the edges among them.
struct RobustBackendGraph {
  std::string name;     // the key in the results
  std::string dataset;  // the manifest's data set
  std::string file;     // relative to the data set's folder
  int dimension = 2;
  int poses = 0;
};

// One cell of the grid: a graph, a robot count, and the wrong closures (rate 0: none, kind unused).
struct RobustBackendCell {
  std::size_t graph = 0;
  int robots = 1;
  sim::WrongClosureKind kind = sim::WrongClosureKind::random;
  double rate = 0.0;
  repro::KeyPath key;  // <graph>.r<robots>.clean, or <graph>.r<robots>.<kind>.out<percent>
};

// One trial's record (the archive of a shard walks KEEL_FIELDS).
struct RobustBackendTrial {
  int cell = 0, trial = 0;
  bool refused = false;  // merge::robust threw (robots left without a common frame, a failed solve)
  std::string error;
  int true_closures = 0, wrong_closures = 0, kept_true = 0, kept_wrong = 0;
  int removed_true = 0, removed_wrong = 0;  // by the residual check
  bool cliques_proven = false;              // every group's selection has a proven size
  bool certified = false, proven = false;
  double relative_gap = 1.0;    // of the proven bound; 1 when nothing was proven
  double cost = 0.0;            // F of the certified solve's answer
  double ate = 0.0, rpe = 0.0;  // against the reference (the certified optimum of the outlier-free graph)
  int residual_rounds = 0;
  double time_s = 0.0, consistency_time_s = 0.0, selection_time_s = 0.0, residual_time_s = 0.0,
         solve_time_s = 0.0;
  KEEL_FIELDS(cell, trial, refused, error, true_closures, wrong_closures, kept_true, kept_wrong, removed_true,
              removed_wrong, cliques_proven, certified, proven, relative_gap, cost, ate, rpe, residual_rounds,
              time_s, consistency_time_s, selection_time_s, residual_time_s, solve_time_s)
};

// The certified solve of a graph's robots without wrong closures: every robot's odometry and every true
// loop closure (what a perfect selection keeps), the reference of ATE and RPE.
struct RobustBackendReference {
  std::size_t graph = 0;
  int robots = 1;
  bool certified = false;
  double cost = 0.0, relative_gap = 1.0, time_s = 0.0;
  std::vector<graph::SE2> poses2;  // the one of the graph's dimension
  std::vector<graph::SE3> poses3;
};

struct RobustBackend {
  struct Options {
    std::vector<RobustBackendGraph> graphs;  // in the order of the profile's `datasets`
    std::vector<int> robots;                 // robot counts
    std::vector<double> rates;               // shares of wrong closures; 0: the outlier-free cell
    std::vector<sim::WrongClosureKind> kinds;
    int group_size = 5;  // aliased groups' size
    int trials = 1;      // per cell
    merge::RobustOptions robust;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    std::vector<RobustBackendCell> cells;
    std::vector<RobustBackendReference> references;  // one per graph and robot count
    std::vector<RobustBackendTrial> trials;          // cell-major
  };
  // The grid's cells in run order: graph, robot count, then the clean cell and each kind's rates.
  static std::vector<RobustBackendCell> make_cells(const Options& options);
  // Graph g's outlier-free subset, read from its data set (in g2 or g3, by its dimension).
  struct CleanGraph {
    graph::PoseGraph2D g2;
    graph::PoseGraph3D g3;
  };
  static CleanGraph clean_graph(const Options& options, std::size_t g);
  // The ATE and RPE reference of graph g cut into `robots` robots (RobustBackendReference), from its clean
  // subset; bench/side_by_side/robust_graphs.cpp writes it for the side-by-side.
  static RobustBackendReference reference(const CleanGraph& clean, const Options& options, std::size_t g,
                                          int robots);
  // Trial t of `cell`: its graph's clean subset with the wrong closures the experiment draws appended (from
  // `streams`, the experiment's seed at base 0), so bench/side_by_side/robust_graphs.cpp writes the graphs
  // the experiment runs.
  static sim::CorruptedGraph2 trial_graph(const graph::PoseGraph2D& clean, const Options& options,
                                          const RobustBackendCell& cell, int trial,
                                          const core::Streams& streams);
  static sim::CorruptedGraph3 trial_graph(const graph::PoseGraph3D& clean, const Options& options,
                                          const RobustBackendCell& cell, int trial,
                                          const core::Streams& streams);
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch4
