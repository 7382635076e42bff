// What the maximum-clique solvers share (private to engine/pcm): the bitset kernels over the adjacency rows
// of a ConsistencyGraph, the degeneracy order, the greedy clique that is both the heuristic and the exact
// search's first incumbent, and the tie bookkeeping. consistency_graph.cpp holds the graph;
// clique_heuristic.cpp, clique_exact.cpp and clique_reference.cpp one solver each; clique.cpp the names and
// the dispatch.
#pragma once

#include <bit>
#include <cstdint>
#include <vector>

#include "pcm/clique.hpp"

namespace keel::pcm::detail {

inline bool test_bit(const std::uint64_t* w, int i) { return (w[i >> 6] >> (i & 63)) & 1u; }
inline void set_bit(std::uint64_t* w, int i) { w[i >> 6] |= std::uint64_t{1} << (i & 63); }
inline void clear_bit(std::uint64_t* w, int i) { w[i >> 6] &= ~(std::uint64_t{1} << (i & 63)); }

inline int popcount(const std::uint64_t* w, int words) {
  int c = 0;
  for (int i = 0; i < words; ++i) c += std::popcount(w[i]);
  return c;
}

inline int popcount_and(const std::uint64_t* a, const std::uint64_t* b, int words) {
  int c = 0;
  for (int i = 0; i < words; ++i) c += std::popcount(a[i] & b[i]);
  return c;
}

inline bool any(const std::uint64_t* w, int words) {
  for (int i = 0; i < words; ++i)
    if (w[i]) return true;
  return false;
}

// Core numbers and the smallest-last (degeneracy) removal order of Batagelj & Zaversnik (2003); bins are
// filled in vertex-id order so the order is deterministic.
struct Degeneracy {
  std::vector<int> core;
  std::vector<int> order;  // removal order: every vertex has at most core[v] neighbours after it
};

Degeneracy degeneracy(const ConsistencyGraph& g);

// The ids sorted ascending.
std::vector<int> sorted(std::vector<int> v);

// Pattabiraman et al.'s greedy clique search over the vertices by core number (clique_heuristic.cpp); `nodes`
// counts the vertices it starts from.
std::vector<int> greedy_clique(const ConsistencyGraph& g, const std::vector<int>& core, long long& nodes);

// The first of the sorted, lexicographically ordered cliques `found` into r.clique, the others into r.ties.
void finish_ties(CliqueResult& r, std::vector<std::vector<int>> found);

}  // namespace keel::pcm::detail
