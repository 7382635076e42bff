// Extraction::forward (extraction.hpp): W_v = L⁻¹ P E_v by sparse forward substitutions along the supernodal
// elimination tree, Σ_ab = W_aᵀ W_b.

#include <Eigen/Core>
#include <fmt/format.h>
#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>

#include "cov/extraction.hpp"

namespace keel::cov::detail {

namespace {

// W_x = L⁻¹ P R_x for items x, each a block of right-hand sides R_x (n × dim x): a variable's unit columns
// E_v (ForwardBlocks) or a linear map's K_uᵀ (ForwardMaps). W_x is nonzero only on the union of the paths to
// the root of the supernodes of R_x's nonzero rows, and is stored there; W_xᵀ W_y is one product over the
// supernodes common to both.
class ForwardStore {
 public:
  // One nonzero of an item: the right-hand side's column `col` (0 … dim − 1) has `value` in row `row` of H.
  struct Entry {
    int col;
    int row;
    double value;
  };

  explicit ForwardStore(const Impl& I) : I_(I) {}

  // Adds an item of `dim` columns with the given nonzeros (rows of H, none of the gauge's); returns its
  // index.
  std::size_t add(int dim, std::vector<Entry> entries) {
    items_.push_back({dim, std::move(entries)});
    return items_.size() - 1;
  }
  std::size_t size() const { return items_.size(); }

  // Forms every W_x, in chunks of items of at most block_columns columns taken in the factor's column order
  // (so that a chunk's paths largely coincide), on `threads` workers; after each item, after(x) on its
  // worker.
  template <class After>
  void run(unsigned threads, const After& after) {
    std::vector<std::pair<int, std::size_t>> order;  // (first permuted column, item)
    order.reserve(items_.size());
    for (std::size_t x = 0; x < items_.size(); ++x) {
      int first = I_.size;
      for (const Entry& e : items_[x].entries)
        first = std::min(first, I_.iperm[static_cast<std::size_t>(e.row)]);
      order.emplace_back(first, x);
    }
    std::sort(order.begin(), order.end());
    order_.resize(order.size());
    for (std::size_t k = 0; k < order.size(); ++k) order_[k] = order[k].second;
    w_.assign(items_.size(), {});
    const auto starts = chunk_starts(order_.size(), I_.options.block_columns,
                                     [&](std::size_t k) { return items_[order_[k]].dim; });
    run_chunks<Workspace>(starts.size() - 1, threads, [&](std::size_t ch, Workspace& ws) {
      solve_chunk(ws, starts[ch], starts[ch + 1]);
      for (std::size_t k = starts[ch]; k < starts[ch + 1]; ++k) after(order_[k]);
    });
  }

  // W_xᵀ W_y over the supernodes common to both paths (dim x × dim y, into acc).
  void product(std::size_t x, std::size_t y, MapX& acc) const {
    const W& wa = w_[x];
    const W& wb = w_[y];
    acc.setZero();
    // Merge the two sorted supernode lists; runs of common supernodes are contiguous in both stores.
    std::size_t ia = 0, ib = 0;
    const std::size_t na = wa.snodes.size(), nb = wb.snodes.size();
    while (ia < na && ib < nb) {
      if (wa.snodes[ia] < wb.snodes[ib]) {
        ++ia;
      } else if (wb.snodes[ib] < wa.snodes[ia]) {
        ++ib;
      } else {
        const int oa = wa.offs[ia], ob = wb.offs[ib];
        int len = 0;
        while (ia < na && ib < nb && wa.snodes[ia] == wb.snodes[ib]) {
          len += I_.nscol(wa.snodes[ia]);
          ++ia;
          ++ib;
        }
        const CMapX A(wa.x.data() + oa, len, acc.rows(), Eigen::OuterStride<>(wa.rows));
        const CMapX B(wb.x.data() + ob, len, acc.cols(), Eigen::OuterStride<>(wb.rows));
        acc.noalias() +=
            A.transpose().lazyProduct(B);  // coefficient-wise dots: faster than GEMM for ≤ 6 columns
      }
    }
  }

 private:
  struct Item {
    int dim = 0;
    std::vector<Entry> entries;
  };

  struct W {
    std::vector<int> snodes;  // supernodes where W_x is nonzero, increasing
    std::vector<int> offs;    // first row of each in x
    int rows = 0;             // Σ nscol over snodes
    std::vector<double> x;    // rows × dim, column-major
  };

  struct Workspace {
    std::vector<int> loc;   // supernode → first row in Y (−1: not reached)
    std::vector<int> mark;  // per-item path marks
    std::vector<int> reached;
    std::vector<double> Y;
    MatX T;
  };

  void solve_chunk(Workspace& ws, std::size_t k0, std::size_t k1) {  // writes only W of the chunk's items
    const Impl& I = I_;
    if (ws.loc.empty()) {
      ws.loc.assign(static_cast<std::size_t>(I.nsuper), -1);
      ws.mark.assign(static_cast<std::size_t>(I.nsuper), -1);
    }
    int nrhs = 0;
    for (std::size_t k = k0; k < k1; ++k) nrhs += items_[order_[k]].dim;
    // supernodes reached from any nonzero row (the union of their paths to the root), in topological order
    ws.reached.clear();
    for (std::size_t k = k0; k < k1; ++k)
      for (const Entry& e : items_[order_[k]].entries)
        for (int s = I.snode_of_col[static_cast<std::size_t>(I.iperm[static_cast<std::size_t>(e.row)])];
             s >= 0 && ws.loc[static_cast<std::size_t>(s)] < 0; s = I.parent[static_cast<std::size_t>(s)]) {
          ws.loc[static_cast<std::size_t>(s)] = 0;
          ws.reached.push_back(s);
        }
    std::sort(ws.reached.begin(), ws.reached.end());
    int R = 0;
    for (int s : ws.reached) {
      ws.loc[static_cast<std::size_t>(s)] = R;
      R += I.nscol(s);
    }
    ws.Y.assign(static_cast<std::size_t>(R) * static_cast<std::size_t>(nrhs), 0.0);
    MapX Y(ws.Y.data(), R, nrhs, Eigen::OuterStride<>(R));
    auto row_of = [&](int col) {
      const int s = I.snode_of_col[static_cast<std::size_t>(col)];
      const int l = ws.loc[static_cast<std::size_t>(s)];
      if (l < 0) throw std::logic_error("MarginalCovariance: a row of L lies outside the path to the root");
      return l + col - I.super[s];
    };
    {
      int j0 = 0;
      for (std::size_t k = k0; k < k1; ++k) {
        const Item& item = items_[order_[k]];
        for (const Entry& e : item.entries)
          Y(row_of(I.iperm[static_cast<std::size_t>(e.row)]), j0 + e.col) += e.value;
        j0 += item.dim;
      }
    }

    // forward substitution L Y = P R, supernode by supernode
    for (int s : ws.reached) {
      const int nc = I.nscol(s), nr = I.nsrow(s);
      const CMapX Ls(I.lx + I.px[s], nr, nc, Eigen::OuterStride<>(nr));
      auto Ys = Y.middleRows(ws.loc[static_cast<std::size_t>(s)], nc);
      Ls.topRows(nc).triangularView<Eigen::Lower>().solveInPlace(Ys);
      if (nr == nc) continue;
      ws.T.noalias() = Ls.bottomRows(nr - nc) * Ys;
      const int* rows = I.ls + I.pi[s] + nc;
      for (int i = 0; i < nr - nc; ++i) Y.row(row_of(rows[i])) -= ws.T.row(i);
    }

    // keep each item's columns on its own path(s)
    int j0 = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      const int x = static_cast<int>(order_[k]);
      const Item& item = items_[order_[k]];
      W& w = w_[order_[k]];
      w.snodes.clear();
      for (const Entry& e : item.entries)
        for (int s = I.snode_of_col[static_cast<std::size_t>(I.iperm[static_cast<std::size_t>(e.row)])];
             s >= 0 && ws.mark[static_cast<std::size_t>(s)] != x; s = I.parent[static_cast<std::size_t>(s)]) {
          ws.mark[static_cast<std::size_t>(s)] = x;
          w.snodes.push_back(s);
        }
      std::sort(w.snodes.begin(), w.snodes.end());
      w.offs.resize(w.snodes.size());
      w.rows = 0;
      for (std::size_t q = 0; q < w.snodes.size(); ++q) {
        w.offs[q] = w.rows;
        w.rows += I.nscol(w.snodes[q]);
      }
      w.x.assign(static_cast<std::size_t>(w.rows) * static_cast<std::size_t>(item.dim), 0.0);
      MapX X(w.x.data(), w.rows, item.dim, Eigen::OuterStride<>(w.rows));
      for (std::size_t q = 0; q < w.snodes.size(); ++q) {
        const int s = w.snodes[q];
        X.middleRows(w.offs[q], I.nscol(s)) =
            Y.block(ws.loc[static_cast<std::size_t>(s)], j0, I.nscol(s), item.dim);
      }
      for (int s : w.snodes) ws.mark[static_cast<std::size_t>(s)] = -1;
      j0 += item.dim;
    }
    for (int s : ws.reached) ws.loc[static_cast<std::size_t>(s)] = -1;
  }

  const Impl& I_;
  std::vector<Item> items_;
  std::vector<std::size_t> order_;  // items in the factor's column order
  std::vector<W> w_;                // by item
};

// Extraction::forward for blocks of Σ: an item per variable asked for, its unit columns E_v; Σ_ab = W_aᵀ W_b.
class ForwardBlocks {
 public:
  explicit ForwardBlocks(const Impl& I)
      : I_(I), store_(I), slot_(static_cast<std::size_t>(I.num_variables()), -1) {}

  void need(int a, int b) {
    for (int v : {a, b})
      if (I_.off(v) >= 0 && slot_[static_cast<std::size_t>(v)] < 0) {
        std::vector<ForwardStore::Entry> unit;
        for (int d = 0; d < I_.dim(v); ++d) unit.push_back({d, I_.off(v) + d, 1.0});
        slot_[static_cast<std::size_t>(v)] = static_cast<int>(store_.add(I_.dim(v), std::move(unit)));
      }
  }

  void run(unsigned threads) {
    // Diagonal blocks Σ_vv = W_vᵀ W_v, once per variable (exactly symmetric), filled in by the chunk's
    // worker.
    diag_start_.assign(store_.size(), 0);
    std::size_t total = 0;
    std::vector<int> dim(store_.size(), 0);
    for (std::size_t v = 0; v < slot_.size(); ++v)
      if (slot_[v] >= 0) dim[static_cast<std::size_t>(slot_[v])] = I_.dim(static_cast<int>(v));
    for (std::size_t x = 0; x < store_.size(); ++x) {
      diag_start_[x] = total;
      total += static_cast<std::size_t>(dim[x] * dim[x]);
    }
    diag_.assign(total, 0.0);
    store_.run(threads, [&](std::size_t x) {
      const int d = dim[x];
      MapX D(diag_.data() + diag_start_[x], d, d, Eigen::OuterStride<>(d));
      store_.product(x, x, D);
      D = (0.5 * (D + D.transpose())).eval();
    });
  }

  // Σ_ab (dim a × dim b) into out (column-major, leading dimension ld); a and b have rows in H.
  void get(int a, int b, double* out, Eigen::Index ld) const {
    const int da = I_.dim(a), db = I_.dim(b);
    MapX dst(out, da, db, Eigen::OuterStride<>(ld));
    const auto xa = static_cast<std::size_t>(slot_[static_cast<std::size_t>(a)]);
    const auto xb = static_cast<std::size_t>(slot_[static_cast<std::size_t>(b)]);
    if (a == b) {
      dst = CMapX(diag_.data() + diag_start_[xa], da, da, Eigen::OuterStride<>(da));
    } else if (a < b) {
      store_.product(xa, xb, dst);
    } else {
      double t[36];
      MapX tb(t, db, da, Eigen::OuterStride<>(db));
      store_.product(xb, xa, tb);
      dst = tb.transpose();
    }
  }

 private:
  const Impl& I_;
  ForwardStore store_;
  std::vector<int> slot_;                // variable → item
  std::vector<std::size_t> diag_start_;  // item → first entry of its diagonal block in diag_
  std::vector<double> diag_;
};

}  // namespace

std::vector<MatX> joint_many_forward(const Impl& I, const std::vector<std::vector<int>>& queries,
                                     unsigned threads) {
  return joint_many_with<ForwardBlocks>(I, queries, threads);
}

template <int D>
std::vector<PairBlock<D>> pairs_forward(const Impl& I, const std::vector<std::pair<int, int>>& pairs,
                                        unsigned threads) {
  return pairs_with<ForwardBlocks, D>(I, pairs, threads);
}
// Extraction::forward for linear maps: an item per map, K_uᵀ's nonzeros (none on the gauge's variable, whose
// rows H does not have); Cov(y_u, y_v) = Z_uᵀ Z_v with Z_u = L⁻¹ P K_uᵀ.
std::vector<MatX> maps_forward(const Impl& I, const std::vector<LinearMap>& maps,
                               const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                               unsigned threads) {
  ForwardStore store(I);
  std::vector<std::ptrdiff_t> item(maps.size(), -1);
  for (const auto& [u, v] : pairs)
    for (const std::size_t m : {u, v}) {
      if (item[m] >= 0) continue;
      std::vector<ForwardStore::Entry> entries;
      const auto rows = static_cast<int>(maps[m].coefficients.front().rows());
      for (std::size_t t = 0; t < maps[m].vars.size(); ++t) {
        const int var = maps[m].vars[t];
        if (I.off(var) < 0) continue;
        const MatX& C = maps[m].coefficients[t];
        for (int r = 0; r < rows; ++r)
          for (int d = 0; d < I.dim(var); ++d)
            if (C(r, d) != 0.0) entries.push_back({r, I.off(var) + d, C(r, d)});
      }
      item[m] = static_cast<std::ptrdiff_t>(store.add(rows, std::move(entries)));
    }
  store.run(threads, [](std::size_t) {});
  std::vector<MatX> out(pairs.size());
  core::parallel_for(
      pairs.size(),
      [&](std::size_t k) {
        const auto [u, v] = pairs[k];
        MatX S(maps[u].coefficients.front().rows(), maps[v].coefficients.front().rows());
        MapX dst(S.data(), S.rows(), S.cols(), Eigen::OuterStride<>(S.rows()));
        store.product(static_cast<std::size_t>(item[u]), static_cast<std::size_t>(item[v]), dst);
        if (u == v) S = (0.5 * (S + S.transpose())).eval();
        out[k] = std::move(S);
      },
      threads);
  return out;
}

template std::vector<PairBlock<3>> pairs_forward<3>(const Impl&, const std::vector<std::pair<int, int>>&,
                                                    unsigned);
template std::vector<PairBlock<6>> pairs_forward<6>(const Impl&, const std::vector<std::pair<int, int>>&,
                                                    unsigned);

}  // namespace keel::cov::detail
