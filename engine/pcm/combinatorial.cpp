#include "pcm/combinatorial.hpp"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "core/names.hpp"
#include "core/timing.hpp"
#include "pcm/selection.hpp"

namespace keel::pcm {

using core::Clock;
using core::seconds_since;

namespace {
constexpr core::NameTable<CombinatorialMethod, 2> kCombinatorialMethodNames{
    "pcm::CombinatorialMethod",
    {{{CombinatorialMethod::exhaustive, "exhaustive"}, {CombinatorialMethod::pruned, "pruned"}}}};
}  // namespace

std::string_view to_string(CombinatorialMethod v) { return kCombinatorialMethodNames.name(v); }
CombinatorialMethod combinatorial_method_from_string(std::string_view s) {
  return kCombinatorialMethodNames.parse(s);
}

namespace {

struct PrunedSearch {
  const std::vector<std::uint64_t>& ok;  // ok[u]: candidates consistent with u (both directions), u excluded
  int best = 0;
  std::uint64_t best_set = 0;
  long long optimal = 0;
  long long nodes = 0;

  // `cand`: candidates above every decided index that are consistent with every member of `cur`.
  void run(std::uint64_t cur, int size, std::uint64_t cand) {
    ++nodes;
    if (size + std::popcount(cand) < best) return;  // cannot reach the best size: prune (keeps ties)
    if (cand == 0) {
      if (size > best) {
        best = size;
        best_set = cur;
        optimal = 1;
      } else if (size == best) {
        ++optimal;
      }
      return;
    }
    const int j = std::countr_zero(cand);
    const std::uint64_t bit = std::uint64_t{1} << j;
    run(cur | bit, size + 1,
        cand & ok[j]);            // include j (ok[j] excludes j and every candidate inconsistent with it)
    run(cur, size, cand & ~bit);  // exclude j
  }
};

}  // namespace

CombinatorialResult max_consistent_set_combinatorial(const ConsistencyMatrix& Q, double gamma,
                                                     CombinatorialMethod method) {
  validate_consistency_matrix(Q, "max_consistent_set_combinatorial");
  validate_gamma(gamma, "max_consistent_set_combinatorial");
  const int m = Q.n;
  const int limit =
      method == CombinatorialMethod::exhaustive ? kCombinatorialExhaustiveMax : kCombinatorialPrunedMax;
  if (m > limit) {
    throw std::invalid_argument(
        fmt::format("max_consistent_set_combinatorial ({}): m = {} measurements exceeds the limit {}",
                    to_string(method), m, limit));
  }
  const auto t0 = Clock::now();
  // ok[u]: bitmask of v ≠ u with q_uv <= γ and q_vu <= γ (the pairwise constraint of eq. 2.5 for s_u = s_v =
  // 1).
  std::vector<std::uint64_t> ok(m, 0);
  for (int u = 0; u < m; ++u)
    for (int v = 0; v < m; ++v)
      if (v != u && Q.at(u, v) <= gamma && Q.at(v, u) <= gamma) ok[u] |= std::uint64_t{1} << v;

  CombinatorialResult r;
  std::uint64_t best_set = 0;
  if (method == CombinatorialMethod::exhaustive) {
    // Every S ∈ {0,1}^m (as a bitmask), kept when all its pairs are consistent; ‖S‖₀ is maximised.
    int best = 0;
    long long optimal = 1;  // the empty set, until a non-empty one is found
    const std::uint64_t end = std::uint64_t{1} << m;
    for (std::uint64_t s = 1; s < end; ++s) {
      const int size = std::popcount(s);
      if (size < best) continue;  // cannot be a maximum set: skip the pairwise test
      bool consistent = true;
      for (std::uint64_t rest = s; rest != 0 && consistent; rest &= rest - 1) {
        const int u = std::countr_zero(rest);
        consistent = (s & ~ok[u] & ~(std::uint64_t{1} << u)) == 0;
      }
      if (!consistent) continue;
      if (size > best) {
        best = size;
        best_set = s;
        optimal = 1;
      } else {
        ++optimal;
      }
    }
    r.optimal_sets = optimal;
    r.subsets_visited = static_cast<long long>(end);
  } else {
    PrunedSearch search{ok};
    const std::uint64_t all = m == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << m) - 1;
    search.run(0, 0, all);
    best_set = search.best_set;
    r.optimal_sets = search.optimal;
    r.subsets_visited = search.nodes;
  }
  for (int u = 0; u < m; ++u)
    if ((best_set >> u) & 1u) r.selected.push_back(u);
  r.time_s = seconds_since(t0);
  return r;
}

int count_inconsistent_pairs(const ConsistencyMatrix& Q, const std::vector<int>& set, double gamma) {
  validate_consistency_matrix(Q, "count_inconsistent_pairs");
  if (std::isnan(gamma)) throw std::invalid_argument("count_inconsistent_pairs: gamma is NaN");
  std::vector<char> seen(Q.n, 0);
  for (int u : set) {
    if (u < 0 || u >= Q.n) {
      throw std::invalid_argument(
          fmt::format("count_inconsistent_pairs: index {} is out of range [0, {})", u, Q.n));
    }
    if (seen[u]) throw std::invalid_argument(fmt::format("count_inconsistent_pairs: index {} repeated", u));
    seen[u] = 1;
  }
  int bad = 0;
  for (std::size_t a = 0; a < set.size(); ++a)
    for (std::size_t b = a + 1; b < set.size(); ++b)
      if (Q.at(set[a], set[b]) > gamma || Q.at(set[b], set[a]) > gamma) ++bad;
  return bad;
}

}  // namespace keel::pcm
