#include "pcm/densest.hpp"

#include "pcm/densest_detail.hpp"

#include <fmt/format.h>

#include <Eigen/Core>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <bit>
#include <cstdint>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace keel::pcm {

void DensestOptions::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("DensestOptions: " + what); };
  if (max_outer < 1) fail(fmt::format("max_outer must be >= 1 (got {})", max_outer));
  if (max_inner < 1) fail(fmt::format("max_inner must be >= 1 (got {})", max_inner));
  if (max_stalled_outer < 0) fail(fmt::format("max_stalled_outer must be >= 0 (got {})", max_stalled_outer));
  if (!(beta > 0.0 && beta < 1.0)) fail(fmt::format("beta must be in (0, 1) (got {:g})", beta));
  if (!(crawl_tolerance >= 0.0 && crawl_tolerance < 1.0))
    fail(fmt::format("crawl_tolerance must be in [0, 1) (got {:g})", crawl_tolerance));
  if (!(tol_u > 0.0) || !(tol_f > 0.0) || !(eps > 0.0))
    fail(fmt::format("tol_u, tol_f and eps must be > 0 (got {:g}, {:g}, {:g})", tol_u, tol_f, eps));
}

namespace detail {

namespace {

// kByteMask[b][k]: all ones where bit k of b is set, else zero; `u_j & mask` is u_j or +0.0 without a branch.
struct ByteMasks {
  alignas(64) std::uint64_t m[256][8];
};
constexpr ByteMasks make_byte_masks() {
  ByteMasks t{};
  for (int b = 0; b < 256; ++b)
    for (int k = 0; k < 8; ++k) t.m[b][k] = ((b >> k) & 1) ? ~std::uint64_t{0} : std::uint64_t{0};
  return t;
}
constexpr ByteMasks kByteMask = make_byte_masks();

}  // namespace

ByteAdjacency::ByteAdjacency(const ConsistencyGraph& g) : n_(g.size()), chunks_((g.size() + 7) / 8) {
  bytes_.assign(static_cast<std::size_t>(chunks_) * static_cast<std::size_t>(n_), 0);
  for (int j = 0; j < n_; ++j) {
    const std::uint64_t* r = g.row(j);
    for (int c = 0; c < chunks_; ++c)
      bytes_[static_cast<std::size_t>(c) * n_ + j] = static_cast<std::uint8_t>(r[c / 8] >> (8 * (c % 8)));
  }
}

int ByteAdjacency::eigen_block(int n) {
  // GeneralMatrixVector.h (Eigen 3.4), column-major kernel: block_cols = cols < 128 ? cols
  // : (lhsStride * sizeof(double) < 32000 ? 16 : 4).
  if (n < 128) return std::max(n, 1);
  return static_cast<long long>(n) * 8 < 32000 ? 16 : 4;
}

namespace {

// The sums of product() for chunks c0 … c0 + G − 1 (8G rows), G independent accumulator sets so that the
// additions of one row's sum do not wait on each other's latency: total[8g + r] for row 8(c0 + g) + r.
// Generic version: u_j & mask picks u_j or +0.0 per row (adding +0.0 leaves a sum unchanged).
template <int G>
[[gnu::always_inline]] inline void chunk_sums(const std::uint8_t* bytes, std::size_t n, int c0,
                                              const double* u, const int* columns, const int* segment_end,
                                              std::size_t segments, double* total) {
  for (int r = 0; r < 8 * G; ++r) total[r] = 0.0;
  int k = 0;
  for (std::size_t s = 0; s < segments; ++s) {
    double part[8 * G] = {};
    for (const int end = segment_end[s]; k < end; ++k) {
      const int j = columns[k];
      const std::uint64_t uj = std::bit_cast<std::uint64_t>(u[j]);
      for (int g = 0; g < G; ++g) {
        const std::uint64_t* mask = kByteMask.m[bytes[(static_cast<std::size_t>(c0) + g) * n + j]];
        for (int r = 0; r < 8; ++r) part[8 * g + r] += std::bit_cast<double>(uj & mask[r]);
      }
    }
    for (int r = 0; r < 8 * G; ++r) total[r] += part[r];
  }
}

#if defined(__x86_64__) && (defined(__clang__) || defined(__GNUC__))
#define KEEL_DENSEST_X86 1
// AVX2: the generic sums compiled for 256-bit vectors, four chunks at a time.
__attribute__((target("avx2"))) void chunk_sums_avx2(const std::uint8_t* bytes, std::size_t n, int c0,
                                                     const double* u, const int* columns,
                                                     const int* segment_end, std::size_t segments,
                                                     double* total) {
  chunk_sums<4>(bytes, n, c0, u, columns, segment_end, segments, total);
}

// AVX-512 (F, and DQ for 8-bit mask loads), eight chunks at a time: a masked add leaves the lanes of unset
// bits as they are, the same sums as adding +0.0 there. Measured on this machine kind: about 0.45 ns per
// (chunk, column) step against 0.75 (AVX2) and 1.5 (generic); loading the masks from memory rather than
// moving them from general registers took world1d_m2000_w0 from 0.52 to 0.38 s.
__attribute__((target("avx512f,avx512dq"))) void chunk_sums_avx512(const std::uint8_t* bytes, std::size_t n,
                                                                   int c0, const double* u,
                                                                   const int* columns, const int* segment_end,
                                                                   std::size_t segments, double* total) {
  constexpr int G = 8;
  __m512d sum[G];
  for (int g = 0; g < G; ++g) sum[g] = _mm512_setzero_pd();
  const std::uint8_t* row[G];
  for (int g = 0; g < G; ++g) row[g] = bytes + (static_cast<std::size_t>(c0) + g) * n;
  int k = 0;
  for (std::size_t s = 0; s < segments; ++s) {
    __m512d part[G];
    for (int g = 0; g < G; ++g) part[g] = _mm512_setzero_pd();
    for (const int end = segment_end[s]; k < end; ++k) {
      const int j = columns[k];
      const __m512d uj = _mm512_set1_pd(u[j]);
      for (int g = 0; g < G; ++g)
        part[g] = _mm512_mask_add_pd(part[g], _cvtu32_mask8(row[g][j]), part[g], uj);
    }
    for (int g = 0; g < G; ++g) sum[g] = _mm512_add_pd(sum[g], part[g]);
  }
  for (int g = 0; g < G; ++g) _mm512_storeu_pd(total + 8 * g, sum[g]);
}
#endif

}  // namespace

bool ByteAdjacency::available(Kernel kernel) {
  switch (kernel) {
    case Kernel::automatic:
    case Kernel::generic:
      return true;
#ifdef KEEL_DENSEST_X86
    case Kernel::avx2:
      return __builtin_cpu_supports("avx2");
    case Kernel::avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
#else
    case Kernel::avx2:
    case Kernel::avx512:
      return false;
#endif
  }
  return false;
}

ByteAdjacency::Kernel ByteAdjacency::best() {
  static const Kernel kernel = available(Kernel::avx512) ? Kernel::avx512
                               : available(Kernel::avx2) ? Kernel::avx2
                                                         : Kernel::generic;
  return kernel;
}

void ByteAdjacency::product(const double* u, std::span<const int> columns, int block, double* out,
                            Kernel kernel) const {
  if (block < 1) throw std::invalid_argument(fmt::format("ByteAdjacency::product: block {} < 1", block));
  if (kernel == Kernel::automatic) {
    kernel = best();
  } else if (!available(kernel)) {
    throw std::invalid_argument(
        "ByteAdjacency::product: this CPU lacks the instructions of the kernel asked for");
  }
  // Where each block's run of the (ascending) columns ends; one division per block, not per column.
  segment_.clear();
  if (!columns.empty()) {
    long long block_end = (static_cast<long long>(columns[0]) / block + 1) * block;
    for (std::size_t k = 1; k < columns.size(); ++k)
      if (columns[k] >= block_end) {
        segment_.push_back(static_cast<int>(k));
        block_end = (static_cast<long long>(columns[k]) / block + 1) * block;
      }
    segment_.push_back(static_cast<int>(columns.size()));
  }
  const auto n = static_cast<std::size_t>(n_);
  const int* cols = columns.data();
  const int* ends = segment_.data();
  const std::size_t segments = segment_.size();
  double total[64];
  auto store = [&](int c0, int chunks) {
    const int rows = std::min(8 * chunks, n_ - 8 * c0);
    std::copy(total, total + rows, out + 8 * c0);
  };
  // The widest kernel over as many chunks as it takes at a time, narrower ones on the rest.
  int c = 0;
#ifdef KEEL_DENSEST_X86
  if (kernel == Kernel::avx512)
    for (; c + 8 <= chunks_; c += 8) {
      chunk_sums_avx512(bytes_.data(), n, c, u, cols, ends, segments, total);
      store(c, 8);
    }
  if (kernel == Kernel::avx512 || kernel == Kernel::avx2)
    for (; c + 4 <= chunks_; c += 4) {
      chunk_sums_avx2(bytes_.data(), n, c, u, cols, ends, segments, total);
      store(c, 4);
    }
#endif
  for (; c + 2 <= chunks_; c += 2) {
    chunk_sums<2>(bytes_.data(), n, c, u, cols, ends, segments, total);
    store(c, 2);
  }
  for (; c < chunks_; ++c) {
    chunk_sums<1>(bytes_.data(), n, c, u, cols, ends, segments, total);
    store(c, 1);
  }
}

}  // namespace detail

namespace {

using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

// The data of F_d: the 0/1 adjacency A of the consistency graph and, for weighted affinities, M (already zero
// on inconsistent pairs, 1 on the diagonal). Binary affinities use M = A + I without storing it. C̄ = 11ᵀ − A
// − I, so C̄u = (Σu)·1 − Au − u needs no matrix of its own.
//
// Two storages. Dense: A as byte columns (detail::ByteAdjacency) and, for weighted affinities, M as an n x n
// matrix; the products cost one pass over the columns in the support of u (after the first steps the
// projection onto u >= 0 leaves about the cluster's size of non-zero entries). Au is summed in the order of
// the dense product of doubles this storage replaced — one column at a time when the support is at most n/4,
// else Eigen's blocked matrix-vector product — so the iterates are those of that product bit for bit, at 1/64
// of its memory (n = 2000: 0.5 MB instead of 32 MB, which no longer streams from main memory at every
// product). Sparse (compressed rows of the adjacency; M's off-diagonal weights beside them): Au = Σ_{j in
// supp u} u_j A_{:,j} scattered over the neighbours of the support when they are fewer than half the stored
// entries, else gathered row by row; the cost follows the edges, not n². A is symmetric, so a row is also a
// column. Either way each row of Au is summed over ascending columns from zero — the order of the byte
// columns with one block — so where the byte columns cost less (byte_columns_pay) the sparse storage takes
// its Au from them, built on first use, with the same bits. The two storages differ only in the order of the
// sums.
struct Problem {
  bool binary = true;
  bool sparse = false;
  const ConsistencyGraph* graph = nullptr;
  // A as byte columns: the dense storage's A; the sparse storage builds them on first use (byte_columns_pay).
  mutable detail::ByteAdjacency bytes;
  mutable bool bytes_built = false;
  Mat M;                         // dense storage, weighted
  std::vector<int> start, next;  // sparse storage: the neighbours of i are next[start[i] … start[i+1])
  std::vector<double> weight;    // sparse, weighted: M_{i,next[k]} beside next[k]

  void products(const Vec& u, Vec& Mu, Vec& Cu) const {
    // The support, ascending, without a branch per entry.
    support_.resize(static_cast<std::size_t>(u.size()));
    std::size_t count = 0;
    for (Eigen::Index i = 0; i < u.size(); ++i) {
      support_[count] = static_cast<int>(i);
      count += u(i) != 0.0 ? 1 : 0;
    }
    support_.resize(count);
    const int n = static_cast<int>(u.size());
    if (sparse) {
      std::size_t touched = 0;
      for (const int j : support_) touched += static_cast<std::size_t>(start[j + 1] - start[j]);
      if (byte_columns_pay(n, touched)) {
        Au_.resize(n);
        if (!bytes_built) {
          bytes = detail::ByteAdjacency(*graph);
          bytes_built = true;
        }
        bytes.product(u.data(), support_, n, Au_.data());
      } else {
        sparse_product(u, nullptr, touched, Au_);
      }
      if (binary) {
        Mu = Au_ + u;
      } else {
        sparse_product(u, weight.data(), touched, Mu);
        Mu += u;
      }
    } else {
      Au_.resize(n);
      const bool few = static_cast<Eigen::Index>(support_.size()) * 4 <= n;
      bytes.product(u.data(), support_, few ? n : detail::ByteAdjacency::eigen_block(n), Au_.data());
      if (binary)
        Mu = Au_ + u;
      else
        dense_product(M, u, Mu);  // M is symmetric
    }
    Cu = Vec::Constant(u.size(), u.sum()) - Au_ - u;
  }

 private:
  // The cost of one (8-row chunk, column) step of the byte columns in units of one stored entry visited by
  // the sparse product, per kernel: measured on this machine kind at n = 115 … 5000, densities 0.01–0.3 and
  // supports of 1–100 % of n, about 0.45, 0.75 and 1.5 ns a step (AVX-512, AVX2, generic) against 0.4–1.3 ns
  // an entry (more where the scatter misses the cache). Beyond kSparseByteColumnsMax vertices (32 MB of byte
  // columns) the sparse storage never builds them.
  static constexpr int kSparseByteColumnsMax = 16384;
  static double byte_step_cost() {
    switch (detail::ByteAdjacency::best()) {
      case detail::ByteAdjacency::Kernel::avx512:
        return 0.75;
      case detail::ByteAdjacency::Kernel::avx2:
        return 1.25;
      default:
        return 2.5;
    }
  }
  bool byte_columns_pay(int n, std::size_t touched) const {
    if (n > kSparseByteColumnsMax) return false;
    const double rows = static_cast<double>(2 * touched < next.size() ? touched : next.size()) + n;
    const double chunks = (n + 7) / 8;
    return byte_step_cost() * static_cast<double>(support_.size()) * chunks < rows;
  }
  void dense_product(const Mat& X, const Vec& u, Vec& out) const {
    const auto n = u.size();
    if (static_cast<Eigen::Index>(support_.size()) * 4 > n) {
      out.noalias() = X * u;
      return;
    }
    out.setZero(n);
    for (const int j : support_) out.noalias() += u(j) * X.col(j);
  }
  // out = Xu for X = A (w == nullptr) or X = M − I (w: the weights beside `next`); `touched`: the stored
  // entries in the columns of the support.
  void sparse_product(const Vec& u, const double* w, std::size_t touched, Vec& out) const {
    const int n = static_cast<int>(u.size());
    if (2 * touched < next.size()) {
      out.setZero(n);
      for (const int j : support_) {
        const double uj = u(j);
        for (int k = start[j]; k < start[j + 1]; ++k) out(next[k]) += w ? w[k] * uj : uj;
      }
      return;
    }
    out.resize(n);
    for (int i = 0; i < n; ++i) {
      double sum = 0.0;
      for (int k = start[i]; k < start[i + 1]; ++k) sum += w ? w[k] * u(next[k]) : u(next[k]);
      out(i) = sum;
    }
  }
  mutable std::vector<int> support_;
  mutable Vec Au_;
};

bool use_sparse(const ConsistencyGraph& g, DensestOptions::Storage storage) {
  switch (storage) {
    case DensestOptions::Storage::dense:
      return false;
    case DensestOptions::Storage::sparse:
      return true;
    case DensestOptions::Storage::automatic:
      break;
  }
  const double n = g.size();
  return n < 2 || 2.0 * static_cast<double>(g.num_edges()) < kSparseDensity * n * (n - 1.0);
}

// The adjacency in the chosen storage (weights are filled by the weighted overload).
Problem adjacency(const ConsistencyGraph& g, bool sparse) {
  const int n = g.size();
  Problem p;
  p.sparse = sparse;
  p.graph = &g;
  if (sparse) {
    p.start.assign(static_cast<std::size_t>(n) + 1, 0);
    p.next.reserve(static_cast<std::size_t>(2 * g.num_edges()));
    for (int v = 0; v < n; ++v) {
      const std::uint64_t* r = g.row(v);
      for (int w = 0; w < g.words(); ++w)
        for (std::uint64_t bits = r[w]; bits; bits &= bits - 1)
          p.next.push_back(w * 64 + std::countr_zero(bits));
      p.start[static_cast<std::size_t>(v) + 1] = static_cast<int>(p.next.size());
    }
  } else {
    p.bytes = detail::ByteAdjacency(g);
    p.bytes_built = true;
  }
  return p;
}

// Raw selection, its repair to a maximal clique, and the violation count (see the header).
void round_and_repair(const ConsistencyGraph& g, const Vec& u, double objective, double eps,
                      DensestResult& r) {
  const int n = g.size();
  std::vector<int> support;
  for (int i = 0; i < n; ++i)
    if (u(i) > eps) support.push_back(i);
  std::sort(support.begin(), support.end(), [&](int a, int b) { return u(a) != u(b) ? u(a) > u(b) : a < b; });
  const long long width =
      std::clamp<long long>(std::llround(objective), 1, static_cast<long long>(support.size()));
  r.raw.assign(support.begin(), support.begin() + width);
  std::sort(r.raw.begin(), r.raw.end());
  for (std::size_t a = 0; a < r.raw.size(); ++a)
    for (std::size_t b = a + 1; b < r.raw.size(); ++b) r.violations += g.adjacent(r.raw[a], r.raw[b]) ? 0 : 1;

  std::vector<int> s = r.raw;
  for (;;) {
    int worst = -1, worst_count = 0;
    for (int v : s) {
      int count = 0;
      for (int w : s) count += (w != v && !g.adjacent(v, w)) ? 1 : 0;
      const bool better = count > worst_count || (count == worst_count && count > 0 &&
                                                  (u(v) < u(worst) || (u(v) == u(worst) && v > worst)));
      if (better) worst = v, worst_count = count;
    }
    if (worst_count == 0) break;
    s.erase(std::find(s.begin(), s.end(), worst));
  }
  // Extend to a maximal clique: candidates adjacent to every member.
  std::vector<char> in(static_cast<std::size_t>(n), 0), candidate(static_cast<std::size_t>(n), 1);
  for (int v : s) in[static_cast<std::size_t>(v)] = 1;
  for (int v = 0; v < n; ++v) {
    if (in[static_cast<std::size_t>(v)]) {
      candidate[static_cast<std::size_t>(v)] = 0;
      continue;
    }
    for (int w : s)
      if (!g.adjacent(v, w)) {
        candidate[static_cast<std::size_t>(v)] = 0;
        break;
      }
  }
  for (;;) {
    int best = -1;
    for (int v = 0; v < n; ++v)
      if (candidate[static_cast<std::size_t>(v)] && (best < 0 || u(v) > u(best))) best = v;
    if (best < 0) break;
    s.push_back(best);
    candidate[static_cast<std::size_t>(best)] = 0;
    for (int v = 0; v < n; ++v)
      if (candidate[static_cast<std::size_t>(v)] && !g.adjacent(v, best))
        candidate[static_cast<std::size_t>(v)] = 0;
  }
  std::sort(s.begin(), s.end());
  r.selection = std::move(s);
}

// DensestOptions::crawl_tolerance: the active vertices (in the support, with an inconsistent partner in it)
// of the last outer iteration, each with its weight scaled by d + F. When the set is the same after the next
// outer iteration and every scaled weight moved by less than the tolerance (relative), those vertices are set
// to zero and u is renormalised: the limit of their 1/(d + F) decay (see the header).
struct Crawl {
  std::vector<int> active;
  std::vector<double> scaled;
  std::vector<int> next_active;
  std::vector<double> next_scaled;

  // True when it zeroed vertices of u (the caller recomputes the products).
  bool drop(Vec& u, const Vec& Cu, double d, double F, const DensestOptions& o) {
    next_active.clear();
    next_scaled.clear();
    for (Eigen::Index i = 0; i < u.size(); ++i)
      if (Cu(i) > o.eps && u(i) > o.eps) {
        next_active.push_back(static_cast<int>(i));
        next_scaled.push_back(u(i) * (d + F));
      }
    bool settled = !next_active.empty() && next_active == active;
    for (std::size_t k = 0; settled && k < next_active.size(); ++k)
      settled = std::fabs(next_scaled[k] - scaled[k]) < o.crawl_tolerance * scaled[k];
    std::swap(active, next_active);
    std::swap(scaled, next_scaled);
    if (!settled) return false;
    Vec kept = u;
    for (const int i : active) kept(i) = 0.0;
    const double norm = kept.norm();
    if (!(norm > 0.0)) return false;  // the whole support is active: nothing would be left
    u = kept / norm;
    active.clear();
    scaled.clear();
    return true;
  }
};

DensestResult solve(const ConsistencyGraph& g, const Problem& p, const DensestOptions& o) {
  o.validate();
  const auto t0 = std::chrono::steady_clock::now();
  DensestResult r;
  const int n = g.size();
  if (n == 0) {
    r.converged = true;
    return r;
  }
  // u0: one power step of M on the all-ones vector, normalised (deterministic; the paper draws u0 at random).
  Vec u, Mu, Cu;
  p.products(Vec::Ones(n), Mu, Cu);
  u = Mu / Mu.norm();
  p.products(u, Mu, Cu);

  // The smallest penalty that makes an active constraint bind: d = min over I of (Mu)_i / (C̄u)_i, with I the
  // vertices in the support of u that have an inconsistent partner in it.
  // With PenaltyStep::mean, the mean of those ratios instead (the CLIPPER paper's schedule).
  auto penalty_step = [&](const Vec& mu, const Vec& cu, const Vec& x) {
    double step = std::numeric_limits<double>::infinity(), sum = 0.0;
    int active = 0;
    for (int i = 0; i < n; ++i)
      if (cu(i) > o.eps && x(i) > o.eps) {
        const double ratio = std::fabs(mu(i) / cu(i));
        step = std::min(step, ratio);
        sum += ratio;
        ++active;
      }
    if (o.penalty_step == DensestOptions::PenaltyStep::mean && active > 0) return sum / active;
    return step;
  };
  double d = penalty_step(Mu, Cu, u);
  if (!std::isfinite(d)) d = 0.0;
  auto objective = [&](const Vec& x, const Vec& mx, const Vec& cx) { return x.dot(mx) - d * x.dot(cx); };

  double F = objective(u, Mu, Cu);
  int stalled_outer = 0;  // consecutive outer iterations that moved u by less than tol_u
  Crawl crawl;
  Vec u_outer;
  // The line search's buffers, allocated once (the City10000 candidate sets take ~100 products of n ≈ 115,
  // where allocating four vectors per inner iteration was a tenth of the time).
  Vec grad(n), un(n), Mun(n), Cun(n);
  const double long_step = std::pow(1.0 / o.beta, 3);
  for (r.outer_iterations = 0; r.outer_iterations < o.max_outer;) {
    ++r.outer_iterations;
    u_outer = u;
    F = objective(u, Mu, Cu);
    for (int inner = 0; inner < o.max_inner; ++inner) {
      // Gradient of F_d (up to the factor 2), projected onto the tangent of the unit sphere.
      grad = Mu - d * Cu;
      grad -= u.dot(grad) * u;
      const double gnorm = grad.norm();
      if (gnorm < 1e-10) break;
      // First step length (1/β)³/‖g‖, shortened by β until F_d does not decrease. Stopping at the first hit
      // of the orthant's boundary instead (one more zero of u per step) costs about n − |support| steps:
      // measured 10–20× slower at n = 2000 with the same selections (bench_clique, BM_PlantedDensest).
      // DensestOptions::LineSearch::clipper instead tries u + β^k (M − dC̄)u, i.e. β^k / (1 + β^k F) along g.
      double alpha = long_step / gnorm, unit = 1.0;
      double Fn = -std::numeric_limits<double>::infinity();
      bool accepted = false;
      for (int tries = 0; tries < 99; ++tries, alpha *= o.beta, unit *= o.beta) {
        double step = alpha;
        if (o.line_search == DensestOptions::LineSearch::clipper) {
          if (!(1.0 + unit * F > 0.0)) continue;
          step = unit / (1.0 + unit * F);
        }
        un = (u + step * grad).cwiseMax(0.0);
        const double norm = un.norm();
        if (!(norm > 0.0)) continue;
        un /= norm;
        p.products(un, Mun, Cun);
        ++r.products;
        Fn = objective(un, Mun, Cun);
        if (Fn >= F - o.eps) {
          accepted = true;
          break;
        }
      }
      ++r.inner_iterations;
      if (!accepted) break;  // no ascent step: a local maximum at this d
      const bool small = (un - u).norm() < o.tol_u || std::fabs(Fn - F) < o.tol_f;
      u.swap(un), Mu.swap(Mun), Cu.swap(Cun), F = Fn;
      if (small) break;
    }
    double step = penalty_step(Mu, Cu, u);
    if (std::isfinite(step) && o.crawl_tolerance > 0.0 && crawl.drop(u, Cu, d, F, o)) {
      p.products(u, Mu, Cu);
      ++r.products;
      ++r.crawl_cuts;
      step = penalty_step(Mu, Cu, u);
    }
    if (!std::isfinite(step)) {  // no inconsistent pair left in the support
      r.converged = true;
      break;
    }
    stalled_outer = (u - u_outer).norm() < o.tol_u ? stalled_outer + 1 : 0;
    if (o.max_stalled_outer > 0 && stalled_outer >= o.max_stalled_outer) {
      r.stalled = true;
      break;
    }
    d += step;
  }
  r.sparse = p.sparse;
  r.penalty = d;
  r.objective = objective(u, Mu, Cu);
  round_and_repair(g, u, r.objective, o.eps, r);
  r.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace

DensestResult densest_subgraph(const ConsistencyGraph& g, const DensestOptions& options) {
  options.validate();
  Problem p = adjacency(g, use_sparse(g, options.storage));
  p.binary = true;
  return solve(g, p, options);
}

DensestResult densest_subgraph(const ConsistencyGraph& g, const std::vector<double>& affinity,
                               const DensestOptions& options) {
  const int n = g.size();
  const auto nn = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  if (affinity.size() != nn)
    throw std::invalid_argument(
        fmt::format("densest_subgraph: affinity has {} entries, expected n² = {}", affinity.size(), nn));
  options.validate();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      const double a = affinity[static_cast<std::size_t>(i) * n + j];
      const double b = affinity[static_cast<std::size_t>(j) * n + i];
      if (!std::isfinite(a) || a < 0.0 || a > 1.0)
        throw std::invalid_argument(
            fmt::format("densest_subgraph: affinity({}, {}) = {:g} is not in [0, 1]", i, j, a));
      if (a != b)
        throw std::invalid_argument(
            fmt::format("densest_subgraph: affinity is not symmetric: ({}, {}) = {:g}, ({}, {}) = {:g}", i, j,
                        a, j, i, b));
    }
  Problem p = adjacency(g, use_sparse(g, options.storage));
  p.binary = false;
  if (p.sparse) {
    p.weight.resize(p.next.size());
    for (int i = 0; i < n; ++i)
      for (int k = p.start[i]; k < p.start[i + 1]; ++k)
        p.weight[k] = affinity[static_cast<std::size_t>(i) * n + p.next[k]];
  } else {
    p.M = Mat::Identity(n, n);
    for (int i = 0; i < n; ++i)
      for (int j : g.neighbors(i)) p.M(i, j) = affinity[static_cast<std::size_t>(i) * n + j];
  }
  return solve(g, p, options);
}

}  // namespace keel::pcm
