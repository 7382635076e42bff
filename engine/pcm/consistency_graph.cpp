// The consistency graph of §2.5 as bitset adjacency rows, and its degeneracy (core numbers and smallest-last
// order).
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

void finish_ties(CliqueResult& r, std::vector<std::vector<int>> found) {
  for (auto& c : found) std::sort(c.begin(), c.end());
  std::sort(found.begin(), found.end());
  r.clique = found.front();
  r.ties.assign(found.begin() + 1, found.end());
}

}  // namespace detail

using namespace detail;

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

std::vector<int> core_numbers(const ConsistencyGraph& g) { return detail::degeneracy(g).core; }

}  // namespace keel::pcm
