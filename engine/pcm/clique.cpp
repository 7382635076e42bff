#include "pcm/clique.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/names.hpp"
#include "core/timing.hpp"

namespace keel::pcm {

namespace {

using core::Clock;
using core::seconds_since;

inline bool test_bit(const std::uint64_t* w, int i) { return (w[i >> 6] >> (i & 63)) & 1u; }
inline void set_bit(std::uint64_t* w, int i) { w[i >> 6] |= std::uint64_t{1} << (i & 63); }
inline void clear_bit(std::uint64_t* w, int i) { w[i >> 6] &= ~(std::uint64_t{1} << (i & 63)); }

int popcount(const std::uint64_t* w, int words) {
  int c = 0;
  for (int i = 0; i < words; ++i) c += std::popcount(w[i]);
  return c;
}

bool any(const std::uint64_t* w, int words) {
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

Degeneracy degeneracy(const ConsistencyGraph& g) {
  const int n = g.size();
  Degeneracy d;
  d.core.assign(n, 0);
  d.order.assign(n, 0);
  if (n == 0) return d;
  std::vector<int> deg(n), pos(n), vert(n);
  int maxdeg = 0;
  for (int v = 0; v < n; ++v) {
    deg[v] = g.degree(v);
    maxdeg = std::max(maxdeg, deg[v]);
  }
  std::vector<int> bin(maxdeg + 1, 0);
  for (int v = 0; v < n; ++v) ++bin[deg[v]];
  int start = 0;
  for (int k = 0; k <= maxdeg; ++k) {
    const int num = bin[k];
    bin[k] = start;
    start += num;
  }
  for (int v = 0; v < n; ++v) {
    pos[v] = bin[deg[v]];
    vert[pos[v]] = v;
    ++bin[deg[v]];
  }
  for (int k = maxdeg; k > 0; --k) bin[k] = bin[k - 1];
  bin[0] = 0;
  const int words = g.words();
  for (int i = 0; i < n; ++i) {
    const int v = vert[i];
    const std::uint64_t* row = g.row(v);
    for (int w = 0; w < words; ++w) {
      std::uint64_t bits = row[w];
      while (bits) {
        const int u = w * 64 + std::countr_zero(bits);
        bits &= bits - 1;
        if (deg[u] > deg[v]) {
          const int du = deg[u], pu = pos[u], pw = bin[du], wv = vert[pw];
          if (u != wv) {
            pos[u] = pw;
            vert[pu] = wv;
            pos[wv] = pu;
            vert[pw] = u;
          }
          ++bin[du];
          --deg[u];
        }
      }
    }
  }
  for (int i = 0; i < n; ++i) d.core[vert[i]] = deg[vert[i]];
  d.order = vert;
  return d;
}

std::vector<int> sorted(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  return v;
}

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
      int pick = -1;
      for (int w = 0; w < words; ++w) {
        std::uint64_t bits = cand[w];
        while (bits) {
          const int u = w * 64 + std::countr_zero(bits);
          bits &= bits - 1;
          if (pick < 0 || better(u, pick)) pick = u;
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

// Branch and bound on one per-vertex subproblem with local bitsets (Tomita-style greedy colouring bounds).
class Search {
 public:
  Search(const CliqueOptions& opt, Clock::time_point t0) : opt_(opt), t0_(t0) {}

  int best = 0;
  std::vector<std::vector<int>> found;  // global ids, unsorted
  long long nodes = 0;
  bool aborted = false;
  SearchStatus stop = SearchStatus::optimal;  // node_limit or time_limit once aborted

  int target() const { return opt_.report_ties ? best : best + 1; }

  // Solve the subproblem "v plus a clique of `cand` (global ids)" where adjacency among cand is taken from g.
  void solve(const ConsistencyGraph& g, int v, std::vector<int> cand) {
    // Local adjacency among cand (bit tests on g's rows, no bounds checks: ids come from g).
    int k0 = static_cast<int>(cand.size());
    if (k0 + 1 < target()) return;
    const int w0 = (k0 + 63) / 64;
    tmp_adj_.assign(static_cast<std::size_t>(k0) * w0, 0);
    for (int i = 0; i < k0; ++i) {
      const std::uint64_t* ri = g.row(cand[i]);
      for (int j = i + 1; j < k0; ++j)
        if (test_bit(ri, cand[j])) {
          set_bit(tmp_adj_.data() + static_cast<std::size_t>(i) * w0, j);
          set_bit(tmp_adj_.data() + static_cast<std::size_t>(j) * w0, i);
        }
    }
    // Peel candidates that cannot be in a clique of target() vertices together with v (fewer than target() -
    // 2 neighbours among the surviving candidates): the k-core pruning of Pattabiraman et al. inside the
    // subproblem.
    std::vector<std::uint64_t> alive(w0, 0);
    for (int i = 0; i < k0; ++i) set_bit(alive.data(), i);
    std::vector<int> local_deg(k0, 0);
    int k = k0;
    for (bool changed = true; changed;) {
      changed = false;
      const int need = target() - 2;
      for (int i = 0; i < k0; ++i) {
        if (!test_bit(alive.data(), i)) continue;
        const std::uint64_t* ri = tmp_adj_.data() + static_cast<std::size_t>(i) * w0;
        int dg = 0;
        for (int w = 0; w < w0; ++w) dg += std::popcount(ri[w] & alive[w]);
        local_deg[i] = dg;
        if (dg < need) {
          clear_bit(alive.data(), i);
          --k;
          changed = true;
        }
      }
      if (k + 1 < target()) return;
    }
    // Local order: degree descending among the survivors, then candidate position (deterministic).
    std::vector<int> perm;
    perm.reserve(k);
    for (int i = 0; i < k0; ++i)
      if (test_bit(alive.data(), i)) perm.push_back(i);
    std::sort(perm.begin(), perm.end(), [&](int a, int b) {
      return local_deg[a] != local_deg[b] ? local_deg[a] > local_deg[b] : a < b;
    });
    ids_.resize(k);
    for (int i = 0; i < k; ++i) ids_[i] = cand[perm[i]];
    kw_ = (k + 63) / 64;
    adj_.assign(static_cast<std::size_t>(k) * kw_, 0);
    for (int i = 0; i < k; ++i) {
      const std::uint64_t* ri = tmp_adj_.data() + static_cast<std::size_t>(perm[i]) * w0;
      for (int j = i + 1; j < k; ++j)
        if (test_bit(ri, perm[j])) {
          set_bit(adj_.data() + static_cast<std::size_t>(i) * kw_, j);
          set_bit(adj_.data() + static_cast<std::size_t>(j) * kw_, i);
        }
    }
    if (static_cast<int>(pool_.size()) < k + 2) pool_.resize(k + 2);
    for (int l = 0; l < k + 2; ++l) pool_[l].assign(static_cast<std::size_t>(3) * kw_ + 2 * k + 2, 0);
    current_.assign(1, v);
    std::uint64_t* p = pool_[0].data();
    for (int i = 0; i < k; ++i) set_bit(p, i);
    if (k == 0) {
      record();
      return;
    }
    expand(0);
  }

 private:
  bool limit_hit() {
    if (opt_.node_limit > 0 && nodes >= opt_.node_limit) {
      stop = SearchStatus::node_limit;
      return true;
    }
    if (opt_.time_limit_s > 0 && (nodes & 1023) == 0 && seconds_since(t0_) > opt_.time_limit_s) {
      stop = SearchStatus::time_limit;
      return true;
    }
    return false;
  }

  void record() {
    const int s = static_cast<int>(current_.size());
    if (s > best) {
      best = s;
      found.clear();
      found.push_back(current_);
    } else if (s == best && opt_.report_ties) {
      if (static_cast<int>(found.size()) < std::max(opt_.max_ties, 0) + 1) found.push_back(current_);
    }
  }

  // pool_[depth] holds P (kw words), scratch Q, U (kw each), then colour order and colours (k ints each, as
  // words).
  void expand(int depth) {
    ++nodes;
    if (limit_hit()) {
      aborted = true;
      return;
    }
    const int k = static_cast<int>(ids_.size());
    std::uint64_t* P = pool_[depth].data();
    std::uint64_t* Q = P + kw_;
    std::uint64_t* U = Q + kw_;
    std::uint64_t* order = U + kw_;  // order[i] vertex, order[k + i] colour
    std::copy(P, P + kw_, Q);
    int cnt = 0, colour = 0;
    while (any(Q, kw_)) {
      ++colour;
      std::copy(Q, Q + kw_, U);
      for (int w = 0; w < kw_; ++w) {
        while (U[w]) {
          const int u = w * 64 + std::countr_zero(U[w]);
          clear_bit(U, u);
          clear_bit(Q, u);
          const std::uint64_t* ru = adj_.data() + static_cast<std::size_t>(u) * kw_;
          for (int x = w; x < kw_; ++x) U[x] &= ~ru[x];
          order[cnt] = static_cast<std::uint64_t>(u);
          order[k + cnt] = static_cast<std::uint64_t>(colour);
          ++cnt;
        }
      }
    }
    std::uint64_t* NP = pool_[depth + 1].data();
    for (int i = cnt - 1; i >= 0; --i) {
      const int size = static_cast<int>(current_.size());
      if (size + static_cast<int>(order[k + i]) < target()) return;
      const int u = static_cast<int>(order[i]);
      current_.push_back(ids_[u]);
      const std::uint64_t* ru = adj_.data() + static_cast<std::size_t>(u) * kw_;
      bool nonempty = false;
      for (int w = 0; w < kw_; ++w) {
        NP[w] = P[w] & ru[w];
        nonempty |= NP[w] != 0;
      }
      if (nonempty)
        expand(depth + 1);
      else
        record();
      current_.pop_back();
      if (aborted) return;
      clear_bit(P, u);
    }
  }

  const CliqueOptions& opt_;
  Clock::time_point t0_;
  std::vector<int> ids_;
  int kw_ = 0;
  std::vector<std::uint64_t> adj_, tmp_adj_;
  std::vector<std::vector<std::uint64_t>> pool_;
  std::vector<int> current_;
};

void finish_ties(CliqueResult& r, std::vector<std::vector<int>> found) {
  for (auto& c : found) std::sort(c.begin(), c.end());
  std::sort(found.begin(), found.end());
  r.clique = found.front();
  r.ties.assign(found.begin() + 1, found.end());
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// ConsistencyGraph

ConsistencyGraph::ConsistencyGraph(int n) {
  if (n < 0) throw std::invalid_argument(fmt::format("ConsistencyGraph: negative vertex count {}", n));
  n_ = n;
  words_ = (n + 63) / 64;
  adj_.assign(static_cast<std::size_t>(n_) * words_, 0);
}

ConsistencyGraph::ConsistencyGraph(int n, const std::vector<std::pair<int, int>>& edges)
    : ConsistencyGraph(n) {
  for (const auto& [u, v] : edges) add_edge(u, v);
}

ConsistencyGraph ConsistencyGraph::from_matrix(const std::vector<std::vector<bool>>& a) {
  const int n = static_cast<int>(a.size());
  ConsistencyGraph g(n);
  for (int i = 0; i < n; ++i)
    if (static_cast<int>(a[i].size()) != n)
      throw std::invalid_argument(fmt::format(
          "ConsistencyGraph::from_matrix: row {} has {} entries, expected {}", i, a[i].size(), n));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (a[i][j] != a[j][i])
        throw std::invalid_argument(
            fmt::format("ConsistencyGraph::from_matrix: matrix is not symmetric at ({}, {})", i, j));
      if (a[i][j]) g.add_edge(i, j);
    }
  return g;
}

ConsistencyGraph ConsistencyGraph::from_threshold(int n, const std::vector<double>& q, double gamma) {
  if (n < 0)
    throw std::invalid_argument(fmt::format("ConsistencyGraph::from_threshold: negative vertex count {}", n));
  if (q.size() != static_cast<std::size_t>(n) * static_cast<std::size_t>(n))
    throw std::invalid_argument(
        fmt::format("ConsistencyGraph::from_threshold: expected {}x{} entries, got {}", n, n, q.size()));
  if (std::isnan(gamma)) throw std::invalid_argument("ConsistencyGraph::from_threshold: gamma is NaN");
  ConsistencyGraph g(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j && std::isnan(q[static_cast<std::size_t>(i) * n + j]))
        throw std::invalid_argument(fmt::format("ConsistencyGraph::from_threshold: NaN at ({}, {})", i, j));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (q[static_cast<std::size_t>(i) * n + j] <= gamma && q[static_cast<std::size_t>(j) * n + i] <= gamma)
        g.add_edge(i, j);
  return g;
}

void ConsistencyGraph::check_vertex(int v, const char* what) const {
  if (v < 0 || v >= n_)
    throw std::invalid_argument(
        fmt::format("ConsistencyGraph::{}: vertex {} out of range [0, {})", what, v, n_));
}

void ConsistencyGraph::add_edge(int u, int v) {
  check_vertex(u, "add_edge");
  check_vertex(v, "add_edge");
  if (u == v)
    throw std::invalid_argument(fmt::format("ConsistencyGraph::add_edge: self loop at vertex {}", u));
  std::uint64_t* ru = adj_.data() + static_cast<std::size_t>(u) * words_;
  if (test_bit(ru, v)) return;
  set_bit(ru, v);
  set_bit(adj_.data() + static_cast<std::size_t>(v) * words_, u);
  ++edges_;
}

bool ConsistencyGraph::adjacent(int u, int v) const {
  check_vertex(u, "adjacent");
  check_vertex(v, "adjacent");
  return test_bit(row(u), v);
}

int ConsistencyGraph::degree(int v) const {
  check_vertex(v, "degree");
  return popcount(row(v), words_);
}

std::vector<int> ConsistencyGraph::neighbors(int v) const {
  check_vertex(v, "neighbors");
  std::vector<int> out;
  const std::uint64_t* r = row(v);
  for (int w = 0; w < words_; ++w) {
    std::uint64_t bits = r[w];
    while (bits) {
      out.push_back(w * 64 + std::countr_zero(bits));
      bits &= bits - 1;
    }
  }
  return out;
}

bool ConsistencyGraph::is_clique(const std::vector<int>& vs) const {
  for (std::size_t i = 0; i < vs.size(); ++i) {
    if (vs[i] < 0 || vs[i] >= n_) return false;
    for (std::size_t j = i + 1; j < vs.size(); ++j)
      if (vs[j] < 0 || vs[j] >= n_ || !test_bit(row(vs[i]), vs[j])) return false;  // also rejects duplicates
  }
  return true;
}

std::vector<int> core_numbers(const ConsistencyGraph& g) { return degeneracy(g).core; }

namespace {
constexpr core::NameTable<CliqueAlgorithm, 3> kCliqueAlgorithmNames{
    "pcm::CliqueAlgorithm",
    {{{CliqueAlgorithm::exact, "exact"},
      {CliqueAlgorithm::heuristic, "heuristic"},
      {CliqueAlgorithm::brute_force, "brute_force"}}}};
constexpr core::NameTable<SearchStatus, 4> kSearchStatusNames{"pcm::SearchStatus",
                                                              {{{SearchStatus::optimal, "optimal"},
                                                                {SearchStatus::unproven, "unproven"},
                                                                {SearchStatus::node_limit, "node_limit"},
                                                                {SearchStatus::time_limit, "time_limit"}}}};
}  // namespace

std::string_view to_string(CliqueAlgorithm a) { return kCliqueAlgorithmNames.name(a); }
CliqueAlgorithm clique_algorithm_from_string(std::string_view s) { return kCliqueAlgorithmNames.parse(s); }
std::string_view to_string(SearchStatus s) { return kSearchStatusNames.name(s); }
SearchStatus search_status_from_string(std::string_view s) { return kSearchStatusNames.parse(s); }

// ---------------------------------------------------------------------------------------------------------------
// Solvers

CliqueResult maximum_clique_heuristic(const ConsistencyGraph& g, const CliqueOptions&) {
  const auto t0 = Clock::now();
  CliqueResult r;
  const auto d = degeneracy(g);
  r.clique = greedy_clique(g, d.core, r.nodes_explored);
  r.upper_bound = g.size() == 0 ? 0 : *std::max_element(d.core.begin(), d.core.end()) + 1;
  r.status =
      static_cast<int>(r.clique.size()) == r.upper_bound ? SearchStatus::optimal : SearchStatus::unproven;
  r.time_s = seconds_since(t0);
  return r;
}

CliqueResult maximum_clique_exact(const ConsistencyGraph& g, const CliqueOptions& opt) {
  const auto t0 = Clock::now();
  CliqueResult r;
  const int n = g.size();
  if (n == 0) {
    r.status = SearchStatus::optimal;
    r.time_s = seconds_since(t0);
    return r;
  }
  const auto d = degeneracy(g);
  std::vector<int> pos(n);
  for (int i = 0; i < n; ++i) pos[d.order[i]] = i;

  long long heuristic_nodes = 0;
  const std::vector<int> initial = greedy_clique(g, d.core, heuristic_nodes);

  Search s(opt, t0);
  s.best = static_cast<int>(initial.size());
  if (!opt.report_ties) s.found.push_back(initial);

  // Per-vertex subproblems, densest end of the degeneracy order first: a clique is found from its earliest
  // vertex.
  int stopped_at = -1;
  std::vector<int> cand;
  for (int i = n - 1; i >= 0; --i) {
    const int v = d.order[i];
    if (d.core[v] + 1 < s.target()) continue;  // k-core pruning
    cand.clear();
    const std::uint64_t* rv = g.row(v);
    for (int w = 0; w < g.words(); ++w)
      for (std::uint64_t bits = rv[w]; bits; bits &= bits - 1) {
        const int u = w * 64 + std::countr_zero(bits);
        if (pos[u] > i && d.core[u] + 1 >= s.target()) cand.push_back(u);
      }
    if (static_cast<int>(cand.size()) + 1 < s.target()) continue;
    std::sort(cand.begin(), cand.end(), [&](int a, int b) { return pos[a] < pos[b]; });
    s.solve(g, v, cand);
    if (s.aborted) {
      stopped_at = i;
      break;
    }
  }

  if (s.found.empty()) s.found.push_back(initial);  // only when aborted with ties requested
  if (opt.report_ties)
    finish_ties(r, s.found);
  else
    r.clique = sorted(s.found.front());
  r.upper_bound = static_cast<int>(r.clique.size());
  if (s.aborted) {
    // Open subproblems: vertices at positions <= stopped_at; a clique through v has at most 1 + |later
    // neighbours|.
    for (int i = stopped_at; i >= 0; --i) {
      const int v = d.order[i];
      int later = 0;
      for (const int u : g.neighbors(v))
        if (pos[u] > i) ++later;
      r.upper_bound = std::max(r.upper_bound, std::min(later, d.core[v]) + 1);
    }
  }
  // A stopped search whose best clique meets its bound is still proven maximum.
  r.status = static_cast<int>(r.clique.size()) == r.upper_bound ? SearchStatus::optimal : s.stop;
  r.nodes_explored = s.nodes + heuristic_nodes;
  r.time_s = seconds_since(t0);
  return r;
}

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
  finish_ties(r, cliques);
  if (!opt.report_ties) r.ties.clear();
  r.upper_bound = best;
  r.status = SearchStatus::optimal;
  r.nodes_explored = nodes;
  r.time_s = seconds_since(t0);
  return r;
}

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
