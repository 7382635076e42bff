// The graphs of ext_certified_noise, written as g2o files for the side-by-side with SE-Sync
// (bench/side_by_side/noise.sh): the study's own generator (CertifiedNoiseSweep::make_graphs) on the
// experiment's seed, so the files are the graphs the experiment solves (g2o round trips every field to the
// last bit, graph/g2o.hpp).
//
// Usage: keel_noise_graphs CONFIG PROFILE OUT_DIR
// Output: OUT_DIR/<key>.g2o per graph, and one line per graph on stdout: "<key>=<path>".
import keel.core;
import keel.graph;
import keel.repro;
import keel.study;

#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: keel_noise_graphs CONFIG PROFILE OUT_DIR\n");
    return 2;
  }
  try {
    const auto config = keel::repro::ExperimentConfig::load(argv[1], argv[2]);
    const auto options = keel::study::ch4::CertifiedNoiseSweep::Options::read(config.params);
    const std::filesystem::path dir = argv[3];
    std::filesystem::create_directories(dir);
    for (const auto& g :
         keel::study::ch4::CertifiedNoiseSweep::make_graphs(options, keel::core::Streams(config.seed))) {
      const std::string key = g.key.name();
      const auto path = dir / (key + ".g2o");
      if (options.subsets[g.subset].dimension == 2)
        keel::graph::write_g2o(g.g2, path);
      else
        keel::graph::write_g2o(g.g3, path);
      std::printf("%s=%s\n", key.c_str(), path.c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "keel_noise_graphs: %s\n", e.what());
    return 1;
  }
  return 0;
}
