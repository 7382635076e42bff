// A densest-subgraph selector beside PCM's maximum clique: the relaxation of Lusk, Fathian and How, "CLIPPER:
// A Graph-Theoretic Framework for Robust Data Association" (ICRA 2021), written here from the paper.
//
// With M the n x n affinity matrix of the candidates (M_ii = 1, M_uv in [0, 1] on consistent pairs, 0 on
// inconsistent ones) and C̄ the indicator of inconsistent pairs (C̄_uv = 1 iff u != v are not adjacent in the
// consistency graph), the selection problem
//     max_u  uᵀ M u / uᵀ u   over u in {0, 1}ⁿ with u_i u_j = 0 whenever C̄_ij = 1
// is relaxed to the penalised continuous problem
//     max_u  F_d(u) = uᵀ (M − d C̄) u   subject to ‖u‖₂ = 1, u >= 0,
// and solved by projected gradient ascent at fixed d (CLIPPER's steps u + β^k (M − dC̄)u, or the paper's
// long step: DensestOptions::line_search), raising d until no two vertices of the support of u are
// inconsistent (the homotopy of the paper; vertices that only shrink as d grows are cut to their limit, zero:
// DensestOptions::crawl_tolerance). For binary M (the adjacency plus the identity) the objective of a clique
// S with u uniform on S is |S|, so the problem is the maximum clique and the relaxation's local maxima are
// maximal cliques — not necessarily maximum ones: the result is a heuristic, and this selector reports what
// it returns as it is (raw support, its violations of consistency) next to a repaired clique.
//
// Rounding (the paper's density heuristic): the raw selection is the round(F_d(u)) largest entries of u.
// Repair: while the raw selection holds an inconsistent pair, drop the vertex with the most non-neighbours in
// it (ties: the smaller u_i, then the larger id); then extend to a maximal clique by adding the candidate
// adjacent to all of it with the largest u_i (ties: the lower id). Deterministic: u starts from one power
// step of M on the all-ones vector.
#pragma once

#include <vector>

#include "pcm/clique.hpp"

namespace keel::pcm {

struct DensestOptions {
  int max_outer = 1000;  // homotopy steps (raising d)
  int max_inner = 200;   // projected-gradient steps at fixed d
  double beta = 0.25;    // backtracking factor of the step length
  double tol_u = 1e-8;   // inner stop: ‖u⁺ − u‖
  double tol_f = 1e-9;   // inner stop: |F(u⁺) − F(u)|
  double eps = 1e-9;     // support threshold on u and on the constraint activity (C̄u)_i
  // How M and the adjacency are stored for the products Mu and C̄u: `automatic` picks compressed sparse rows
  // when the graph's edge density is below kSparseDensity, else dense n x n matrices. Both give the same
  // iterates up to the order of floating-point sums (densest_test.cpp checks the answers agree).
  enum class Storage { automatic, dense, sparse };
  Storage storage = Storage::automatic;
  // How far each homotopy step raises d: `minimum`, the smallest ratio (Mu)_i / (C̄u)_i over the active
  // constraints (one constraint starts to bind), or `mean`, their mean (the CLIPPER paper's schedule: larger
  // steps, fewer outer iterations, and on bench_clique's family a maximum clique less often).
  enum class PenaltyStep { minimum, mean };
  PenaltyStep penalty_step = PenaltyStep::minimum;
  // The step lengths the line search tries along the projected gradient g = (M − dC̄)u − F u (F = F_d(u),
  // ‖u‖ = 1), each shortened by β until F_d does not decrease: `clipper` (the default), the steps of
  // CLIPPER's implementation, u + β^k (M − dC̄)u along the unprojected gradient from k = 0, which after the
  // projection onto u >= 0 and the sphere are the steps β^k / (1 + β^k F) along g (a k with 1 + β^k F <= 0 is
  // skipped); or `long_step`, from (1/β)³/‖g‖ (the paper's long step, the default before the acceptance rule
  // of docs/DESIGN.md "The densest selector's default" adopted `clipper`). Near a maximum ‖g‖ is small, so
  // the long step overshoots and backtracks at every iteration; CLIPPER's first try is a power step on I + M
  // − dC̄. Measured on bench_clique's family (143 graphs, same process, without the crawl cut below):
  // `clipper` takes 3.6× fewer products on the 1D worlds and planted cliques (geometric mean; from 0.3× to
  // 25×) and about as many on the small City10000 and sphere2500 candidate sets (0.23× to 29×); the same
  // repaired selection on 134 graphs, another of the same size on 8 and a larger one on 1.
  enum class LineSearch { long_step, clipper };
  LineSearch line_search = LineSearch::clipper;
  // The crawl cut. A pair (or group) of mutually inconsistent vertices, each adjacent to the rest of the
  // support, sits at an interior stationary point of F_d: for a symmetric pair a, b, (M − dC̄)u = F u gives
  // u_a = u_b = (Mu)_a / (d + F). Raising d only shrinks them as 1/(d + F); they reach the support threshold
  // eps after ~30 doublings of d (the `minimum` penalty step nearly doubles d there), at about 50 products
  // each — 95 % of the work on City10000's candidate sets (city10000_d73: 26 outer iterations and 1,358
  // products, of which 38 before the pair settled). When the active vertices (in the support, with an
  // inconsistent partner in it) are the same after two consecutive outer iterations and u_i (d + F) moved by
  // less than this fraction for each of them, they are set to their limit, zero, u is renormalised and the
  // homotopy goes on from there (it has converged if the support is then consistent). 0 turns it off.
  // Measured on bench_clique's family (143 graphs, `clipper` steps): the same repaired selection on all 143
  // with the cut at 0.05, 0.1 or 0.25 (and with u_i d in place of u_i (d + F) at 0.1), 6.1× fewer products
  // in all (118,711 → 19,538 at 0.1).
  double crawl_tolerance = 0.1;
  // The homotopy stops when this many outer iterations in a row moved u by less than tol_u each (0: never):
  // it has stalled, with inconsistent pairs left in the support that raising d no longer removes (d grows to
  // ~1e11 over max_outer steps while the line search finds only steps at the rounding of F). The answer is
  // then the rounding and repair of that u, as after max_outer. Measured on bench_clique's family (143
  // graphs): 23 stall, all of them stopped within 24–40 outer iterations instead of 1,000, with the same raw
  // and repaired selections on every graph (world1d_m500_w2: 1.2 s → 67 ms; City10000 candidate sets
  // 14–75 ms → 0.5–1.6 ms).
  int max_stalled_outer = 3;
  // The options of the default before the crawl cut and `clipper` steps (kept for the acceptance rule's
  // paired comparison, bench/densest_acceptance.cpp).
  static DensestOptions before_acceptance_rule() {
    DensestOptions o;
    o.line_search = LineSearch::long_step;
    o.crawl_tolerance = 0.0;
    return o;
  }
  // Throws std::invalid_argument naming the violated constraint (counts >= 1, max_stalled_outer >= 0, beta in
  // (0, 1), tolerances > 0, crawl_tolerance in [0, 1)).
  void validate() const;
};

// The edge density 2|E| / (n(n − 1)) below which Storage::automatic chooses sparse rows. With binary
// affinities both storages now take Au from byte columns where those cost less, and on bench_clique's family
// they run within about 10 % of each other (one process, forcing each storage: world1d_m2000_w1
// 278 ms sparse against 258 dense, world1d_m1000_w0 73 against 65, planted_n2000_k40_p20 25 against 27,
// planted_n1000_k20_p5 13 against 16, city10000_d00 0.69 against 0.71). So the threshold no longer decides
// the speed but the order in which Au is summed (and the memory: the rows hold 2|E| ints). It stays where
// it was because moving it changes that order, and with it answers at rounding level, on the graphs it moves:
// on G(2000, 0.5) with a planted 20 (ext_clique_scale) the two orders round to different raw selections.
inline constexpr double kSparseDensity = 0.3;

struct DensestResult {
  std::vector<int> raw;        // the rounded selection, ascending (may hold inconsistent pairs)
  long long violations = 0;    // inconsistent pairs in `raw`
  std::vector<int> selection;  // `raw` repaired to a maximal clique of the consistency graph, ascending
  double objective = 0;        // F_d(u) at the end (≈ |raw| for binary M when the support is a clique)
  double penalty = 0;          // the final d
  int outer_iterations = 0;
  long long inner_iterations = 0;
  long long products = 0;  // trial points of the line search, each one product with A (and M)
  bool converged = false;  // the support of u became consistent before max_outer
  bool stalled = false;    // stopped by max_stalled_outer (not converged)
  int crawl_cuts = 0;      // times the crawl cut zeroed vertices (DensestOptions::crawl_tolerance)
  bool sparse = false;     // the products used compressed sparse rows (DensestOptions::storage)
  double time_s = 0;
};

// Binary affinities: M = adjacency + I, so the objective counts the selected clique's size.
[[nodiscard]] DensestResult densest_subgraph(const ConsistencyGraph& g, const DensestOptions& options = {});

// Weighted affinities: `affinity` is n x n row-major, symmetric, finite, in [0, 1] off the diagonal (the
// diagonal is taken as 1 and entries on inconsistent pairs are ignored). Throws std::invalid_argument naming
// the entry that breaks this, or a size that is not n².
[[nodiscard]] DensestResult densest_subgraph(const ConsistencyGraph& g, const std::vector<double>& affinity,
                                             const DensestOptions& options = {});

}  // namespace keel::pcm
