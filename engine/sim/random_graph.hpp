// Random consistency graphs for benchmarks and tests of the clique solvers.
#pragma once

#include <cstdint>
#include <vector>

#include "pcm/clique.hpp"

namespace keel::sim {

// Erdős–Rényi G(n, p) graph: each pair {i < j} is an edge with probability `density`, drawn from
// keel::core::Rng::stream(seed, 0) in the order (0,1), (0,2), ..., (1,2), ... — identical on every platform.
// Throws std::invalid_argument for n < 0 or a density outside [0, 1].
[[nodiscard]] pcm::ConsistencyGraph random_graph(int n, double density, std::uint64_t seed);

// A planted-clique consistency graph: G(n, p) from random_graph(n, density, seed) with a clique added on k
// vertices drawn uniformly without replacement (a partial Fisher–Yates shuffle from
// keel::core::Rng::stream(seed, 1)) — the model of k mutually consistent inliers among n candidates whose
// other pairs are consistent by chance. Throws std::invalid_argument for k outside [0, n] (and as
// random_graph).
struct PlantedClique {
  pcm::ConsistencyGraph graph;
  std::vector<int> planted;  // ascending
};
[[nodiscard]] PlantedClique planted_clique_graph(int n, int k, double density, std::uint64_t seed);

}  // namespace keel::sim
