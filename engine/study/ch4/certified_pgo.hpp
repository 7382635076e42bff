// Beyond the thesis: certified pose-graph optimization (pgo/certified.hpp) on every benchmark graph that
// SE-Sync ships (Rosen et al., IJRR 2019) and the planar and 3D data sets keel already reads — the isotropic
// (chordal) model solved by the Riemannian staircase, with a dual certificate whose lower bound survives
// rounding. One study, CertifiedBenchmark, in the study shape of repro/run.hpp; each data set is one solve.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "pgo/certified.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"

namespace keel::study::ch4 {

// One graph file of the benchmark: a data set of datasets/manifest.toml and a file in it.
struct CertifiedGraphFile {
  std::string name;     // the key in the results
  std::string dataset;  // the manifest's data set
  std::string file;     // relative to the data set's folder
  int dimension = 2;    // 2 (EDGE_SE2) or 3 (EDGE_SE3:QUAT)
};

// The certified solve's options that every ch4 study of whole graphs reads from its [params]: gap_tolerance,
// max_rank, max_iterations and stationarity_tolerance (the caller sets the rest and validates).
[[nodiscard]] pgo::CertifiedOptions read_certified_solve(const core::ConfigTable& p);
// The entries of [params.graphs] that the profile's `datasets` names, in that order. Every entry is read and
// checked (dataset, file, dimension 2 or 3), and `extra`, when given, reads each entry's further keys.
[[nodiscard]] std::vector<CertifiedGraphFile> read_graph_files(
    const core::ConfigTable& p,
    const std::function<void(const std::string& name, const core::ConfigTable& entry)>& extra = {});

// read_graph_files with each entry's `poses` (>= 0; 0: every pose): the first poses of each file.
struct GraphPrefix {
  CertifiedGraphFile file;
  int poses = 0;
};
[[nodiscard]] std::vector<GraphPrefix> read_graph_prefixes(const core::ConfigTable& p);

// One data set's outcome.
struct CertifiedGraphOutcome {
  CertifiedGraphFile graph;
  int indefinite_information = 0;  // information blocks that are not positive definite (read for κ, τ only)
  pgo::CertifiedSummary summary;
};

struct CertifiedBenchmark {
  struct Options {
    std::vector<CertifiedGraphFile> graphs;  // in the order of the profile's `datasets`
    pgo::CertifiedOptions solve;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    std::vector<CertifiedGraphOutcome> graphs;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch4
