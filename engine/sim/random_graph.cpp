#include "sim/random_graph.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>
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

PlantedClique planted_clique_graph(int n, int k, double density, std::uint64_t seed) {
  if (k < 0 || k > n)
    throw std::invalid_argument(fmt::format("planted_clique_graph: k = {} must be in [0, n = {}]", k, n));
  PlantedClique out{random_graph(n, density, seed), {}};
  auto rng = core::Rng::stream(seed, 1);
  std::vector<int> ids(static_cast<std::size_t>(n));
  std::iota(ids.begin(), ids.end(), 0);
  for (int i = 0; i < k; ++i) {
    const int r = i + std::min(n - i - 1, static_cast<int>(rng.uniform() * (n - i)));
    std::swap(ids[static_cast<std::size_t>(i)], ids[static_cast<std::size_t>(r)]);
  }
  out.planted.assign(ids.begin(), ids.begin() + k);
  std::sort(out.planted.begin(), out.planted.end());
  for (std::size_t a = 0; a < out.planted.size(); ++a)
    for (std::size_t b = a + 1; b < out.planted.size(); ++b)
      out.graph.add_edge(out.planted[a], out.planted[b]);
  return out;
}

}  // namespace keel::sim
