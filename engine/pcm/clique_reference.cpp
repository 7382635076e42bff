// The reference maximum-clique search for validation: Bron–Kerbosch without pivoting over every maximal
// clique of a graph of at most kBruteForceMaxVertices vertices (one 64-bit word per adjacency row).
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/timing.hpp"
#include "pcm/clique_detail.hpp"

namespace keel::pcm {

using core::Clock;
using core::seconds_since;

CliqueResult maximum_clique_brute_force(const ConsistencyGraph& g, const CliqueOptions& opt) {
  const auto t0 = Clock::now();
  const int n = g.size();
  if (n > kBruteForceMaxVertices)
    throw std::invalid_argument(fmt::format("maximum_clique_brute_force: {} vertices exceed the limit of {}",
                                            n, kBruteForceMaxVertices));
  CliqueResult r;
  std::vector<std::uint64_t> nb(n, 0);
  for (int v = 0; v < n; ++v) nb[v] = n == 0 ? 0 : g.row(v)[0];
  int best = -1;
  std::vector<std::uint64_t> found;
  long long nodes = 0;
  const std::size_t cap = static_cast<std::size_t>(std::max(opt.max_ties, 0)) + 1;
  // Bron–Kerbosch without pivot: every maximal clique is reported exactly once.
  auto bk = [&](auto&& self, std::uint64_t R, std::uint64_t P, std::uint64_t X) -> void {
    ++nodes;
    if (P == 0 && X == 0) {
      const int s = std::popcount(R);
      if (s > best) {
        best = s;
        found.assign(1, R);
      } else if (s == best && opt.report_ties && found.size() < cap) {
        found.push_back(R);
      }
      return;
    }
    while (P) {
      const int v = std::countr_zero(P);
      const std::uint64_t bit = std::uint64_t{1} << v;
      self(self, R | bit, P & nb[v], X & nb[v]);
      P &= ~bit;
      X |= bit;
    }
  };
  const std::uint64_t all = n == 0 ? 0 : (n == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1);
  bk(bk, 0, all, 0);
  std::vector<std::vector<int>> cliques;
  for (const auto m : found) {
    std::vector<int> c;
    for (int v = 0; v < n; ++v)
      if ((m >> v) & 1u) c.push_back(v);
    cliques.push_back(c);
  }
  detail::finish_ties(r, cliques);
  if (!opt.report_ties) r.ties.clear();
  r.upper_bound = best;
  r.status = SearchStatus::optimal;
  r.nodes_explored = nodes;
  r.time_s = seconds_since(t0);
  return r;
}

}  // namespace keel::pcm
