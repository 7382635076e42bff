// Extraction of blocks of Σ = H⁻¹ from the factor of a MarginalCovariance (private to engine/cov).
//
// Extraction methods — why forward substitutions along the elimination tree (Extraction::forward):
//   The target batches — e.g. every pose pair (i, i+k) for k up to 500 on Manhattan3500 — ask for blocks Σ_ab
//   that lie far outside the pattern of L, so selected inversion (Takahashi recurrences, which give Σ on the
//   pattern of L only) would still need a solve for almost every block. Instead, with W = L⁻¹ P E (E: the
//   unit columns of the variables asked for), Σ_ab = E_aᵀ H⁻¹ E_b = W_aᵀ W_b. A column of W is nonzero only
//   on the path of its column's supernode to the root of the supernodal elimination tree, so each W_a is
//   computed by a forward substitution that visits just those supernodes (dense triangular solve + update per
//   supernode, on a block of many right-hand sides at a time: `block_columns` variables adjacent in the
//   factor's order, whose paths largely coincide), and stored sparse. A block Σ_ab is then one small product
//   over the supernodes common to both paths. On Manhattan3500 the path of a column holds 12 % of L with AMD
//   and 4 % with METIS, so this costs a fraction of the full solves of Extraction::solve (which needs no
//   supernodal structure: multi-column solves of H X = E on dense n×k blocks for the distinct variables,
//   keeping only the rows needed; it is the fallback for simplicial factors and the cross-check in the
//   tests). Neither method ever forms the dense inverse, and each distinct variable is solved for once per
//   batch, shared by every query that names it. Memory of forward: Σ over the distinct variables of dim ×
//   (rows on its path) doubles.
//
// Threads: workers take whole column blocks (then whole queries), each with its own workspace (and, for
//   solve, its own linalg::SolveWorkspace). Both methods only read the factor: the workers need no
//   locks. Measured on this 2-core machine, Manhattan3500, all 44 425 pairs (bench/bench_cov.cpp, quiet
//   machine):
//     forward, AMD (CHOLMOD's choice)  138 ms on 1 thread, 72 ms on 2;  forward, METIS  55 ms / 23 ms;
//     solve, AMD  1.80 s on 1 thread, 0.83 s on 2 — and 2.1 s on 2 threads when the cholmod_solve2 calls
//
// A block source (ForwardBlocks in extraction_forward.cpp, SolveBlocks in extraction_solve.cpp) is told
// need(a, b) for every block a query uses, then run(threads), then answers get(a, b) from any thread for
// variables with rows in H (get_block answers the gauge's zero blocks). The
// templates below drive one; each source's file instantiates them for itself, so the hot loops stay in one
// translation unit with the source they call.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <utility>
#include <vector>

#include "core/parallel.hpp"
#include "cov/factor.hpp"

namespace keel::cov::detail {

using Impl = MarginalCovariance::Impl;

// The 2d × 2d joint covariance [Σ_ii Σ_ij; Σ_ji Σ_jj] of a pair of poses of tangent dimension d.
template <int D>
using PairBlock = Eigen::Matrix<double, 2 * D, 2 * D>;

// joint_many() and the pair queries with each extraction method (Impl::extraction picks one).
std::vector<MatX> joint_many_forward(const Impl& I, const std::vector<std::vector<int>>& queries,
                                     unsigned threads);
std::vector<MatX> joint_many_solve(const Impl& I, const std::vector<std::vector<int>>& queries,
                                   unsigned threads);
template <int D>
std::vector<PairBlock<D>> pairs_forward(const Impl& I, const std::vector<std::pair<int, int>>& pairs,
                                        unsigned threads);
template <int D>
std::vector<PairBlock<D>> pairs_solve(const Impl& I, const std::vector<std::pair<int, int>>& pairs,
                                      unsigned threads);
// linear_map_covariances() with each extraction method (the maps already checked).
std::vector<MatX> maps_forward(const Impl& I, const std::vector<LinearMap>& maps,
                               const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                               unsigned threads);
std::vector<MatX> maps_solve(const Impl& I, const std::vector<LinearMap>& maps,
                             const std::vector<std::pair<std::size_t, std::size_t>>& pairs, unsigned threads);

// Runs body(chunk, workspace) for chunks [0, num_chunks) on `threads` workers, each with its own workspace.
template <class Workspace, class Body>
void run_chunks(std::size_t num_chunks, unsigned threads, const Body& body) {
  if (num_chunks == 0) return;
  if (threads == 0) threads = core::default_threads();
  threads = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(num_chunks)));
  std::atomic<std::size_t> next{0};
  core::parallel_for(
      threads,
      [&](std::size_t) {
        Workspace ws;
        for (std::size_t ch = next++; ch < num_chunks; ch = next++) body(ch, ws);
      },
      threads);
}

// Splits consecutive items of the given widths into chunks of at most `limit` (at least one item each).
template <class Width>
std::vector<std::size_t> chunk_starts(std::size_t count, int limit, const Width& width) {
  std::vector<std::size_t> starts{0};
  int w = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const int d = width(k);
    if (w > 0 && w + d > limit) {
      starts.push_back(k);
      w = 0;
    }
    w += d;
  }
  starts.push_back(count);
  return starts;
}

// Σ_ab from a block source into out (column-major, leading dimension ld): zero where a or b is the variable
// the gauge fixes (no rows in H), else the source's block.
template <class Source>
void get_block(const Source& src, const Impl& I, int a, int b, double* out, Eigen::Index ld) {
  if (I.off(a) < 0 || I.off(b) < 0) {
    MapX(out, I.dim(a), I.dim(b), Eigen::OuterStride<>(ld)).setZero();
    return;
  }
  src.get(a, b, out, ld);
}

template <class Source>
std::vector<MatX> joint_many_with(const Impl& I, const std::vector<std::vector<int>>& queries,
                                  unsigned threads) {
  Source src(I);
  for (const auto& q : queries)
    for (std::size_t a = 0; a < q.size(); ++a)
      for (std::size_t b = 0; b <= a; ++b) src.need(q[a], q[b]);
  src.run(threads);
  std::vector<MatX> out(queries.size());
  core::parallel_for(
      queries.size(),
      [&](std::size_t k) {
        const auto& q = queries[k];
        std::vector<int> start(q.size() + 1, 0);
        for (std::size_t a = 0; a < q.size(); ++a) start[a + 1] = start[a] + I.dim(q[a]);
        MatX S(start.back(), start.back());
        // each unordered pair once; the transposed block is copied, so S is exactly symmetric
        for (std::size_t a = 0; a < q.size(); ++a)
          for (std::size_t b = a; b < q.size(); ++b) {
            get_block(src, I, q[a], q[b], &S(start[a], start[b]), S.rows());
            if (b != a)
              S.block(start[b], start[a], I.dim(q[b]), I.dim(q[a])) =
                  S.block(start[a], start[b], I.dim(q[a]), I.dim(q[b])).transpose();
          }
        out[k] = std::move(S);
      },
      threads);
  return out;
}

template <class Source, int D>
std::vector<PairBlock<D>> pairs_with(const Impl& I, const std::vector<std::pair<int, int>>& pairs,
                                     unsigned threads) {
  Source src(I);
  for (const auto& [i, j] : pairs) {
    src.need(i, i);
    src.need(j, j);
    src.need(i, j);
  }
  src.run(threads);
  std::vector<PairBlock<D>> out(pairs.size());
  core::parallel_for(
      pairs.size(),
      [&](std::size_t k) {
        const auto [i, j] = pairs[k];
        PairBlock<D>& S = out[k];
        get_block(src, I, i, i, S.data(), 2 * D);
        get_block(src, I, i, j, S.data() + D * 2 * D, 2 * D);      // block (0, D)
        get_block(src, I, j, j, S.data() + D * 2 * D + D, 2 * D);  // block (D, D)
        S.template block<D, D>(D, 0) = S.template block<D, D>(0, D).transpose();
      },
      threads);
  return out;
}

// K_u Σ K_vᵀ from the blocks Σ_ab of a block source, Σ_st C_us Σ_{a_s b_t} C_vtᵀ (Extraction::solve; the
// forward method forms L⁻¹ P K_uᵀ instead, extraction_forward.cpp).
template <class Source>
std::vector<MatX> maps_with(const Impl& I, const std::vector<LinearMap>& maps,
                            const std::vector<std::pair<std::size_t, std::size_t>>& pairs, unsigned threads) {
  Source src(I);
  for (const auto& [u, v] : pairs)
    for (const int a : maps[u].vars)
      for (const int b : maps[v].vars) src.need(a, b);
  src.run(threads);
  std::vector<MatX> out(pairs.size());
  core::parallel_for(
      pairs.size(),
      [&](std::size_t k) {
        const auto [u, v] = pairs[k];
        const LinearMap& mu = maps[u];
        const LinearMap& mv = maps[v];
        MatX S = MatX::Zero(mu.coefficients.front().rows(), mv.coefficients.front().rows());
        MatX block;
        for (std::size_t s = 0; s < mu.vars.size(); ++s)
          for (std::size_t t = 0; t < mv.vars.size(); ++t) {
            block.resize(I.dim(mu.vars[s]), I.dim(mv.vars[t]));
            get_block(src, I, mu.vars[s], mv.vars[t], block.data(), block.rows());
            S.noalias() += mu.coefficients[s] * block * mv.coefficients[t].transpose();
          }
        if (u == v) S = (0.5 * (S + S.transpose())).eval();
        out[k] = std::move(S);
      },
      threads);
  return out;
}

}  // namespace keel::cov::detail
