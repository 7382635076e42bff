// The graphs of ext_robust_backend's cells, written as g2o files for the side-by-side with Kimera-RPGO
// (bench/side_by_side/robust.sh with PREPARED=N): the study's own generator (RobustBackend::trial_graph) on
// the experiment's seed, so the files are the graphs the experiment runs (g2o round trips every field to the
// last bit, graph/g2o.hpp). The clean subset's edges come first and the wrong closures after them.
//
// Usage: keel_robust_graphs CONFIG PROFILE OUT_DIR [TRIALS [SEED [ROBOTS]]]
//   TRIALS: the first trials of each cell (default all); SEED: instead of the experiment's, for graphs drawn
//   fresh; ROBOTS: the robot counts whose cells are written, comma-separated (default 1).
// Output, one line per trial on stdout:
//   one robot:   "<key>.t<trial>=<path> <n> <reference>", the graph OUT_DIR/<key>.t<trial>.g2o and n the
//   number
//                of its edges before the wrong closures;
//   R > 1 robots: "<key>.t<trial>=<path_0>,…,<path_R−1> <candidates> <true> <wrong> <reference>": the trial's
//   graph cut as
//                the study cuts it (sim::split_into_robots), robot r's graph
//                OUT_DIR/<key>.t<trial>.robot<r>.g2o with its own pose ids, the inter-robot candidates
//                OUT_DIR/<key>.t<trial>.candidates.g2o with global ids (robot r's pose k is k plus the poses
//                of the robots before it: the uncut graph's ids, which `keel robust --candidates` and
//                kimera_measure read), <true> the number of true loop closures, and
//                OUT_DIR/<key>.t<trial>.wrong listing each wrong closure's global ids "i j". Each robot's
//                poses are written in its own frame (its first pose at the identity), as a robot's odometry
//                gives them: the uncut graph's chained estimate would hand a peer the robots' relative
//                alignment that the dropped joining odometry held.
// <reference> is OUT_DIR/<graph>.r<R>.reference.txt, written once per graph and robot count: the positions of
// the experiment's ATE reference (its RobustBackendReference: the certified solve, with the experiment's
// solver options, of every robot's odometry and every true loop closure, without the odometry that joins two
// robots), one line "id x y [z]" per pose in global ids, after a first line "certified 1|0".
import keel.core;
import keel.graph;
import keel.repro;
import keel.sim;
import keel.study;

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

// Robot r's graph in its own frame: every pose left-multiplied by the inverse of its first.
template <class Graph>
Graph in_own_frame(Graph g) {
  if (g.poses.empty()) return g;
  const auto to_own = g.poses.front().inverse();
  for (auto& p : g.poses) p = to_own * p;
  return g;
}

// Writes trial `key` of a cell with `robots` > 1 robots and prints its line (the header's format).
template <class Corrupted>
void write_split(const Corrupted& corrupted, int robots, std::size_t clean_edges,
                 const std::filesystem::path& dir, const std::string& key,
                 const std::filesystem::path& reference) {
  const auto split = keel::sim::split_into_robots(corrupted.graph, robots);
  std::ostringstream line;
  line << key << "=";
  for (int r = 0; r < robots; ++r) {
    const auto path = dir / (key + ".robot" + std::to_string(r) + ".g2o");
    keel::graph::write_g2o(in_own_frame(split.robots[static_cast<std::size_t>(r)]), path);
    line << (r ? "," : "") << path.string();
  }
  const auto cpath = dir / (key + ".candidates.g2o");
  keel::graph::write_g2o_edges(split.inter, cpath);
  const auto wpath = dir / (key + ".wrong");
  std::ofstream wrong(wpath);
  int true_closures = 0;
  for (std::size_t e = 0; e < corrupted.graph.edges.size(); ++e) {
    const auto& edge = corrupted.graph.edges[e];
    if (e >= clean_edges)
      wrong << edge.i << " " << edge.j << "\n";
    else if (edge.j != edge.i + 1 && edge.i != edge.j + 1)
      ++true_closures;
  }
  if (!wrong) throw std::runtime_error("cannot write " + wpath.string());
  line << " " << cpath.string() << " " << true_closures << " " << wpath.string() << " " << reference.string();
  std::printf("%s\n", line.str().c_str());
}

// The ATE reference of graph g cut into `robots` robots (the study's own, RobustBackend::reference), written
// as the header says.
std::filesystem::path write_reference(const keel::study::ch4::RobustBackend::CleanGraph& clean,
                                      const keel::study::ch4::RobustBackend::Options& options, std::size_t g,
                                      int robots, const std::filesystem::path& dir, const std::string& name) {
  const auto ref = keel::study::ch4::RobustBackend::reference(clean, options, g, robots);
  const auto path = dir / (name + ".r" + std::to_string(robots) + ".reference.txt");
  std::ofstream out(path);
  out << "certified " << (ref.certified ? 1 : 0) << "\n";
  char buffer[128];
  auto write = [&](const auto& poses) {
    for (std::size_t k = 0; k < poses.size(); ++k) {
      const auto& t = poses[k].translation();
      if (t.size() == 2)
        std::snprintf(buffer, sizeof buffer, "%zu %.17g %.17g\n", k, t[0], t[1]);
      else
        std::snprintf(buffer, sizeof buffer, "%zu %.17g %.17g %.17g\n", k, t[0], t[1], t[2]);
      out << buffer;
    }
  };
  if (options.graphs[g].dimension == 2)
    write(ref.poses2);
  else
    write(ref.poses3);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  return path;
}

std::set<int> robot_counts(const char* text) {
  std::set<int> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.insert(std::stoi(item));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4 || argc > 7) {
    std::fprintf(stderr, "usage: keel_robust_graphs CONFIG PROFILE OUT_DIR [TRIALS [SEED [ROBOTS]]]\n");
    return 2;
  }
  try {
    using keel::study::ch4::RobustBackend;
    const auto config = keel::repro::ExperimentConfig::load(argv[1], argv[2]);
    const auto options = RobustBackend::Options::read(config.params);
    const int trials = argc >= 5 ? std::stoi(argv[4]) : options.trials;
    const std::filesystem::path dir = argv[3];
    std::filesystem::create_directories(dir);
    const keel::core::Streams streams(argc >= 6 ? std::stoull(argv[5]) : config.seed);
    const std::set<int> robots = argc == 7 ? robot_counts(argv[6]) : std::set<int>{1};
    std::vector<RobustBackend::CleanGraph> clean;
    for (std::size_t g = 0; g < options.graphs.size(); ++g)
      clean.push_back(RobustBackend::clean_graph(options, g));
    std::map<std::pair<std::size_t, int>, std::filesystem::path> references;  // per graph and robot count
    for (const auto& cell : RobustBackend::make_cells(options)) {
      if (!robots.contains(cell.robots)) continue;
      const bool two_d = options.graphs[cell.graph].dimension == 2;
      const auto& c = clean[cell.graph];
      auto& reference = references[{cell.graph, cell.robots}];
      if (reference.empty()) {
        const std::string name = cell.key.name().substr(0, cell.key.name().find('.'));
        reference = write_reference(c, options, cell.graph, cell.robots, dir, name);
      }
      for (int t = 0; t < trials && t < options.trials; ++t) {
        const std::string key = cell.key.name() + ".t" + std::to_string(t);
        if (cell.robots > 1) {
          if (two_d)
            write_split(RobustBackend::trial_graph(c.g2, options, cell, t, streams), cell.robots,
                        c.g2.edges.size(), dir, key, reference);
          else
            write_split(RobustBackend::trial_graph(c.g3, options, cell, t, streams), cell.robots,
                        c.g3.edges.size(), dir, key, reference);
          continue;
        }
        const auto path = dir / (key + ".g2o");
        if (two_d)
          keel::graph::write_g2o(RobustBackend::trial_graph(c.g2, options, cell, t, streams).graph, path);
        else
          keel::graph::write_g2o(RobustBackend::trial_graph(c.g3, options, cell, t, streams).graph, path);
        std::printf("%s=%s %zu %s\n", key.c_str(), path.c_str(),
                    two_d ? c.g2.edges.size() : c.g3.edges.size(), reference.c_str());
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "keel_robust_graphs: %s\n", e.what());
    return 1;
  }
  return 0;
}
