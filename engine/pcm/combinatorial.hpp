// The combinatorial "gold standard" of eq. 2.5 (§2.7.1): a search over the subsets S ∈ {0,1}^m of the
// candidates that does not use the clique code, so it checks PCM's maximum clique independently; and the
// count of pairs of a set that violate eq. 2.3 (Fig. 2.2's second row).
#pragma once

#include <string_view>
#include <vector>

#include "pcm/consistency.hpp"

namespace keel::pcm {

// Combinatorial solution of eq. 2.5 straight from Q and γ, independent of the clique code: the largest S ⊆
// {0..m−1} with q_uv <= γ and q_vu <= γ for all u ≠ v in S.
enum class CombinatorialMethod {
  exhaustive,  // all 2^m subsets, each tested for pairwise consistency (m <= kCombinatorialExhaustiveMax)
  pruned,      // depth-first include/exclude over the candidates in index order; a candidate is only included
               // when consistent with every included one, and a branch stops when even taking all remaining
               // candidates could not reach the best size (m <= kCombinatorialPrunedMax)
};
std::string_view to_string(CombinatorialMethod m);
CombinatorialMethod combinatorial_method_from_string(std::string_view s);  // "exhaustive" | "pruned"
inline constexpr int kCombinatorialExhaustiveMax = 30;
inline constexpr int kCombinatorialPrunedMax = 64;

struct CombinatorialResult {
  std::vector<int> selected;   // one maximum pairwise consistent set, sorted (exhaustive: smallest bitmask)
  long long optimal_sets = 0;  // number of distinct maximum pairwise consistent sets
  long long subsets_visited = 0;  // exhaustive: 2^m; pruned: search nodes
  double time_s = 0.0;
};
// Throws std::invalid_argument for a bad Q or γ (as select_pcm) or m above the method's limit.
[[nodiscard]] CombinatorialResult max_consistent_set_combinatorial(
    const pcm::ConsistencyMatrix& Q, double gamma, CombinatorialMethod method = CombinatorialMethod::pruned);

// Number of pairs {u, v} of `set` that violate eq. 2.3 (q_uv > γ or q_vu > γ). `set` must hold distinct
// indices in range (std::invalid_argument otherwise).
[[nodiscard]] int count_inconsistent_pairs(const pcm::ConsistencyMatrix& Q, const std::vector<int>& set,
                                           double gamma);

}  // namespace keel::pcm
