#include "sim/random_graph.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "core/random.hpp"

namespace keel::sim {

pcm::ConsistencyGraph random_graph(int n, double density, std::uint64_t seed) {
  if (n < 0) throw std::invalid_argument(fmt::format("random_graph: n = {} must be >= 0", n));
  if (!(density >= 0.0 && density <= 1.0))
    throw std::invalid_argument(fmt::format("random_graph: density {} not in [0, 1]", density));
  pcm::ConsistencyGraph g(n);
  auto rng = core::Rng::stream(seed, 0);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (rng.uniform() < density) g.add_edge(i, j);
  return g;
}

}  // namespace keel::sim
