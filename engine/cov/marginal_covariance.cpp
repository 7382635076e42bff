// Marginal covariances from a CHOLMOD factorization of H (L Lᵀ = P H Pᵀ, supernodal by default).
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
//   supernodal structure: cholmod_solve2 of H X = E on dense n×k blocks for the distinct variables, keeping
//   only the rows needed; it is the fallback for simplicial factors and the cross-check in the tests).
//   Neither method ever forms the dense inverse, and each distinct variable is solved for once per batch,
//   shared by every query that names it. Memory of forward: Σ over the distinct variables of dim × (rows on
//   its path) doubles.
//
// Threads: workers take whole column blocks (then whole queries), each with its own workspace (and, for
//   solve, its own cholmod_common and dense B/X/Y/E). Both methods only read the factor: the workers need no
//   locks. Measured on this 2-core machine, Manhattan3500, all 44 425 pairs (bench/bench_cov.cpp, quiet
//   machine):
//     forward, AMD (CHOLMOD's choice)  138 ms on 1 thread, 72 ms on 2;  forward, METIS  55 ms / 23 ms;
//     solve, AMD  1.80 s on 1 thread, 0.83 s on 2 — and 2.1 s on 2 threads when the cholmod_solve2 calls
//     were serialized behind one mutex (tried once): parallel solves with per-thread commons win.
//   Results do not depend on the number of threads (the column blocks are fixed before the workers start).
#include "cov/marginal_covariance.hpp"

#include <cholmod.h>

#include <Eigen/Core>
#include <fmt/format.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>

#include "core/names.hpp"
#include "core/parallel.hpp"

namespace keel::cov {

// ---------------------------------------------------------------------------------------------------------------------
// Options
// ---------------------------------------------------------------------------------------------------------------------

namespace {

constexpr core::NameTable<Ordering, 5> kOrdering{"cov::Ordering",
                                                 {{{Ordering::automatic, "auto"},
                                                   {Ordering::amd, "amd"},
                                                   {Ordering::metis, "metis"},
                                                   {Ordering::nesdis, "nesdis"},
                                                   {Ordering::natural, "natural"}}}};
constexpr core::NameTable<Extraction, 3> kExtraction{
    "cov::Extraction",
    {{{Extraction::automatic, "auto"}, {Extraction::forward, "forward"}, {Extraction::solve, "solve"}}}};

}  // namespace

std::string_view to_string(Ordering o) { return kOrdering.name(o); }

Ordering ordering_from_string(std::string_view s) { return kOrdering.parse(s); }

std::string_view to_string(Extraction e) { return kExtraction.name(e); }

Extraction extraction_from_string(std::string_view s) { return kExtraction.parse(s); }

void CovarianceOptions::validate() const {
  if (block_columns < 1)
    throw std::invalid_argument(
        fmt::format("CovarianceOptions: block_columns must be >= 1 (got {})", block_columns));
  if (extraction == Extraction::forward && !supernodal)
    throw std::invalid_argument(
        "CovarianceOptions: extraction 'forward' needs a supernodal factorization "
        "(supernodal = true)");
}

namespace {

using MapX = Eigen::Map<MatX, 0, Eigen::OuterStride<>>;
using CMapX = Eigen::Map<const MatX, 0, Eigen::OuterStride<>>;

const char* cholmod_ordering_name(int ordering) {
  switch (ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_GIVEN:
      return "given";
    case CHOLMOD_AMD:
      return "amd";
    case CHOLMOD_METIS:
      return "metis";
    case CHOLMOD_NESDIS:
      return "nesdis";
    case CHOLMOD_COLAMD:
      return "colamd";
    case CHOLMOD_POSTORDERED:
      return "postordered";
  }
  return "unknown";
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A cholmod_common that starts silent and is finished on destruction.
struct Common {
  cholmod_common c;
  Common() {
    cholmod_start(&c);
    c.print = 0;  // errors come back through status checks, never printed by CHOLMOD
  }
  ~Common() { cholmod_finish(&c); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
};

}  // namespace

// ---------------------------------------------------------------------------------------------------------------------
// Impl
// ---------------------------------------------------------------------------------------------------------------------

struct MarginalCovariance::Impl {
  int num_poses = 0;
  int num_landmarks = 0;
  int pose_dof = 3;
  int landmark_dof = 2;
  int size = 0;
  std::vector<int> offset;
  CovarianceOptions options;
  Extraction extraction = Extraction::solve;  // resolved (never automatic)
  FactorSummary summary;
  Common common;  // analysis / factorization; owns L
  cholmod_factor* L = nullptr;
  // Supernodal structure (Extraction::forward): the factor's arrays and the supernodal elimination tree.
  int nsuper = 0;
  const int* super = nullptr;  // columns super[s] … super[s+1]−1 of supernode s
  const int* pi = nullptr;     // row indices of s: ls[pi[s] … pi[s+1])
  const int* px = nullptr;     // values of s: lx[px[s] …], nsrow × nscol column-major
  const int* ls = nullptr;
  const double* lx = nullptr;
  std::vector<int> snode_of_col;  // permuted column → supernode
  std::vector<int> parent;        // supernode → parent supernode (−1 at a root); parent[s] > s
  std::vector<int> iperm;         // row of H → permuted column (L L ᵀ = P H Pᵀ)

  ~Impl() {
    if (L) cholmod_free_factor(&L, &common.c);
  }

  int num_variables() const { return num_poses + num_landmarks; }
  int dim(int v) const { return v < num_poses ? pose_dof : landmark_dof; }
  int off(int v) const { return offset[static_cast<std::size_t>(v)]; }
  int nscol(int s) const { return super[s + 1] - super[s]; }
  int nsrow(int s) const { return pi[s + 1] - pi[s]; }
  void check(int v) const {
    if (v < 0 || v >= num_variables())
      throw std::out_of_range(
          fmt::format("MarginalCovariance: variable {} is not in [0, {}) ({} poses, {} landmarks)", v,
                      num_variables(), num_poses, num_landmarks));
  }
  int variable_of_row(int r) const {  // error messages only
    int best = -1;
    for (int v = 0; v < num_variables(); ++v)
      if (off(v) >= 0 && off(v) <= r) best = v;
    return best;
  }
  std::string variable_name(int v) const {
    return v < num_poses ? fmt::format("pose {}", v) : fmt::format("landmark {}", v - num_poses);
  }
};

MarginalCovariance::MarginalCovariance(const SparseInformation& H, const CovarianceOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  H.validate();
  if (H.size == 0)
    throw std::invalid_argument("MarginalCovariance: H is empty (nothing left after the gauge)");
  Impl& I = *impl_;
  I.num_poses = H.num_poses;
  I.num_landmarks = H.num_landmarks;
  I.pose_dof = H.pose_dof;
  I.landmark_dof = H.landmark_dof;
  I.size = H.size;
  I.offset = H.offset;
  I.options = options;
  cholmod_common* c = &I.common.c;

  // H as a CHOLMOD matrix (stype = +1: the upper triangle is used). The arrays are copied, H stays untouched.
  cholmod_sparse* A =
      cholmod_allocate_sparse(static_cast<std::size_t>(H.size), static_cast<std::size_t>(H.size),
                              H.nonzeros(), /*sorted=*/1, /*packed=*/1, /*stype=*/1, CHOLMOD_REAL, c);
  if (!A)
    throw std::runtime_error(
        fmt::format("MarginalCovariance: CHOLMOD could not allocate H (status {})", c->status));
  std::copy(H.col_start.begin(), H.col_start.end(), static_cast<int*>(A->p));
  std::copy(H.row_index.begin(), H.row_index.end(), static_cast<int*>(A->i));
  std::copy(H.value.begin(), H.value.end(), static_cast<double*>(A->x));

  c->supernodal = options.supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  switch (options.ordering) {
    case Ordering::automatic:
      c->nmethods = 0;
      break;  // CHOLMOD default: AMD, METIS too if AMD fills badly
    case Ordering::amd:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_AMD;
      break;
    case Ordering::metis:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_METIS;
      break;
    case Ordering::nesdis:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_NESDIS;
      break;
    case Ordering::natural:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_NATURAL;
      c->postorder = 0;
      break;
  }

  auto t0 = std::chrono::steady_clock::now();
  I.L = cholmod_analyze(A, c);
  I.summary.analyze_time_s = seconds_since(t0);
  if (!I.L) {
    cholmod_free_sparse(&A, c);
    throw std::runtime_error(
        fmt::format("MarginalCovariance: CHOLMOD analysis failed (status {})", c->status));
  }
  t0 = std::chrono::steady_clock::now();
  const int ok = cholmod_factorize(A, I.L, c);
  I.summary.factorize_time_s = seconds_since(t0);
  cholmod_free_sparse(&A, c);
  if (!ok || c->status == CHOLMOD_NOT_POSDEF || I.L->minor < I.L->n) {
    std::string msg = "MarginalCovariance: the information matrix is not positive definite";
    if (I.L->minor < I.L->n) {
      const int row = static_cast<int*>(I.L->Perm)[I.L->minor];
      msg += fmt::format(
          " (the factorization broke down at row {}, {}): is every variable constrained and the graph "
          "connected to the gauge pose?",
          row, I.variable_name(I.variable_of_row(row)));
    } else {
      msg += fmt::format(" (CHOLMOD status {})", c->status);
    }
    throw std::runtime_error(msg);
  }

  FactorSummary& s = I.summary;
  s.ordering = cholmod_ordering_name(I.L->ordering);
  s.supernodal = I.L->is_super != 0;
  s.size = H.size;
  s.nnz_h = H.nonzeros();
  s.nnz_l = c->lnz;
  s.factor_flops = c->fl;
  s.num_supernodes = s.supernodal ? I.L->nsuper : 0;
  s.l_storage = s.supernodal ? I.L->xsize : I.L->nzmax;

  I.extraction = options.extraction == Extraction::automatic
                     ? (s.supernodal ? Extraction::forward : Extraction::solve)
                     : options.extraction;
  if (I.extraction == Extraction::forward && !s.supernodal)
    throw std::runtime_error(
        "MarginalCovariance: CHOLMOD returned a simplicial factor; extraction 'forward' needs a "
        "supernodal one");
  s.extraction = std::string(to_string(I.extraction));

  const int n = H.size;
  I.iperm.assign(static_cast<std::size_t>(n), 0);
  const int* perm = static_cast<const int*>(I.L->Perm);
  for (int k = 0; k < n; ++k) I.iperm[static_cast<std::size_t>(perm[k])] = k;
  if (s.supernodal) {
    I.nsuper = static_cast<int>(I.L->nsuper);
    I.super = static_cast<const int*>(I.L->super);
    I.pi = static_cast<const int*>(I.L->pi);
    I.px = static_cast<const int*>(I.L->px);
    I.ls = static_cast<const int*>(I.L->s);
    I.lx = static_cast<const double*>(I.L->x);
    I.snode_of_col.assign(static_cast<std::size_t>(n), 0);
    I.parent.assign(static_cast<std::size_t>(I.nsuper), -1);
    for (int sn = 0; sn < I.nsuper; ++sn)
      for (int j = I.super[sn]; j < I.super[sn + 1]; ++j) I.snode_of_col[static_cast<std::size_t>(j)] = sn;
    for (int sn = 0; sn < I.nsuper; ++sn)
      if (I.nsrow(sn) > I.nscol(sn)) {
        // The first row below the diagonal block names the parent; every other row lies in an ancestor.
        const int p = I.snode_of_col[static_cast<std::size_t>(I.ls[I.pi[sn] + I.nscol(sn)])];
        if (p <= sn)
          throw std::logic_error("MarginalCovariance: supernodal tree is not topologically ordered");
        I.parent[static_cast<std::size_t>(sn)] = p;
      }
    // share of L on the path of each column: path[s] = own + path[parent], parents come later
    std::vector<double> path(static_cast<std::size_t>(I.nsuper), 0.0);
    double total = 0.0;
    for (int sn = I.nsuper - 1; sn >= 0; --sn) {
      const double own = static_cast<double>(I.nscol(sn)) * I.nsrow(sn);
      total += own;
      const int p = I.parent[static_cast<std::size_t>(sn)];
      path[static_cast<std::size_t>(sn)] = own + (p >= 0 ? path[static_cast<std::size_t>(p)] : 0.0);
    }
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
      sum += path[static_cast<std::size_t>(I.snode_of_col[static_cast<std::size_t>(j)])];
    s.mean_path_fraction = sum / (static_cast<double>(n) * total);
  }
}

MarginalCovariance::~MarginalCovariance() = default;
MarginalCovariance::MarginalCovariance(MarginalCovariance&&) noexcept = default;
MarginalCovariance& MarginalCovariance::operator=(MarginalCovariance&&) noexcept = default;

const FactorSummary& MarginalCovariance::summary() const { return impl_->summary; }
int MarginalCovariance::num_poses() const { return impl_->num_poses; }
int MarginalCovariance::num_landmarks() const { return impl_->num_landmarks; }
int MarginalCovariance::num_variables() const { return impl_->num_variables(); }
int MarginalCovariance::variable_dim(int var) const {
  impl_->check(var);
  return impl_->dim(var);
}

// ---------------------------------------------------------------------------------------------------------------------
// Block sources: need(a, b) for every block a query uses, run(threads), then get(a, b) (thread-safe).
// ---------------------------------------------------------------------------------------------------------------------

namespace {

using Impl = MarginalCovariance::Impl;

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

// Extraction::solve — H X = E for the columns of the distinct variables (cholmod_solve2, dense multi-column
// blocks), keeping for each column variable c the rows of the variables r ≤ c paired with it.
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

  void get(int a, int b, double* out, Eigen::Index ld) const {
    const int da = I_.dim(a), db = I_.dim(b);
    MapX dst(out, da, db, Eigen::OuterStride<>(ld));
    if (I_.off(a) < 0 || I_.off(b) < 0) {
      dst.setZero();
      return;
    }
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
  // Per-thread CHOLMOD state: its own common and dense workspaces (reused across chunks by cholmod_solve2).
  struct Workspace {
    Common common;
    cholmod_dense *B = nullptr, *X = nullptr, *Y = nullptr, *E = nullptr;
    Workspace() = default;
    ~Workspace() {
      for (cholmod_dense** d : {&B, &X, &Y, &E})
        if (*d) cholmod_free_dense(d, &common.c);
    }
    Workspace(const Workspace&) = delete;
    Workspace& operator=(const Workspace&) = delete;
  };

  void solve_chunk(Workspace& w, std::size_t k0, std::size_t k1) {
    cholmod_common* c = &w.common.c;
    const std::size_t n = static_cast<std::size_t>(I_.size);
    int ncols = 0;
    for (std::size_t k = k0; k < k1; ++k) ncols += I_.dim(cols_[k]);
    if (!w.B || w.B->ncol != static_cast<std::size_t>(ncols)) {
      if (w.B) cholmod_free_dense(&w.B, c);
      w.B = cholmod_zeros(n, static_cast<std::size_t>(ncols), CHOLMOD_REAL, c);
      if (!w.B)
        throw std::runtime_error("MarginalCovariance: CHOLMOD could not allocate the right-hand sides");
    } else {
      std::fill_n(static_cast<double*>(w.B->x), n * static_cast<std::size_t>(ncols), 0.0);
    }
    double* b = static_cast<double*>(w.B->x);
    int col = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      const int v = cols_[k], o = I_.off(v);
      for (int d = 0; d < I_.dim(v); ++d, ++col)
        b[static_cast<std::size_t>(col) * n + static_cast<std::size_t>(o + d)] = 1.0;
    }
    if (!cholmod_solve2(CHOLMOD_A, I_.L, w.B, nullptr, &w.X, nullptr, &w.Y, &w.E, c))
      throw std::runtime_error(
          fmt::format("MarginalCovariance: CHOLMOD solve failed (status {})", c->status));
    const CMapX X(static_cast<const double*>(w.X->x), static_cast<Eigen::Index>(n), ncols,
                  Eigen::OuterStride<>(static_cast<Eigen::Index>(w.X->d)));
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
            src.get(q[a], q[b], &S(start[a], start[b]), S.rows());
            if (b != a)
              S.block(start[b], start[a], I.dim(q[b]), I.dim(q[a])) =
                  S.block(start[a], start[b], I.dim(q[a]), I.dim(q[b])).transpose();
          }
        out[k] = std::move(S);
      },
      threads);
  return out;
}

template <class Source>
std::vector<Mat6> pairs_with(const Impl& I, const std::vector<std::pair<int, int>>& pairs, unsigned threads) {
  Source src(I);
  for (const auto& [i, j] : pairs) {
    src.need(i, i);
    src.need(j, j);
    src.need(i, j);
  }
  src.run(threads);
  std::vector<Mat6> out(pairs.size());
  core::parallel_for(
      pairs.size(),
      [&](std::size_t k) {
        const auto [i, j] = pairs[k];
        Mat6& S = out[k];
        src.get(i, i, S.data(), 6);
        src.get(i, j, S.data() + 18, 6);  // block (0, 3)
        src.get(j, j, S.data() + 21, 6);  // block (3, 3)
        S.block<3, 3>(3, 0) = S.block<3, 3>(0, 3).transpose();
      },
      threads);
  return out;
}

}  // namespace

std::vector<MatX> MarginalCovariance::joint_many(const std::vector<std::vector<int>>& queries,
                                                 unsigned threads) const {
  const Impl& I = *impl_;
  for (const auto& q : queries)
    for (int v : q) I.check(v);
  return I.extraction == Extraction::forward ? joint_many_with<ForwardBlocks>(I, queries, threads)
                                             : joint_many_with<SolveBlocks>(I, queries, threads);
}

MatX MarginalCovariance::joint(const std::vector<int>& vars) const { return joint_many({vars}, 1).front(); }

MatX MarginalCovariance::marginal(int var) const { return joint({var}); }

std::vector<Mat6> pair_marginals_2d(const MarginalCovariance& cov,
                                    const std::vector<std::pair<int, int>>& pairs, unsigned threads) {
  const Impl& I = *cov.impl_;
  if (I.pose_dof != 3)
    throw std::invalid_argument(
        fmt::format("pair_marginals_2d: the poses are not SE(2) (pose DoF {})", I.pose_dof));
  for (const auto& [i, j] : pairs)
    for (int v : {i, j})
      if (v < 0 || v >= I.num_poses)
        throw std::invalid_argument(
            fmt::format("pair_marginals_2d: {} is not a pose id (0 … {})", v, I.num_poses - 1));
  return I.extraction == Extraction::forward ? pairs_with<ForwardBlocks>(I, pairs, threads)
                                             : pairs_with<SolveBlocks>(I, pairs, threads);
}

}  // namespace keel::cov
