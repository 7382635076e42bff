// Consistency graphs of chapter 2's two-robot data sets (Q of eq. 2.4 with the joint composition, thresholded
// at γ(11 %)), shared by bench_clique's family and densest_acceptance's fresh graphs. Include it after
// importing keel.pcm, keel.repro and keel.study: it uses their names.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace keel::bench {

struct NamedGraph {
  std::string name, origin;
  keel::pcm::ConsistencyGraph graph;
};

// Data sets index_base … index_base + count − 1 of experiment `id` (its config's full profile: scenario and
// candidate options) drawn from `seed`, named <prefix>_d<i> (i from index_base). `seed` and `count` default
// to the experiment's own seed and number of data sets, so that the graphs are that experiment's.
// `config_path` is the experiment's experiment.toml.
template <class Table, bool three_d>
std::vector<NamedGraph> study_graphs(const std::string& config_path, const std::string& id,
                                     const std::string& prefix, std::optional<std::uint64_t> seed = {},
                                     std::optional<std::size_t> count = {}, std::uint64_t index_base = 0) {
  const auto config = keel::repro::ExperimentConfig::load(config_path, "full");
  const auto o = Table::Options::read(config.params);
  const std::uint64_t s = seed.value_or(config.seed);
  const std::size_t m = count.value_or(o.datasets);
  std::vector<keel::pcm::ConsistencyMatrix> qs;
  if constexpr (three_d) {
    const auto scenario = keel::study::ch2::load_scenario_3d(o.scenario);
    const auto local = keel::study::ch2::solve_local_pair(scenario);
    qs = keel::study::ch2::dataset_consistency_matrices(scenario, local, o.candidates, s, m, index_base);
  } else {
    const auto scenario = keel::study::ch2::load_scenario_2d(o.scenario);
    const auto local = keel::study::ch2::solve_local_pair(scenario);
    qs = keel::study::ch2::dataset_consistency_matrices(scenario, local, o.candidates, s, m, index_base);
  }
  std::vector<NamedGraph> out;
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const double gamma = keel::pcm::consistency_threshold(0.11, qs[i].dof);
    out.push_back(
        {fmt::format("{}_d{:02}", prefix, index_base + i),
         fmt::format("{} data set {} (seed {}), Q joint, gamma(0.11) = {:.6g}", id, index_base + i, s, gamma),
         keel::pcm::ConsistencyGraph::from_threshold(qs[i].n, qs[i].q, gamma)});
  }
  return out;
}

// Writes `graph` as the DIMACS "p edge" file DIR/<name>.clq (1-based vertices; `origin` in a comment), the
// input of the side-by-side scripts' solvers (bench/side_by_side/dimacs.hpp). Throws std::runtime_error when
// it cannot.
inline void write_dimacs(const std::filesystem::path& dir, const std::string& name, const std::string& origin,
                         const keel::pcm::ConsistencyGraph& graph) {
  std::filesystem::create_directories(dir);
  const auto path = dir / (name + ".clq");
  std::ofstream out(path);
  out << "c keel graph " << name << "\nc " << origin << "\n";
  out << "p edge " << graph.size() << ' ' << graph.num_edges() << '\n';
  for (int v = 0; v < graph.size(); ++v)
    for (int w : graph.neighbors(v))
      if (w > v) out << "e " << v + 1 << ' ' << w + 1 << '\n';
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace keel::bench
