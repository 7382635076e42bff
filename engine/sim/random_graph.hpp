// Random consistency graphs for benchmarks and tests of the clique solvers.
#pragma once

#include <cstdint>

#include "pcm/clique.hpp"

namespace keel::sim {

// Erdős–Rényi G(n, p) graph: each pair {i < j} is an edge with probability `density`, drawn from
// keel::core::Rng::stream(seed, 0) in the order (0,1), (0,2), ..., (1,2), ... — identical on every platform.
// Throws std::invalid_argument for n < 0 or a density outside [0, 1].
[[nodiscard]] pcm::ConsistencyGraph random_graph(int n, double density, std::uint64_t seed);

}  // namespace keel::sim
