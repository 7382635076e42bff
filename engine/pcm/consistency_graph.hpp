// The consistency graph of thesis §2.5: vertices are measurements, an edge joins a pairwise-consistent pair
// (q_uv ≤ γ and q_vu ≤ γ). Dense bitset adjacency, which the maximum-clique solvers (clique.hpp) work on.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace keel::pcm {

// Undirected simple graph on vertices 0..n-1 with dense bitset adjacency (one row of ceil(n/64) words per
// vertex).
class ConsistencyGraph {
 public:
  ConsistencyGraph() = default;
  explicit ConsistencyGraph(int n);  // n >= 0, no edges
  // Edge list; duplicates are allowed (idempotent), self loops and out-of-range ids throw
  // std::invalid_argument.
  ConsistencyGraph(int n, const std::vector<std::pair<int, int>>& edges);

  // From a symmetric boolean adjacency matrix (n rows of n entries). The diagonal is ignored (a measurement
  // is always consistent with itself); a non-square or asymmetric matrix throws std::invalid_argument naming
  // the entry.
  static ConsistencyGraph from_matrix(const std::vector<std::vector<bool>>& adjacency);

  // Consistency graph of §2.5 from the n x n matrix Q of consistency measures (row-major): edge {u, v} iff
  // q_uv <= gamma and q_vu <= gamma. The diagonal is ignored; NaN entries or a wrong size throw.
  static ConsistencyGraph from_threshold(int n, const std::vector<double>& q, double gamma);

  void add_edge(int u, int v);        // idempotent; throws on self loop / out of range
  bool adjacent(int u, int v) const;  // throws on out of range; adjacent(v, v) == false
  int degree(int v) const;
  int size() const { return n_; }
  long long num_edges() const { return edges_; }
  int words() const { return words_; }  // words per adjacency row
  const std::uint64_t* row(int v) const { return adj_.data() + static_cast<std::size_t>(v) * words_; }
  std::vector<int> neighbors(int v) const;  // ascending

  // True iff `vertices` are distinct, in range and pairwise adjacent (the empty set is a clique).
  bool is_clique(const std::vector<int>& vertices) const;

 private:
  void check_vertex(int v, const char* what) const;
  int n_ = 0;
  int words_ = 0;
  long long edges_ = 0;
  std::vector<std::uint64_t> adj_;
};

// Core number of every vertex (Batagelj–Zaversnik, O(n + m)); a clique of size k lies in the (k-1)-core.
std::vector<int> core_numbers(const ConsistencyGraph& g);

}  // namespace keel::pcm
