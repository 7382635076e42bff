// The exact maximum-clique search (eq. 2.5): branch and bound over the subproblems of the degeneracy order,
// on bitsets, with the colouring, re-colouring and MaxSAT bounds described at class Search.
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

namespace {

using core::Clock;
using core::seconds_since;
using namespace detail;

// The graph renumbered into the search order: index 0 is the last vertex of the smallest-last (degeneracy)
// order, so low indices are the dense end. Subproblem j is "vertex j plus a clique of its neighbours with
// smaller index": every clique is found in the subproblem of its highest-index vertex, and subproblem j only
// touches the ceil(j / 64) words of indices below j (San Segundo et al.'s BBMC keeps one global bitset graph
// in its initial order in the same way, so no subproblem rebuilds an adjacency). Only the vertices whose core
// number admits a clique of `min_size` vertices are kept (the target never falls below it, so the others can
// never join a clique the search looks for): on easy graphs, where the greedy clique meets the degeneracy
// bound, nothing is renumbered at all (1D worlds of m = 1000: the renumbering alone cost 1.5 ms of 3.5).
struct OrderedGraph {
  int n = 0;
  int words = 0;
  std::vector<std::uint64_t> adj;  // n rows of `words` words, in search order
  std::vector<int> id;             // search index -> vertex id of g
  std::vector<int> core;           // core number by search index
  const std::uint64_t* row(int j) const { return adj.data() + static_cast<std::size_t>(j) * words; }

  OrderedGraph(const ConsistencyGraph& g, const Degeneracy& d, int min_size) {
    const int all = g.size();
    std::vector<int> index(static_cast<std::size_t>(all), -1);
    for (int k = all - 1; k >= 0; --k) {
      const int v = d.order[k];
      if (d.core[v] + 1 < min_size) continue;
      index[v] = static_cast<int>(id.size());
      id.push_back(v);
      core.push_back(d.core[v]);
    }
    n = static_cast<int>(id.size());
    words = (n + 63) / 64;
    adj.assign(static_cast<std::size_t>(n) * words, 0);
    for (int j = 0; j < n; ++j) {
      const std::uint64_t* r = g.row(id[j]);
      std::uint64_t* out = adj.data() + static_cast<std::size_t>(j) * words;
      for (int w = 0; w < g.words(); ++w)
        for (std::uint64_t bits = r[w]; bits; bits &= bits - 1) {
          const int l = index[w * 64 + std::countr_zero(bits)];
          if (l >= 0) set_bit(out, l);
        }
    }
  }
};

// Branch and bound over the subproblems of an OrderedGraph (Tomita et al.'s MCS scheme on bitsets, as in San
// Segundo et al.'s BBMC):
//   * at each node the candidate set P is greedily coloured in index order, but only into the kmin = target −
//     |C| − 1 classes that can never be branched on (a clique in them has at most kmin vertices); the rest B
//     is the branching set (San Segundo, Matia, Rodriguez-Losada, Galan, Jimenez, Hernando, "An improved bit
//     parallel exact maximum clique algorithm", Optim. Letters 7, 2013);
//   * each b in B is first re-placed into those classes if it can be: inserted where it has no neighbour, or
//     moved by Re-NUMBER (Tomita, Sutani, Higashi, Takahashi, Wakatsuki, WALCOM 2010: b has one neighbour q
//     in class k1 and q none in class k2, so q moves to k2 and b takes its place);
//   * what stays in B is tested by unit propagation on the MaxSAT encoding of Li & Quan (AAAI 2010; the
//     incremental use of Li, Jiang, Manyà, "On minimization of the number of branches in branch-and-bound
//     algorithms for the maximum clique problem", C&OR 84, 2017): the classes are soft clauses, non-edges
//     hard clauses; choosing b forces every class reduced to one neighbour of the chosen vertices; when a
//     class is left with none, {b} and the s classes involved hold at most s clique vertices, so b is not
//     branched on and those s classes are not used again at this node (disjoint inconsistent sets keep the
//     bound valid);
//   * the remaining B is coloured on into classes kmin + 1, … and branched on from the highest colour down,
//   so
//     the prune test |C| + colour < target stays valid when the incumbent grows.
// The two bounds in the third and fourth steps each run only while they pay for themselves (class Search's
// `pays`): the search counts the adjacency words it reads — in colouring and branching (the work of a node)
// and in each bound — and a bound runs at a candidate only while its words so far are at most
// kFreeShare of the node work plus, for every candidate it removed, the mean work of a node (a removed
// candidate saves at least the child node it would have opened). Measured on the clique family of
// bench_clique: on consistency graphs of 1D worlds (m = 2000) the bounds removed no candidate in 4,554 tries,
// each reading ~3·10⁵ words, and made the search 6–22× slower than colouring alone; on G(300, 0.7) they halve
// the nodes and still cost 25 % more time; on planted graphs with k ≥ 2 % of n they never run. Counting
// words, not time, keeps the node count and the answer independent of the machine and its load.
class Search {
 public:
  Search(const OrderedGraph& g, const CliqueOptions& opt, Clock::time_point t0)
      : g_(g),
        opt_(opt),
        t0_(t0),
        Q_(static_cast<std::size_t>(g.words)),
        U_(static_cast<std::size_t>(g.words)) {}

  int best = 0;
  std::vector<std::vector<int>> found;  // global ids, unsorted
  long long nodes = 0;
  bool aborted = false;
  SearchStatus stop = SearchStatus::optimal;  // node_limit or time_limit once aborted
  int root_bound = 0;                         // bound of the subproblem in progress (1 + its root colouring)

  int target() const { return opt_.report_ties ? best : best + 1; }

  // Candidates of subproblem j under the current target: neighbours of j with smaller index whose core number
  // admits a clique of target() vertices, peeled to the (target() − 2)-core of the candidate set (the k-core
  // pruning of Pattabiraman et al. inside the subproblem). Returns false when no clique of target() vertices
  // through j can remain.
  bool candidates(int j, std::uint64_t* P) {
    const int kw = (j + 63) / 64;
    const std::uint64_t* rj = g_.row(j);
    int count = 0;
    for (int w = 0; w < kw; ++w) {
      std::uint64_t bits = rj[w];
      if (w == kw - 1 && (j & 63)) bits &= (std::uint64_t{1} << (j & 63)) - 1;
      P[w] = 0;
      for (std::uint64_t b = bits; b; b &= b - 1) {
        const int l = w * 64 + std::countr_zero(b);
        if (g_.core[l] + 1 >= target()) {
          P[w] |= std::uint64_t{1} << (l & 63);
          ++count;
        }
      }
    }
    const int need = target() - 2;
    for (bool changed = true; changed;) {
      if (count + 1 < target()) return false;
      changed = false;
      for (int w = 0; w < kw; ++w)
        for (std::uint64_t b = P[w]; b; b &= b - 1) {
          const int l = w * 64 + std::countr_zero(b);
          const std::uint64_t* rl = g_.row(l);
          int dg = 0;
          for (int x = 0; x < kw && dg < need; ++x) dg += std::popcount(rl[x] & P[x]);
          if (dg < need) {
            clear_bit(P, l);
            --count;
            changed = true;
          }
        }
    }
    return count + 1 >= target();
  }

  // Solve subproblem j: vertex j plus a clique of its candidates.
  void solve(int j) {
    kw_ = std::max(1, (j + 63) / 64);
    ensure_depth(0);
    if (!candidates(j, pool_[0].data())) return;
    current_.assign(1, j);
    const int count = popcount(pool_[0].data(), kw_);
    if (count == 0) {
      record();
      return;
    }
    root_bound = 1 + count;   // until the root colouring sharpens it
    ensure_depth(count + 1);  // the depth never exceeds |P|: no level moves while the search holds it
    rows_ = g_.adj.data();
    stride_ = g_.words;
    // Most subproblems of an easy graph end at their root colouring, and most of the rest after a few nodes:
    // search on g_'s rows first, with a node budget.
    restart_at_ = opt_.report_ties ? std::numeric_limits<long long>::max() : nodes + kLocalAfterNodes;
    expand(0);
    if (!restarting_) return;
    restarting_ = false;
    restart_at_ = std::numeric_limits<long long>::max();
    current_.assign(1, j);
    if (!candidates(j, pool_[0].data())) return;  // under the incumbent found meanwhile
    // A subproblem that outgrows the budget starts again on its own rows, its candidates renumbered by degree
    // among themselves, highest first: greedy colouring in that order (Welsh–Powell within the subproblem)
    // gives tighter bounds than the global order restricted to P (G(300, 0.7): 30 % less time), and the
    // renumbering (O(|P| · degree) bit operations) would cost more than it saves on the many small
    // subproblems of large graphs (G(2000, 0.7) with a planted 200-clique: 30 % more time when every
    // subproblem is renumbered). Without ties the restart is exact: the incumbent only grew. With ties it
    // would report a clique twice, so a search for ties stays on g_'s rows.
    const std::uint64_t* P = pool_[0].data();
    map_.clear();
    std::vector<int>& deg = degree_;
    deg.assign(static_cast<std::size_t>(j), 0);
    for (int w = 0; w < kw_; ++w)
      for (std::uint64_t b = P[w]; b; b &= b - 1) {
        const int l = w * 64 + std::countr_zero(b);
        map_.push_back(l);
        deg[l] = popcount_and(g_.row(l), P, kw_);
      }
    std::sort(map_.begin(), map_.end(),
              [&](int a, int b) { return deg[a] != deg[b] ? deg[a] > deg[b] : a < b; });
    const int k = static_cast<int>(map_.size());
    if (k == 0) return;
    const int lw = (k + 63) / 64;
    if (static_cast<int>(position_.size()) < g_.n) position_.assign(g_.n, -1);
    for (int i = 0; i < k; ++i) position_[map_[i]] = i;
    local_adj_.assign(static_cast<std::size_t>(k) * lw, 0);
    for (int i = 0; i < k; ++i) {
      const std::uint64_t* r = g_.row(map_[i]);
      std::uint64_t* out = local_adj_.data() + static_cast<std::size_t>(i) * lw;
      for (int w = 0; w < kw_; ++w)
        for (std::uint64_t b = r[w] & P[w]; b; b &= b - 1)
          set_bit(out, position_[w * 64 + std::countr_zero(b)]);
    }
    for (int i = 0; i < k; ++i) position_[map_[i]] = -1;
    std::uint64_t* LP = pool_[0].data();
    std::fill(LP, LP + g_.words, 0);
    for (int i = 0; i < k; ++i) set_bit(LP, i);
    kw_ = lw;
    rows_ = local_adj_.data();
    stride_ = lw;
    local_ = true;
    expand(0);
    local_ = false;
  }

  // 1 + the number of greedy colours of subproblem j's candidates: a bound on any clique through j found in
  // it.
  int colour_bound(int j) {
    kw_ = std::max(1, (j + 63) / 64);
    ensure_depth(0);
    std::uint64_t* P = pool_[0].data();
    if (!candidates(j, P)) return 0;
    rows_ = g_.adj.data();
    stride_ = g_.words;
    local_ = false;
    std::copy(P, P + kw_, Q_.data());
    int colours = 0;
    while (any(Q_.data(), kw_)) {
      ++colours;
      take_class([](int) {});
    }
    return colours + 1;
  }

 private:
  struct Level {
    std::vector<std::uint64_t> P;
    std::vector<int> branch, colour;  // branching set in branching order reversed, and its colours
  };

  void ensure_depth(int depth) {
    if (static_cast<int>(levels_.size()) > depth) return;
    const int from = static_cast<int>(levels_.size());
    pool_.resize(depth + 1);
    levels_.resize(depth + 1);
    for (int l = from; l <= depth; ++l) pool_[l].assign(g_.words, 0);
  }

  // The work accounting behind `pays` (see the class comment), in words of adjacency rows and classes read.
  // Fitted to wall times of bench_clique's family (G(200, 0.7) and G(300, 0.7) with and without the bounds,
  // time = a·words + b·nodes, then the bounds' share): a node costs kNodeWords words beside the words it
  // reads, a bound's visit of a class kClassWords beside the words it reads, and a word read by a bound costs
  // kBoundWordCost words of colouring (short scans, more branches). A bound may spend kFreeShare of the node
  // work without removing anything.
  static constexpr double kNodeWords = 190.0;
  static constexpr int kClassWords = 2;  // a bound's visit of one class, beside the words it reads
  static constexpr double kBoundWordCost = 8.0;
  static constexpr double kFreeShare = 0.02;
  double node_work_ = 0, renumber_work_ = 0, maxsat_work_ = 0;
  long long renumber_hits_ = 0, maxsat_hits_ = 0;
  // Words a bound may still read: its share of the node work plus a mean node per candidate it removed, less
  // what it has read (infinite when the bounds run everywhere).
  double allowance(double work, long long hits) const {
    if (!opt_.adaptive_bounds || opt_.node_limit > 0)  // nodes are the budget: see clique.hpp
      return std::numeric_limits<double>::infinity();
    const double per_node = node_work_ / static_cast<double>(std::max(nodes, 1LL));
    return (kFreeShare * node_work_ + static_cast<double>(hits) * per_node) / kBoundWordCost - work;
  }
  bool pays(double work, long long hits) const { return allowance(work, hits) >= 0.0; }

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
    std::vector<int> ids(current_.size());
    for (std::size_t i = 0; i < current_.size(); ++i) ids[i] = g_.id[current_[i]];
    if (s > best) {
      best = s;
      found.clear();
      found.push_back(std::move(ids));
    } else if (s == best && opt_.report_ties) {
      if (static_cast<int>(found.size()) < std::max(opt_.max_ties, 0) + 1) found.push_back(std::move(ids));
    }
  }

  std::uint64_t* cls(int k) { return classes_.data() + static_cast<std::size_t>(k) * kw_; }
  std::uint64_t* restricted(int k) { return reduced_.data() + static_cast<std::size_t>(k) * kw_; }

  // Number of neighbours of u in class k, stopping at 2; the neighbour when there is exactly one.
  // `words` counts the words read.
  int neighbours_in(const std::uint64_t* ru, const std::uint64_t* c, int& q, double& words) const {
    int count = 0;
    for (int w = 0; w < kw_; ++w) {
      const std::uint64_t x = ru[w] & c[w];
      if (!x) continue;
      count += std::popcount(x);
      if (count > 1) {
        words += w + 1 + kClassWords;
        return count;
      }
      q = w * 64 + std::countr_zero(x);
    }
    words += kw_ + kClassWords;
    return count;
  }

  // Re-places the branching candidate u (see the class comment): inserts it into a class where it has no
  // neighbour, or Re-NUMBERs it, or refutes it by unit propagation over the classes not yet used at this
  // node, marking the classes of the conflict as used. Returns true when u need not be branched on. Runs
  // insertion and Re-NUMBER when `renumber`, unit propagation when `maxsat`; the first pass belongs to
  // Re-NUMBER when it runs (it is what finds the insertions), else to the MaxSAT bound.
  bool settle(int u, int ncls, bool renumber, bool maxsat) {
    const std::uint64_t* ru = row(u);
    double pass = 0;
    // One cheap pass: the number of neighbours of u in each class, stopping at 2 (classes are large near the
    // root, so this usually stops in the first words).
    // A class used by an earlier conflict keeps its members: a refutation holds only for the classes it saw,
    // so neither insertion nor Re-NUMBER may change them.
    int units = 0;
    for (int k = 0; k < ncls; ++k) {
      single_[k] = -1;
      if (used_[k]) continue;
      int q = -1;
      const int c = neighbours_in(ru, cls(k), q, pass);
      if (c == 0) {
        set_bit(cls(k), u);
        (renumber ? renumber_work_ : maxsat_work_) += pass;
        ++(renumber ? renumber_hits_ : maxsat_hits_);
        return true;
      }
      single_[k] = c == 1 ? q : -1;
      units += c == 1 ? 1 : 0;
    }
    (renumber ? renumber_work_ : maxsat_work_) += pass;
    if (units == 0) return false;  // no class forces anything: neither rule applies
    // Each rule stops when it has read its allowance (u then stays a branching candidate, which is always
    // sound): near the root of a large subproblem one call can read more words than the whole search's nodes
    // (world1d_m2000_w4: one call, 1.35·10⁷ words against 4.3·10⁷ of node work, 12 % of the time), and
    // `pays` is asked only before the call.
    if (renumber) {
      const double stop_at = renumber_work_ + allowance(renumber_work_, renumber_hits_);
      for (int k1 = 0; k1 < ncls && renumber_work_ <= stop_at; ++k1) {
        const int q = single_[k1];
        if (q < 0) continue;
        const std::uint64_t* rq = row(q);
        for (int k2 = 0; k2 < ncls; ++k2) {
          if (k2 == k1 || used_[k2]) continue;
          const std::uint64_t* c2 = cls(k2);
          bool free = true;
          int w = 0;
          for (; w < kw_ && free; ++w) free = (rq[w] & c2[w]) == 0;
          renumber_work_ += w + kClassWords;
          if (!free) continue;
          clear_bit(cls(k1), q);
          set_bit(cls(k1), u);
          set_bit(cls(k2), q);
          ++renumber_hits_;
          return true;
        }
      }
    }
    if (!maxsat) return false;
    const double maxsat_allowance = allowance(maxsat_work_, maxsat_hits_);
    double words = 0;
    // Unit propagation from "u is in the clique": restricted(k) = class k ∩ N(u) ∩ N(forced vertices).
    chain_.clear();
    int unit = -1, q = -1;
    for (int k = 0; k < ncls; ++k) {
      state_[k] = used_[k] ? 2 : 0;  // 0 open, 1 forced (in the chain), 2 used by an earlier conflict
      if (used_[k]) continue;
      const std::uint64_t* c = cls(k);
      std::uint64_t* r = restricted(k);
      for (int w = 0; w < kw_; ++w) r[w] = c[w] & ru[w];
      words += kw_ + kClassWords;
      if (unit < 0 && single_[k] >= 0) {
        unit = k;
        q = single_[k];
      }
    }
    while (unit >= 0 && words <= maxsat_allowance) {
      state_[unit] = 1;
      chain_.push_back(unit);
      const std::uint64_t* rq = row(q);
      unit = -1;
      for (int k = 0; k < ncls; ++k) {
        if (state_[k] != 0) continue;
        std::uint64_t* r = restricted(k);
        int count = 0, v = -1;
        for (int w = 0; w < kw_; ++w) {
          r[w] &= rq[w];
          if (r[w]) {
            count += std::popcount(r[w]);
            v = w * 64 + std::countr_zero(r[w]);
          }
        }
        words += kw_ + kClassWords;
        if (count == 0) {  // conflict: {u} and the classes of the chain and k hold at most |chain| + 1 − 1
          used_[k] = 1;
          for (const int c : chain_) used_[c] = 1;
          maxsat_work_ += words;
          ++maxsat_hits_;
          return true;
        }
        if (count == 1 && unit < 0) {
          unit = k;
          q = v;
        }
      }
    }
    maxsat_work_ += words;
    return false;
  }

  // One step of greedy sequential colouring: removes from Q_ the maximal independent set that scanning Q_ in
  // index order picks, calling add(u) for each of its vertices.
  // Q_ and U_ hold g_.words words (a subproblem's kw_ never exceeds it); the words read are summed as an
  // integer and added once (the same value as adding them one by one: integers below 2⁵³).
  template <class Add>
  void take_class(Add&& add) {
    std::uint64_t* Q = Q_.data();
    std::uint64_t* U = U_.data();
    for (int w = 0; w < kw_; ++w) U[w] = Q[w];
    long long work = kw_;
    for (int w = 0; w < kw_; ++w)
      while (U[w]) {
        const int b = std::countr_zero(U[w]);
        U[w] &= U[w] - 1;
        Q[w] &= ~(std::uint64_t{1} << b);
        const int u = w * 64 + b;
        add(u);
        const std::uint64_t* ru = row(u);
        for (int x = w; x < kw_; ++x) U[x] &= ~ru[x];
        work += kw_ - w;
      }
    node_work_ += static_cast<double>(work);
  }

  // Colours P (see the class comment) and fills the level's branching set; returns the number of classes
  // below kmin that were built.
  int colour(std::uint64_t* P, int kmin, Level& L) {
    L.branch.clear();
    L.colour.clear();
    std::copy(P, P + kw_, Q_.data());
    const std::size_t need = static_cast<std::size_t>(std::max(kmin, 0)) * kw_;
    if (classes_.size() < need) classes_.resize(need);
    int ncls = 0;
    while (ncls < kmin && any(Q_.data(), kw_)) {
      std::uint64_t* c = cls(ncls);
      std::fill(c, c + kw_, 0);
      take_class([&](int u) { set_bit(c, u); });
      ++ncls;
    }
    if (!any(Q_.data(), kw_)) return ncls;
    if (ncls == kmin && kmin > 0 &&
        ((opt_.recolour && pays(renumber_work_, renumber_hits_)) ||
         (opt_.maxsat_bound && pays(maxsat_work_, maxsat_hits_)))) {
      if (reduced_.size() < need) reduced_.resize(need);
      used_.assign(ncls, 0);
      state_.resize(ncls);
      single_.resize(ncls);
      for (int w = 0; w < kw_; ++w)
        for (std::uint64_t b = Q_[w]; b; b &= b - 1) {
          const bool renumber = opt_.recolour && pays(renumber_work_, renumber_hits_);
          const bool maxsat = opt_.maxsat_bound && pays(maxsat_work_, maxsat_hits_);
          if (!renumber && !maxsat) continue;
          const int u = w * 64 + std::countr_zero(b);
          if (settle(u, ncls, renumber, maxsat)) clear_bit(Q_.data(), u);
        }
    }
    int col = ncls;
    while (any(Q_.data(), kw_)) {
      ++col;
      take_class([&](int u) {
        L.branch.push_back(u);
        L.colour.push_back(col);
      });
    }
    return ncls;
  }

  // One node: colour P and branch.
  void expand(int depth) {
    ++nodes;
    node_work_ += kNodeWords;
    if (limit_hit()) {
      aborted = true;
      return;
    }
    if (nodes > restart_at_) {
      restarting_ = true;
      return;
    }
    std::uint64_t* P = pool_[depth].data();
    Level& L = levels_[depth];
    const int size = static_cast<int>(current_.size());
    const int ncls = colour(P, target() - size - 1, L);
    if (depth == 0) root_bound = size + (L.colour.empty() ? ncls : L.colour.back());
    std::uint64_t* NP = pool_[depth + 1].data();
    for (int i = static_cast<int>(L.branch.size()) - 1; i >= 0; --i) {
      if (size + L.colour[i] < target()) return;  // the incumbent grew since P was coloured
      const int u = L.branch[i];
      current_.push_back(local_ ? map_[u] : u);
      const std::uint64_t* ru = row(u);
      bool nonempty = false;
      for (int w = 0; w < kw_; ++w) {
        NP[w] = P[w] & ru[w];
        nonempty |= NP[w] != 0;
      }
      node_work_ += kw_;
      if (nonempty)
        expand(depth + 1);
      else
        record();
      current_.pop_back();
      if (aborted || restarting_) return;
      clear_bit(P, u);
    }
  }

  const std::uint64_t* row(int u) const { return rows_ + static_cast<std::size_t>(u) * stride_; }

  const OrderedGraph& g_;
  const CliqueOptions& opt_;
  Clock::time_point t0_;
  int kw_ = 1;
  // The rows the search reads: g_'s, or a subproblem's own renumbered copy (local_; map_ takes its indices
  // back).
  const std::uint64_t* rows_ = nullptr;
  int stride_ = 0;
  bool local_ = false;
  // Measured (bench/side_by_side/clique.sh, colouring only, one process per value): 256 → 64 took G(200, 0.7)
  // with a planted 4 from 172,130 to 151,991 nodes (a1b7a03, which renumbered every subproblem: 143,717) and
  // G(300, 0.5) with a planted 6 from 84,956 to 65,143; 32 and 16 saved a few percent more there but cost
  // 19–60 % more nodes on G(100, 0.7) (1,398 → 1,665 → 1,929); planted graphs with k ≥ 2 % of n and the 1D
  // worlds kept their node counts within 1 % (world1d_m2000_w4: 5,497 → 4,729).
  static constexpr long long kLocalAfterNodes = 64;
  long long restart_at_ = std::numeric_limits<long long>::max();
  bool restarting_ = false;
  std::vector<int> map_, position_;
  std::vector<std::uint64_t> local_adj_;
  std::vector<std::vector<std::uint64_t>> pool_;
  std::vector<Level> levels_;
  std::vector<std::uint64_t> classes_, reduced_, Q_, U_;
  std::vector<char> used_, state_;
  std::vector<int> chain_, single_, degree_;
  std::vector<int> current_;
};

}  // namespace

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
  long long heuristic_nodes = 0;
  std::vector<int> initial = greedy_clique(g, d.core, heuristic_nodes);
  if (!opt.initial_clique.empty()) {
    if (!g.is_clique(opt.initial_clique))
      throw std::invalid_argument(
          "maximum_clique_exact: CliqueOptions::initial_clique is not a clique of the graph (ids out of "
          "range, "
          "repeated, or a pair not adjacent)");
    if (opt.initial_clique.size() > initial.size()) initial = sorted(opt.initial_clique);
  }
  const int first_target =
      opt.report_ties ? static_cast<int>(initial.size()) : static_cast<int>(initial.size()) + 1;
  const OrderedGraph og(g, d, first_target);

  Search s(og, opt, t0);
  s.best = static_cast<int>(initial.size());
  if (!opt.report_ties) s.found.push_back(initial);

  // Subproblems from the dense end: subproblem j holds every clique whose highest search index is j.
  int stopped_at = -1;
  for (int j = 0; j < og.n; ++j) {
    if (og.core[j] + 1 < s.target()) continue;  // k-core pruning
    s.solve(j);
    if (s.aborted) {
      stopped_at = j;
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
    // The subproblem in progress is bounded by its root colouring, the unopened ones by colouring their
    // candidates (under the final incumbent: a vertex whose core number admits no larger clique is left out).
    r.upper_bound = std::max(r.upper_bound, s.root_bound);
    for (int j = stopped_at + 1; j < og.n; ++j)
      if (og.core[j] + 1 > r.upper_bound) r.upper_bound = std::max(r.upper_bound, s.colour_bound(j));
  }
  // A stopped search whose best clique meets its bound is still proven maximum.
  r.status = static_cast<int>(r.clique.size()) == r.upper_bound ? SearchStatus::optimal : s.stop;
  r.nodes_explored = s.nodes + heuristic_nodes;
  r.time_s = seconds_since(t0);
  return r;
}

}  // namespace keel::pcm
