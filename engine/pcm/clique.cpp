// The names of the maximum-clique algorithms and the dispatch over them (the solvers: clique_exact.cpp,
// clique_heuristic.cpp, clique_reference.cpp).
#include "pcm/clique.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "core/names.hpp"

namespace keel::pcm {

namespace {
constexpr core::NameTable<CliqueAlgorithm, 3> kCliqueAlgorithmNames{
    "pcm::CliqueAlgorithm",
    {{{CliqueAlgorithm::exact, "exact"},
      {CliqueAlgorithm::heuristic, "heuristic"},
      {CliqueAlgorithm::brute_force, "brute_force"}}}};
}  // namespace

std::string_view to_string(CliqueAlgorithm a) { return kCliqueAlgorithmNames.name(a); }
CliqueAlgorithm clique_algorithm_from_string(std::string_view s) { return kCliqueAlgorithmNames.parse(s); }

CliqueResult maximum_clique(const ConsistencyGraph& g, CliqueAlgorithm algorithm,
                            const CliqueOptions& options) {
  switch (algorithm) {
    case CliqueAlgorithm::exact:
      return maximum_clique_exact(g, options);
    case CliqueAlgorithm::heuristic:
      return maximum_clique_heuristic(g, options);
    case CliqueAlgorithm::brute_force:
      return maximum_clique_brute_force(g, options);
  }
  throw std::invalid_argument(
      fmt::format("maximum_clique: unknown algorithm {}", static_cast<int>(algorithm)));
}

}  // namespace keel::pcm
