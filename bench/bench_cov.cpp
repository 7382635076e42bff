// Google Benchmark for keel.cov (thesis §5.8.2): joint Lie-algebra marginals of Manhattan3500 at its ground
// truth.
//   BM_Factorize            information matrix (Lie-algebra Jacobians) + CHOLMOD analysis and factorization
//   BM_AllPairMarginals     all 44 425 pairs (i, i+k), k ∈ {5, 10, …, 50, 100, 200, 500}: 6×6 joint
//   marginals, on a
//                           factor made once; config 0 = defaults (CHOLMOD's ordering, forward extraction),
//                           1 = METIS ordering + forward, 2 = CHOLMOD's ordering + multi-column solves
//                           (solve)
//   BM_MarginalsOneCall     information matrix + factorization + all 44 425 pairs in one iteration (one
//                           `keel marginals` / keel.marginals call; bench/bench_python.py compares with it)
//   BM_JointSingle          one joint() query of three poses
//   BM_Subset{Keel,Ceres}   200 of those pairs, keel.cov vs ceres::Covariance on the same residuals with the
//   poses on a
//                           manifold whose tangent is the same left perturbation; counter max_rel_diff = max
//                           over the pairs of ‖Σ_ceres − Σ_keel‖_F / ‖Σ_keel‖_F
// Run from the repository root (the dataset resolver looks for datasets/manifest.toml):
// build/release/bench/bench_cov Note: Debian's libbenchmark prints "Library was built as DEBUG"; that
// concerns the library's own timing loop only.
import keel.lie;
import keel.datasets;
import keel.graph;
import keel.cov;

#include <benchmark/benchmark.h>

#include "csv_union.hpp"
#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace cov = keel::cov;
namespace datasets = keel::datasets;
namespace graph = keel::graph;
namespace lie = keel::lie;

namespace {

struct Manhattan {
  std::string error;  // non-empty when the data could not be loaded
  graph::PoseGraph2D graph;
  std::vector<lie::SE2> truth;
  std::unique_ptr<cov::MarginalCovariance> marginals;             // default options
  std::vector<std::unique_ptr<cov::MarginalCovariance>> configs;  // see BM_AllPairMarginals
  std::vector<std::pair<int, int>> pairs;                         // the 44 425 pairs
  std::vector<std::pair<int, int>> subset;                        // 200 of them, spread over all k
  std::vector<lie::Mat6> subset_keel;  // keel's answer on the subset (reference for the Ceres comparison)
};

const Manhattan& manhattan() {
  static const Manhattan m = [] {
    Manhattan m;
    try {
      m.graph =
          graph::read_isam_2d(datasets::resolve_dataset_file("manhattan3500", "isam/manhattanOlson3500.txt"));
      m.truth = graph::read_poses_2d(datasets::resolve_dataset_file(
          "manhattan3500", "derived/manhattanOlson3500_groundtruth_poses.txt"));
      const cov::SparseInformation H = cov::information_matrix(m.graph, m.truth);
      m.marginals = std::make_unique<cov::MarginalCovariance>(H);
      cov::CovarianceOptions metis, solve;
      metis.ordering = cov::Ordering::metis;
      solve.extraction = cov::Extraction::solve;
      for (const auto& o : {cov::CovarianceOptions{}, metis, solve})
        m.configs.push_back(std::make_unique<cov::MarginalCovariance>(H, o));
    } catch (const std::exception& e) {
      m.error = e.what();
      return m;
    }
    const int n = static_cast<int>(m.truth.size());
    for (int k : {5, 10, 15, 20, 25, 30, 35, 40, 45, 50, 100, 200, 500})
      for (int i = 0; i + k < n; ++i) m.pairs.emplace_back(i, i + k);
    const std::size_t stride = m.pairs.size() / 200;
    for (std::size_t s = stride / 2; m.subset.size() < 200; s += stride) m.subset.push_back(m.pairs[s]);
    m.subset_keel = cov::pair_marginals_2d(*m.marginals, m.subset, 1);
    return m;
  }();
  return m;
}

// ---------------------------------------------------------------------------------------------------------------------
// keel.cov

void BM_Factorize(benchmark::State& state) {
  const Manhattan& m = manhattan();
  if (!m.error.empty()) return state.SkipWithError(m.error.c_str());
  for (auto _ : state) {
    const cov::MarginalCovariance mc(cov::information_matrix(m.graph, m.truth));
    benchmark::DoNotOptimize(mc.summary().nnz_l);
  }
  const auto& s = m.marginals->summary();
  state.SetLabel(fmt::format("ordering {}, {}", s.ordering, s.supernodal ? "supernodal" : "simplicial"));
  state.counters["size"] = s.size;
  state.counters["nnz_H"] = static_cast<double>(s.nnz_h);
  state.counters["nnz_L"] = s.nnz_l;
  state.counters["supernodes"] = static_cast<double>(s.num_supernodes);
  state.counters["path_share"] = s.mean_path_fraction;
}

void BM_AllPairMarginals(benchmark::State& state) {
  const Manhattan& m = manhattan();
  if (!m.error.empty()) return state.SkipWithError(m.error.c_str());
  const auto& mc = *m.configs[static_cast<std::size_t>(state.range(0))];
  const unsigned threads = static_cast<unsigned>(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(cov::pair_marginals_2d(mc, m.pairs, threads).data());
  state.SetLabel(fmt::format("ordering {}, extraction {}", mc.summary().ordering, mc.summary().extraction));
  state.counters["pairs"] = static_cast<double>(m.pairs.size());
  state.counters["pairs_per_s"] =
      benchmark::Counter(static_cast<double>(m.pairs.size()), benchmark::Counter::kIsIterationInvariantRate);
}

// What one `keel marginals --pairs` or Python keel.marginals(pairs=…) call does: information matrix,
// factorization and every pair, in one iteration (the counterpart of bench/bench_python.py's one-call line;
// BM_Factorize + BM_AllPairMarginals time the two halves apart, without the interference of CHOLMOD's BLAS
// threads with the extraction threads that one call has).
void BM_MarginalsOneCall(benchmark::State& state) {
  const Manhattan& m = manhattan();
  if (!m.error.empty()) return state.SkipWithError(m.error.c_str());
  const unsigned threads = static_cast<unsigned>(state.range(0));
  for (auto _ : state) {
    const cov::MarginalCovariance mc(cov::information_matrix(m.graph, m.truth));
    benchmark::DoNotOptimize(cov::pair_marginals_2d(mc, m.pairs, threads).data());
  }
  state.counters["pairs"] = static_cast<double>(m.pairs.size());
}

// One small query (3 poses far apart): a forward substitution along three paths of the elimination tree.
void BM_JointSingle(benchmark::State& state) {
  const Manhattan& m = manhattan();
  if (!m.error.empty()) return state.SkipWithError(m.error.c_str());
  for (auto _ : state) benchmark::DoNotOptimize(m.marginals->joint({1000, 2000, 3000}).data());
}

// The subset from scratch (information matrix, factorization, extraction), like ceres::Covariance::Compute
// below.
void BM_SubsetKeel(benchmark::State& state) {
  const Manhattan& m = manhattan();
  if (!m.error.empty()) return state.SkipWithError(m.error.c_str());
  for (auto _ : state) {
    const cov::MarginalCovariance mc(cov::information_matrix(m.graph, m.truth));
    benchmark::DoNotOptimize(cov::pair_marginals_2d(mc, m.subset, 1).data());
  }
  state.counters["pairs"] = static_cast<double>(m.subset.size());
}

// ---------------------------------------------------------------------------------------------------------------------
// ceres::Covariance on the same problem

// ρ(z⁻¹ T_i⁻¹ T_j) = (x_E, y_E, wrap θ_E) of graph/pose_graph.hpp, in the pose coordinates (x, y, θ),
// whitened by the upper Cholesky factor U of Ω (Ω = UᵀU).
struct EdgeResidual {
  double zx, zy, zt;
  double U[6];  // u00 u01 u02 u11 u12 u22
  template <class T>
  bool operator()(const T* a, const T* b, T* r) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    const T ca = cos(a[2]), sa = sin(a[2]);
    const T dx = b[0] - a[0], dy = b[1] - a[1];
    const T px = ca * dx + sa * dy - zx, py = -sa * dx + ca * dy - zy;  // translation of T_i⁻¹ T_j, minus t_z
    const double cz = std::cos(zt), sz = std::sin(zt);
    const T ex = cz * px + sz * py, ey = -sz * px + cz * py;
    const T th = b[2] - a[2] - zt;
    const T et = atan2(sin(th), cos(th));
    r[0] = U[0] * ex + U[1] * ey + U[2] * et;
    r[1] = U[3] * ey + U[4] * et;
    r[2] = U[5] * et;
    return true;
  }
};

// Coordinates (x, y, θ) with the tangent of the left perturbation T = exp(δ^) T̄ (eq. 5.14): Plus(x, δ) =
// exp(δ^) T(x).
class LeftPerturbationSE2 final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 3; }
  int TangentSize() const override { return 3; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const lie::SE2 T = lie::SE2::exp(lie::Vec3(delta[0], delta[1], delta[2])) * lie::SE2(x[0], x[1], x[2]);
    x_plus_delta[0] = T.translation().x();
    x_plus_delta[1] = T.translation().y();
    x_plus_delta[2] = T.angle();
    return true;
  }
  bool PlusJacobian(const double* x,
                    double* J) const override {  // ∂(coords of exp(δ^) T)/∂δ at δ = 0, row-major
    const double v[9] = {1.0, 0.0, -x[1], 0.0, 1.0, x[0], 0.0, 0.0, 1.0};
    std::copy(v, v + 9, J);
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const lie::Vec3 xi = (lie::SE2(y[0], y[1], y[2]) * lie::SE2(x[0], x[1], x[2]).inverse()).log();
    for (int k = 0; k < 3; ++k) y_minus_x[k] = xi(k);
    return true;
  }
  bool MinusJacobian(const double* x, double* J) const override {
    const double v[9] = {1.0, 0.0, x[1], 0.0, 1.0, -x[0], 0.0, 0.0, 1.0};
    std::copy(v, v + 9, J);
    return true;
  }
};

void BM_SubsetCeres(benchmark::State& state) {
  const Manhattan& m = manhattan();
  if (!m.error.empty()) return state.SkipWithError(m.error.c_str());
  const int n = static_cast<int>(m.truth.size());
  std::vector<double> x(3 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    x[3 * i] = m.truth[i].translation().x();
    x[3 * i + 1] = m.truth[i].translation().y();
    x[3 * i + 2] = m.truth[i].angle();
  }
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  LeftPerturbationSE2 manifold;
  for (const auto& e : m.graph.edges) {
    auto* f = new EdgeResidual;
    f->zx = e.measurement.translation().x();
    f->zy = e.measurement.translation().y();
    f->zt = e.measurement.angle();
    // 3×3 upper Cholesky factor of Ω, by hand (the bench stays free of Eigen decompositions).
    const auto& O = e.information;
    const double u00 = std::sqrt(O(0, 0)), u01 = O(0, 1) / u00, u02 = O(0, 2) / u00;
    const double u11 = std::sqrt(O(1, 1) - u01 * u01), u12 = (O(1, 2) - u01 * u02) / u11;
    const double u22 = std::sqrt(O(2, 2) - u02 * u02 - u12 * u12);
    const double U[6] = {u00, u01, u02, u11, u12, u22};
    std::copy(U, U + 6, f->U);
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<EdgeResidual, 3, 3, 3>(f), nullptr, &x[3 * e.i],
                             &x[3 * e.j]);
  }
  for (int i = 0; i < n; ++i) problem.SetManifold(&x[3 * i], &manifold);
  problem.SetParameterBlockConstant(&x[0]);  // the gauge: pose 0

  std::vector<std::pair<const double*, const double*>> blocks;
  for (const auto& [i, j] : m.subset)
    for (const auto& [a, b] : {std::pair{i, i}, std::pair{j, j}, std::pair{i, j}})
      blocks.emplace_back(&x[3 * a], &x[3 * b]);
  std::sort(blocks.begin(), blocks.end());
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());

  ceres::Covariance::Options co;  // SPARSE_QR with SuiteSparseQR (Ceres' default)
  co.num_threads = static_cast<int>(state.range(0));
  double max_rel = 0.0;
  for (auto _ : state) {
    ceres::Covariance covariance(co);
    if (!covariance.Compute(blocks, &problem))
      return state.SkipWithError("ceres::Covariance::Compute failed");
    max_rel = 0.0;
    for (std::size_t k = 0; k < m.subset.size(); ++k) {
      const auto [i, j] = m.subset[k];
      const int v[2] = {i, j};
      double diff = 0.0, ref = 0.0;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          double c[9];
          covariance.GetCovarianceBlockInTangentSpace(&x[3 * v[a]], &x[3 * v[b]], c);
          for (int r = 0; r < 3; ++r)
            for (int s = 0; s < 3; ++s) {
              const double kv = m.subset_keel[k](3 * a + r, 3 * b + s);
              diff += (c[3 * r + s] - kv) * (c[3 * r + s] - kv);
              ref += kv * kv;
            }
        }
      max_rel = std::max(max_rel, std::sqrt(diff / ref));
    }
  }
  state.counters["pairs"] = static_cast<double>(m.subset.size());
  state.counters["max_rel_diff"] = max_rel;
}

}  // namespace

BENCHMARK(BM_Factorize)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AllPairMarginals)
    ->ArgsProduct({{0, 1, 2}, {1, 2}})
    ->ArgNames({"config", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_MarginalsOneCall)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_JointSingle)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SubsetKeel)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SubsetCeres)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();

KEEL_BENCHMARK_MAIN()
