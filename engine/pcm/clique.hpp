// Maximum clique of a consistency graph (thesis §2.5): the PCM problem of eq. 2.5 — the largest set of
// measurements that are pairwise consistent — is the maximum clique of the graph whose edges join
// pairwise-consistent measurements. The exact solver is a branch and bound: core-number (k-core) pruning of
// vertices that cannot beat the incumbent and a greedy initial clique (Pattabiraman et al. 2015), per-vertex
// subproblems in degeneracy order on one bitset graph renumbered once (San Segundo et al.'s BBMC), greedy
// colouring bounds that colour only the classes never branched on (Tomita et al.'s MCS, BBMCR), and a
// branching set shrunk by Re-NUMBER and by MaxSAT unit propagation over the colour classes (Li & Quan 2010;
// Li, Jiang & Manyà 2017). clique_exact.cpp cites each step (the graph: consistency_graph.hpp; the heuristic:
// clique_heuristic.cpp; the Bron–Kerbosch reference: clique_reference.cpp). With a node or time limit it
// returns the best clique, a proven upper bound from colouring the unfinished subproblems, and the status.
// Everything is deterministic: vertex orders break ties by vertex id.
#pragma once

#include <tuple>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/bound.hpp"
#include "pcm/consistency_graph.hpp"
#include "core/fields.hpp"

namespace keel::pcm {

enum class CliqueAlgorithm { exact, heuristic, brute_force };
std::string_view to_string(CliqueAlgorithm a);
CliqueAlgorithm clique_algorithm_from_string(std::string_view s);  // throws std::invalid_argument

// How a maximum-clique search ended: core::SearchStatus (optimal: the clique is proven maximum, its size
// equals the proven upper bound; unproven: the heuristic finished without proving its clique maximum;
// node_limit / time_limit: the exact search stopped at CliqueOptions::node_limit / time_limit_s with the best
// clique so far and a valid bound).
using core::SearchStatus;

struct CliqueOptions {
  bool report_ties = false;   // collect other maximum cliques in CliqueResult::ties
  int max_ties = 16;          // cap on ties.size()
  double time_limit_s = 0.0;  // exact only; <= 0: none
  long long node_limit = 0;   // exact only; <= 0: none (nodes = branch-and-bound calls)
  // Exact only: the bounds that shrink the branching set beyond greedy colouring (clique_exact.cpp, class
  // Search). Both are on by default; they change the node count and time, never the size found.
  bool recolour = true;      // insertion and Re-NUMBER into the classes that are not branched on
  bool maxsat_bound = true;  // unit propagation on the MaxSAT encoding of the colour classes
  // Run each bound only while it pays for itself: while the work it has cost (adjacency words read, counted,
  // so the node count never depends on timing) stays within a small share of the search's work plus a node's
  // work for every candidate it removed. false: each bound that is on runs at every candidate. A search with
  // a node_limit runs them at every candidate as well: nodes are then its budget, and a removed candidate
  // always saves nodes (ext_clique_scale's node-limited comparison: adaptive bounds found 2.3 vertices
  // smaller cliques within 10⁶ nodes on G(2000, 0.5) with a planted 40).
  bool adaptive_bounds = true;
  // Exact only: a clique known in advance (vertex ids, any order), used as the first incumbent when it is
  // larger than the greedy one; std::invalid_argument if it is not a clique of g.
  std::vector<int> initial_clique;
};

struct CliqueResult {
  std::vector<int> clique;                       // sorted vertex ids of a largest clique found
  int upper_bound = 0;                           // no clique is larger than this
  SearchStatus status = SearchStatus::unproven;  // optimal iff clique.size() == upper_bound
  std::vector<std::vector<int>> ties;  // other maximum cliques (sorted ids, lexicographic), if requested
  long long nodes_explored = 0;
  double time_s = 0.0;
  bool proven_optimal() const { return status == SearchStatus::optimal; }
  // How many vertices a larger clique could still have: upper_bound − |clique| (0 iff optimal).
  int gap() const { return upper_bound - static_cast<int>(clique.size()); }
  // The bound on the maximum clique's size (core/bound.hpp): lower = |clique| (attained), upper =
  // upper_bound.
  core::Bound bound() const { return {static_cast<double>(clique.size()), static_cast<double>(upper_bound)}; }
  // The members, for repro::save/load (the per-trial records of sharded runs, core/archive.hpp).
  KEEL_FIELDS(clique, upper_bound, status, ties, nodes_explored, time_s)
};

[[nodiscard]] CliqueResult maximum_clique_exact(const ConsistencyGraph& g, const CliqueOptions& options = {});

// Pattabiraman et al.'s heuristic: from every vertex, grow a clique greedily choosing the candidate of
// highest core number (then degree, then lowest id) with core-number pruning. Returns a clique (never larger
// than the maximum); upper_bound is the degeneracy bound max core + 1; ties are not collected.
[[nodiscard]] CliqueResult maximum_clique_heuristic(const ConsistencyGraph& g,
                                                    const CliqueOptions& options = {});

// Bron–Kerbosch without pivoting over all maximal cliques, for validation only: throws std::invalid_argument
// when g.size() > kBruteForceMaxVertices. With report_ties, ties lists every other maximum clique (up to
// max_ties).
inline constexpr int kBruteForceMaxVertices = 32;
[[nodiscard]] CliqueResult maximum_clique_brute_force(const ConsistencyGraph& g,
                                                      const CliqueOptions& options = {});

// Dispatch on the algorithm.
[[nodiscard]] CliqueResult maximum_clique(const ConsistencyGraph& g, CliqueAlgorithm algorithm,
                                          const CliqueOptions& options = {});

}  // namespace keel::pcm
