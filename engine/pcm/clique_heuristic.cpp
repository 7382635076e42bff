// Pattabiraman et al.'s maximum-clique heuristic (the thesis's PCM-HeuPatt): from every vertex, grow a clique
// greedily by core number with core-number pruning.
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

namespace detail {

// Heuristic core shared by maximum_clique_heuristic and the exact solver's initial incumbent.
std::vector<int> greedy_clique(const ConsistencyGraph& g, const std::vector<int>& core, long long& nodes) {
  const int n = g.size();
  if (n == 0) return {};
  const int words = g.words();
  std::vector<int> deg(n);
  for (int v = 0; v < n; ++v) deg[v] = g.degree(v);
  auto better = [&](int a, int b) {  // true if a is preferred over b
    if (core[a] != core[b]) return core[a] > core[b];
    if (deg[a] != deg[b]) return deg[a] > deg[b];
    return a < b;
  };
  std::vector<int> order(n);
  for (int v = 0; v < n; ++v) order[v] = v;
  std::sort(order.begin(), order.end(), better);
  // rank[v]: v's place in that order, so that picking the best candidate compares one int (`better` is a
  // strict total order, so the smallest rank is the candidate `better` prefers over all others).
  std::vector<int> rank(n);
  for (int i = 0; i < n; ++i) rank[order[i]] = i;

  std::vector<int> best{order[0]};
  int lb = 1;
  std::vector<std::uint64_t> alive(words, 0), cand(words);
  for (int v = 0; v < n; ++v)
    if (core[v] >= lb) set_bit(alive.data(), v);
  std::vector<int> clique;
  for (const int v : order) {
    if (core[v] < lb) break;  // a clique through v has at most core[v] + 1 <= lb vertices
    ++nodes;
    const std::uint64_t* rv = g.row(v);
    for (int w = 0; w < words; ++w) cand[w] = rv[w] & alive[w];
    clique.assign(1, v);
    int remaining = popcount(cand.data(), words);
    while (remaining > 0) {
      if (static_cast<int>(clique.size()) + remaining <= lb) break;
      int pick = -1, pick_rank = n;
      for (int w = 0; w < words; ++w) {
        std::uint64_t bits = cand[w];
        while (bits) {
          const int u = w * 64 + std::countr_zero(bits);
          bits &= bits - 1;
          if (rank[u] < pick_rank) pick = u, pick_rank = rank[u];
        }
      }
      clique.push_back(pick);
      const std::uint64_t* ru = g.row(pick);
      for (int w = 0; w < words; ++w) cand[w] &= ru[w];
      remaining = popcount(cand.data(), words);
    }
    if (static_cast<int>(clique.size()) > lb) {
      lb = static_cast<int>(clique.size());
      best = clique;
      for (int u = 0; u < n; ++u)
        if (core[u] < lb) clear_bit(alive.data(), u);
    }
  }
  return sorted(best);
}

}  // namespace detail

using core::Clock;
using core::seconds_since;

CliqueResult maximum_clique_heuristic(const ConsistencyGraph& g, const CliqueOptions&) {
  const auto t0 = Clock::now();
  CliqueResult r;
  const auto d = detail::degeneracy(g);
  r.clique = detail::greedy_clique(g, d.core, r.nodes_explored);
  r.upper_bound = g.size() == 0 ? 0 : *std::max_element(d.core.begin(), d.core.end()) + 1;
  r.status =
      static_cast<int>(r.clique.size()) == r.upper_bound ? SearchStatus::optimal : SearchStatus::unproven;
  r.time_s = seconds_since(t0);
  return r;
}

}  // namespace keel::pcm
