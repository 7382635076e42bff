// The graphs of ext_robust_backend's single-robot cells, written as g2o files for the side-by-side with
// Kimera-RPGO (bench/side_by_side/robust.sh with PREPARED=1): the study's own generator
// (RobustBackend::trial_graph) on the experiment's seed, so the files are the graphs the experiment runs as
// one robot (g2o round trips every field to the last bit, graph/g2o.hpp). The clean subset's edges come first
// and the wrong closures after them.
//
// Usage: keel_robust_graphs CONFIG PROFILE OUT_DIR [TRIALS [SEED]]   (TRIALS: the first trials of each cell,
// default all; SEED: instead of the experiment's, for graphs drawn fresh) Output: OUT_DIR/<key>.t<trial>.g2o
// per graph, and one line per graph on stdout: "<key>.t<trial>=<path> <n>", n the number of edges before the
// wrong closures.
import keel.core;
import keel.graph;
import keel.repro;
import keel.study;

#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 4 || argc > 6) {
    std::fprintf(stderr, "usage: keel_robust_graphs CONFIG PROFILE OUT_DIR [TRIALS [SEED]]\n");
    return 2;
  }
  try {
    using keel::study::ch4::RobustBackend;
    const auto config = keel::repro::ExperimentConfig::load(argv[1], argv[2]);
    const auto options = RobustBackend::Options::read(config.params);
    const int trials = argc >= 5 ? std::stoi(argv[4]) : options.trials;
    const std::filesystem::path dir = argv[3];
    std::filesystem::create_directories(dir);
    const keel::core::Streams streams(argc == 6 ? std::stoull(argv[5]) : config.seed);
    std::vector<RobustBackend::CleanGraph> clean;
    for (std::size_t g = 0; g < options.graphs.size(); ++g)
      clean.push_back(RobustBackend::clean_graph(options, g));
    for (const auto& cell : RobustBackend::make_cells(options)) {
      if (cell.robots != 1) continue;
      for (int t = 0; t < trials && t < options.trials; ++t) {
        const std::string key = cell.key.name() + ".t" + std::to_string(t);
        const auto path = dir / (key + ".g2o");
        std::size_t edges = 0;
        if (options.graphs[cell.graph].dimension == 2) {
          keel::graph::write_g2o(
              RobustBackend::trial_graph(clean[cell.graph].g2, options, cell, t, streams).graph, path);
          edges = clean[cell.graph].g2.edges.size();
        } else {
          keel::graph::write_g2o(
              RobustBackend::trial_graph(clean[cell.graph].g3, options, cell, t, streams).graph, path);
          edges = clean[cell.graph].g3.edges.size();
        }
        std::printf("%s=%s %zu\n", key.c_str(), path.c_str(), edges);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "keel_robust_graphs: %s\n", e.what());
    return 1;
  }
  return 0;
}
