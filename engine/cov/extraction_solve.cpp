// Extraction::solve (extraction.hpp): multi-column solves of H X = E for the distinct variables,
// keeping the rows the queries need (simplicial factors, and the cross-check of Extraction::forward in the
// tests).
#include <Eigen/Core>
#include <fmt/format.h>
#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>

#include "cov/extraction.hpp"

namespace keel::cov::detail {

namespace {

// Extraction::solve — H X = E for the columns of the distinct variables (linalg::SparseCholesky, dense
// multi-column blocks), keeping for each column variable c the rows of the variables r ≤ c paired with it.
class SolveBlocks {
 public:
  explicit SolveBlocks(const Impl& I) : I_(I), col_of_var_(static_cast<std::size_t>(I.num_variables()), -1) {}

  void need(int a, int b) {
    if (I_.off(a) < 0 || I_.off(b) < 0) return;
    requests_.emplace_back(std::max(a, b), std::min(a, b));
  }

  void run(unsigned threads) {
    std::sort(requests_.begin(), requests_.end());
    requests_.erase(std::unique(requests_.begin(), requests_.end()), requests_.end());
    for (std::size_t k = 0; k < requests_.size();) {
      const int c = requests_[k].first;
      col_of_var_[static_cast<std::size_t>(c)] = static_cast<int>(cols_.size());
      cols_.push_back(c);
      rows_.emplace_back();
      row_start_.emplace_back();
      int height = 0;
      for (; k < requests_.size() && requests_[k].first == c; ++k) {
        rows_.back().push_back(requests_[k].second);
        row_start_.back().push_back(height);
        height += I_.dim(requests_[k].second);
      }
      height_.push_back(height);
      store_.push_back(total_);
      total_ += static_cast<std::size_t>(height) * static_cast<std::size_t>(I_.dim(c));
    }
    requests_.clear();
    requests_.shrink_to_fit();
    values_.assign(total_, 0.0);
    const auto starts =
        chunk_starts(cols_.size(), I_.options.block_columns, [&](std::size_t k) { return I_.dim(cols_[k]); });
    run_chunks<Workspace>(starts.size() - 1, threads, [&](std::size_t ch, Workspace& ws) {
      solve_chunk(ws, starts[ch], starts[ch + 1]);
    });
  }

  // Σ_ab into out (column-major, leading dimension ld); a and b have rows in H.
  void get(int a, int b, double* out, Eigen::Index ld) const {
    const int da = I_.dim(a), db = I_.dim(b);
    MapX dst(out, da, db, Eigen::OuterStride<>(ld));
    const int c = std::max(a, b), r = std::min(a, b);
    const int ci = col_of_var_[static_cast<std::size_t>(c)];
    if (ci < 0) throw std::logic_error("MarginalCovariance: block was not requested");
    const auto& rows = rows_[static_cast<std::size_t>(ci)];
    const auto it = std::lower_bound(rows.begin(), rows.end(), r);
    if (it == rows.end() || *it != r) throw std::logic_error("MarginalCovariance: block was not requested");
    const std::size_t ri = static_cast<std::size_t>(it - rows.begin());
    const CMapX block(values_.data() + store_[static_cast<std::size_t>(ci)] +
                          static_cast<std::size_t>(row_start_[static_cast<std::size_t>(ci)][ri]),
                      I_.dim(r), I_.dim(c), Eigen::OuterStride<>(height_[static_cast<std::size_t>(ci)]));
    if (a == r)
      dst = block;  // Σ_rc
    else
      dst = block.transpose();
  }

 private:
  // Per-thread solve state (CHOLMOD's common and dense workspaces, reused across chunks).
  using Workspace = linalg::SolveWorkspace;

  void solve_chunk(Workspace& w, std::size_t k0, std::size_t k1) {
    const std::size_t n = static_cast<std::size_t>(I_.size);
    int ncols = 0;
    for (std::size_t k = k0; k < k1; ++k) ncols += I_.dim(cols_[k]);
    double* b = w.right_hand_sides(I_.size, ncols);
    int col = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      const int v = cols_[k], o = I_.off(v);
      for (int d = 0; d < I_.dim(v); ++d, ++col)
        b[static_cast<std::size_t>(col) * n + static_cast<std::size_t>(o + d)] = 1.0;
    }
    int ld = 0;
    const double* x = I_.factor->solve(w, &ld);
    const CMapX X(x, static_cast<Eigen::Index>(n), ncols, Eigen::OuterStride<>(ld));
    col = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      const int v = cols_[k], dc = I_.dim(v);
      MapX dst(values_.data() + store_[k], height_[k], dc, Eigen::OuterStride<>(height_[k]));
      for (std::size_t ri = 0; ri < rows_[k].size(); ++ri) {
        const int r = rows_[k][ri], dr = I_.dim(r);
        auto blk = dst.middleRows(row_start_[k][ri], dr);
        blk = X.block(I_.off(r), col, dr, dc);
        if (r == v) blk = (0.5 * (blk + blk.transpose())).eval();  // the diagonal block: exactly symmetric
      }
      col += dc;
    }
  }

  const Impl& I_;
  std::vector<std::pair<int, int>> requests_;  // (column var, row var), row ≤ column
  std::vector<int> col_of_var_;
  std::vector<int> cols_;
  std::vector<std::vector<int>> rows_;
  std::vector<std::vector<int>> row_start_;
  std::vector<int> height_;
  std::vector<std::size_t> store_;
  std::size_t total_ = 0;
  std::vector<double> values_;
};

}  // namespace

std::vector<MatX> joint_many_solve(const Impl& I, const std::vector<std::vector<int>>& queries,
                                   unsigned threads) {
  return joint_many_with<SolveBlocks>(I, queries, threads);
}

template <int D>
std::vector<PairBlock<D>> pairs_solve(const Impl& I, const std::vector<std::pair<int, int>>& pairs,
                                      unsigned threads) {
  return pairs_with<SolveBlocks, D>(I, pairs, threads);
}
std::vector<MatX> maps_solve(const Impl& I, const std::vector<LinearMap>& maps,
                             const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                             unsigned threads) {
  return maps_with<SolveBlocks>(I, maps, pairs, threads);
}

template std::vector<PairBlock<3>> pairs_solve<3>(const Impl&, const std::vector<std::pair<int, int>>&,
                                                  unsigned);
template std::vector<PairBlock<6>> pairs_solve<6>(const Impl&, const std::vector<std::pair<int, int>>&,
                                                  unsigned);

}  // namespace keel::cov::detail
