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

// Extraction::forward — W_v = L⁻¹ P E_v on the supernodes of v's path(s) to the root; Σ_ab = W_aᵀ W_b.
class ForwardBlocks {
 public:
  explicit ForwardBlocks(const Impl& I) : I_(I), slot_(static_cast<std::size_t>(I.num_variables()), -1) {}

  void need(int a, int b) {
    for (int v : {a, b})
      if (I_.off(v) >= 0 && slot_[static_cast<std::size_t>(v)] < 0) {
        slot_[static_cast<std::size_t>(v)] = static_cast<int>(vars_.size());
        vars_.push_back(v);
      }
  }

  void run(unsigned threads) {
    // Variables in the factor's column order, so that a chunk's paths to the root largely coincide.
    std::vector<std::pair<int, int>> order;  // (first permuted column, variable)
    order.reserve(vars_.size());
    for (int v : vars_) {
      int first = I_.size;
      for (int d = 0; d < I_.dim(v); ++d)
        first = std::min(first, I_.iperm[static_cast<std::size_t>(I_.off(v) + d)]);
      order.emplace_back(first, v);
    }
    std::sort(order.begin(), order.end());
    for (std::size_t k = 0; k < order.size(); ++k) vars_[k] = order[k].second;
    for (std::size_t k = 0; k < vars_.size(); ++k)
      slot_[static_cast<std::size_t>(vars_[k])] = static_cast<int>(k);
    w_.assign(vars_.size(), {});
    const auto starts =
        chunk_starts(vars_.size(), I_.options.block_columns, [&](std::size_t k) { return I_.dim(vars_[k]); });
    // Diagonal blocks Σ_vv = W_vᵀ W_v, once per variable (exactly symmetric), filled in by the chunk's
    // worker.
    diag_start_.assign(vars_.size(), 0);
    std::size_t total = 0;
    for (std::size_t k = 0; k < vars_.size(); ++k) {
      diag_start_[k] = total;
      total += static_cast<std::size_t>(I_.dim(vars_[k]) * I_.dim(vars_[k]));
    }
    diag_.assign(total, 0.0);
    run_chunks<Workspace>(starts.size() - 1, threads, [&](std::size_t ch, Workspace& ws) {
      solve_chunk(ws, starts[ch], starts[ch + 1]);
      for (std::size_t k = starts[ch]; k < starts[ch + 1]; ++k) {
        const int d = I_.dim(vars_[k]);
        MapX D(diag_.data() + diag_start_[k], d, d, Eigen::OuterStride<>(d));
        product(vars_[k], vars_[k], D);
        D = (0.5 * (D + D.transpose())).eval();
      }
    });
  }

  // Σ_ab (dim a × dim b) into out (column-major, leading dimension ld).
  void get(int a, int b, double* out, Eigen::Index ld) const {
    const int da = I_.dim(a), db = I_.dim(b);
    MapX dst(out, da, db, Eigen::OuterStride<>(ld));
    if (I_.off(a) < 0 || I_.off(b) < 0) {
      dst.setZero();
    } else if (a == b) {
      dst = CMapX(diag_.data() + diag_start_[static_cast<std::size_t>(slot_[static_cast<std::size_t>(a)])],
                  da, da, Eigen::OuterStride<>(da));
    } else if (a < b) {
      product(a, b, dst);
    } else {
      double t[36];
      MapX tb(t, db, da, Eigen::OuterStride<>(db));
      product(b, a, tb);
      dst = tb.transpose();
    }
  }

 private:
  // W_aᵀ W_b over the supernodes common to both paths.
  void product(int a, int b, MapX& acc) const {
    const W& wa = w_[static_cast<std::size_t>(slot_[static_cast<std::size_t>(a)])];
    const W& wb = w_[static_cast<std::size_t>(slot_[static_cast<std::size_t>(b)])];
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

  struct W {
    std::vector<int> snodes;  // supernodes where W_v is nonzero, increasing
    std::vector<int> offs;    // first row of each in x
    int rows = 0;             // Σ nscol over snodes
    std::vector<double> x;    // rows × dim(v), column-major
  };

  struct Workspace {
    std::vector<int> loc;   // supernode → first row in Y (−1: not reached)
    std::vector<int> mark;  // per-variable path marks
    std::vector<int> reached;
    std::vector<double> Y;
    MatX T;
  };

  void solve_chunk(Workspace& ws, std::size_t k0, std::size_t k1) {  // writes only the slots k0 … k1−1 of w_
    const Impl& I = I_;
    if (ws.loc.empty()) {
      ws.loc.assign(static_cast<std::size_t>(I.nsuper), -1);
      ws.mark.assign(static_cast<std::size_t>(I.nsuper), -1);
    }
    // right-hand-side columns: the permuted columns of the chunk's variables
    std::vector<int> cols;
    for (std::size_t k = k0; k < k1; ++k)
      for (int d = 0; d < I.dim(vars_[k]); ++d)
        cols.push_back(I.iperm[static_cast<std::size_t>(I.off(vars_[k]) + d)]);
    const int nrhs = static_cast<int>(cols.size());
    // supernodes reached from any of them (the union of their paths to the root), in topological order
    ws.reached.clear();
    for (int c : cols)
      for (int s = I.snode_of_col[static_cast<std::size_t>(c)];
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
    for (int j = 0; j < nrhs; ++j) Y(row_of(cols[static_cast<std::size_t>(j)]), j) = 1.0;

    // forward substitution L Y = E, supernode by supernode
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

    // keep each variable's columns on its own path(s)
    int j0 = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      const int v = vars_[k], dv = I.dim(v);
      W& w = w_[k];
      w.snodes.clear();
      for (int d = 0; d < dv; ++d)
        for (int s = I.snode_of_col[static_cast<std::size_t>(cols[static_cast<std::size_t>(j0 + d)])];
             s >= 0 && ws.mark[static_cast<std::size_t>(s)] != v; s = I.parent[static_cast<std::size_t>(s)]) {
          ws.mark[static_cast<std::size_t>(s)] = v;
          w.snodes.push_back(s);
        }
      std::sort(w.snodes.begin(), w.snodes.end());
      w.offs.resize(w.snodes.size());
      w.rows = 0;
      for (std::size_t q = 0; q < w.snodes.size(); ++q) {
        w.offs[q] = w.rows;
        w.rows += I.nscol(w.snodes[q]);
      }
      w.x.assign(static_cast<std::size_t>(w.rows) * static_cast<std::size_t>(dv), 0.0);
      MapX X(w.x.data(), w.rows, dv, Eigen::OuterStride<>(w.rows));
      for (std::size_t q = 0; q < w.snodes.size(); ++q) {
        const int s = w.snodes[q];
        X.middleRows(w.offs[q], I.nscol(s)) =
            Y.block(ws.loc[static_cast<std::size_t>(s)], j0, I.nscol(s), dv);
      }
      for (int s : w.snodes) ws.mark[static_cast<std::size_t>(s)] = -1;
      j0 += dv;
    }
    for (int s : ws.reached) ws.loc[static_cast<std::size_t>(s)] = -1;
  }

  const Impl& I_;
  std::vector<int> slot_;  // variable → index in vars_ / w_
  std::vector<int> vars_;
  std::vector<W> w_;
  std::vector<std::size_t> diag_start_;  // slot → first entry of its diagonal block in diag_
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
template std::vector<PairBlock<3>> pairs_forward<3>(const Impl&, const std::vector<std::pair<int, int>>&,
                                                    unsigned);
template std::vector<PairBlock<6>> pairs_forward<6>(const Impl&, const std::vector<std::pair<int, int>>&,
                                                    unsigned);

}  // namespace keel::cov::detail
