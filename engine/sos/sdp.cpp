#include "sos/sdp.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <stdexcept>

#include "core/names.hpp"
#include "core/quiet.hpp"
#include "core/timing.hpp"

extern "C" {
#include <dsdp5.h>
}

namespace keel::sos {

namespace {
constexpr core::NameTable<SdpSolver, 2> kSolverNames{
    "sos::SdpSolver", {{{SdpSolver::dsdp, "dsdp"}, {SdpSolver::sdpa, "sdpa"}}}};

void check_entries(const std::vector<int>& sizes, const std::vector<SdpEntry>& entries,
                   const std::string& what) {
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const SdpEntry& e = entries[k];
    if (e.block < 0 || e.block >= static_cast<int>(sizes.size()))
      throw std::invalid_argument(
          fmt::format("sos::Sdp: {} entry {} names block {} (blocks: {})", what, k, e.block, sizes.size()));
    const int n = sizes[static_cast<std::size_t>(e.block)];
    if (e.col < 0 || e.row < e.col || e.row >= n)
      throw std::invalid_argument(
          fmt::format("sos::Sdp: {} entry {} at ({}, {}) is not in the lower triangle of block {} (size {})",
                      what, k, e.row, e.col, e.block, n));
    if (!std::isfinite(e.value))
      throw std::invalid_argument(fmt::format("sos::Sdp: {} entry {} is not finite ({})", what, k, e.value));
  }
}

// DSDP keeps global state and prints with printf: calls are serialised with every other area's DSDP calls
// (core::library_mutex("dsdp")), and stdout points at /dev/null while one runs.
void ok(int code, const char* what) {
  if (code != 0) throw std::runtime_error(fmt::format("sos::solve_sdp: DSDP {} returned {}", what, code));
}

// DSDP's packed lower triangle: (row, col), row ≥ col, at row (row + 1) / 2 + col.
int packed(int row, int col) { return row * (row + 1) / 2 + col; }

double inner(const std::vector<Eigen::MatrixXd>& x, const std::vector<SdpEntry>& entries) {
  double v = 0.0;
  for (const SdpEntry& e : entries) {
    const double xe = x[static_cast<std::size_t>(e.block)](e.row, e.col);
    v += (e.row == e.col ? 1.0 : 2.0) * e.value * xe;
  }
  return v;
}

double min_eigenvalue(const Eigen::MatrixXd& m) {
  if (m.rows() == 0) return 0.0;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m, Eigen::EigenvaluesOnly);
  return es.eigenvalues()(0);
}
}  // namespace

std::string_view to_string(SdpSolver v) { return kSolverNames.name(v); }
SdpSolver sdp_solver_from_string(std::string_view s) { return kSolverNames.parse(s); }

void Sdp::validate() const {
  if (block_sizes.empty()) throw std::invalid_argument("sos::Sdp: no blocks");
  for (std::size_t k = 0; k < block_sizes.size(); ++k)
    if (block_sizes[k] < 1)
      throw std::invalid_argument(
          fmt::format("sos::Sdp: block {} has size {} (must be >= 1)", k, block_sizes[k]));
  if (a.size() != b.size())
    throw std::invalid_argument(
        fmt::format("sos::Sdp: {} constraint matrices but {} right-hand sides", a.size(), b.size()));
  check_entries(block_sizes, c, "C");
  for (std::size_t i = 0; i < a.size(); ++i) {
    check_entries(block_sizes, a[i], fmt::format("A_{}", i));
    if (!std::isfinite(b[i])) throw std::invalid_argument(fmt::format("sos::Sdp: b_{} is not finite", i));
  }
}

void SdpSettings::validate() const {
  if (!(gap_tolerance > 0))
    throw std::invalid_argument(
        fmt::format("sos::SdpSettings: gap_tolerance must be > 0 (got {})", gap_tolerance));
  if (max_iterations <= 0)
    throw std::invalid_argument(
        fmt::format("sos::SdpSettings: max_iterations must be > 0 (got {})", max_iterations));
}

std::vector<Eigen::MatrixXd> dense_blocks(const std::vector<int>& block_sizes,
                                          const std::vector<SdpEntry>& entries) {
  std::vector<Eigen::MatrixXd> out;
  out.reserve(block_sizes.size());
  for (int n : block_sizes) out.push_back(Eigen::MatrixXd::Zero(n, n));
  for (const SdpEntry& e : entries) {
    auto& m = out[static_cast<std::size_t>(e.block)];
    m(e.row, e.col) += e.value;
    if (e.row != e.col) m(e.col, e.row) += e.value;
  }
  return out;
}

SdpSolution solve_sdp(const Sdp& sdp, const SdpSettings& settings) {
  sdp.validate();
  settings.validate();
  switch (settings.solver) {
    case SdpSolver::dsdp:
      return detail::solve_with_dsdp(sdp, settings);
    case SdpSolver::sdpa:
      return detail::solve_with_sdpa(sdp, settings);
  }
  throw std::invalid_argument("sos::solve_sdp: unknown solver");
}

SdpCheck check_sdp(const Sdp& sdp, const SdpSolution& sol) {
  if (sol.x.size() != sdp.block_sizes.size() || sol.y.size() != sdp.constraints())
    throw std::invalid_argument("sos::check_sdp: the solution does not belong to this program");
  SdpCheck out;
  out.primal_objective = inner(sol.x, sdp.c);
  double bmax = 0.0, rmax = 0.0;
  for (int i = 0; i < sdp.constraints(); ++i) {
    const auto iu = static_cast<std::size_t>(i);
    out.dual_objective += sdp.b[iu] * sol.y(i);
    bmax = std::max(bmax, std::abs(sdp.b[iu]));
    rmax = std::max(rmax, std::abs(inner(sol.x, sdp.a[iu]) - sdp.b[iu]));
  }
  out.primal_residual = rmax / (1.0 + bmax);
  out.s = dense_blocks(sdp.block_sizes, sdp.c);
  for (int i = 0; i < sdp.constraints(); ++i)
    for (const SdpEntry& e : sdp.a[static_cast<std::size_t>(i)]) {
      auto& m = out.s[static_cast<std::size_t>(e.block)];
      m(e.row, e.col) -= sol.y(i) * e.value;
      if (e.row != e.col) m(e.col, e.row) -= sol.y(i) * e.value;
    }
  out.x_min_eigenvalue = INFINITY;
  out.s_min_eigenvalue = INFINITY;
  for (std::size_t k = 0; k < out.s.size(); ++k) {
    out.x_min_eigenvalue = std::min(out.x_min_eigenvalue, min_eigenvalue(sol.x[k]));
    out.s_min_eigenvalue = std::min(out.s_min_eigenvalue, min_eigenvalue(out.s[k]));
  }
  out.relative_gap = std::abs(out.primal_objective - out.dual_objective) /
                     (1.0 + std::abs(out.primal_objective) + std::abs(out.dual_objective));
  return out;
}

namespace detail {

SdpSolution solve_with_dsdp(const Sdp& sdp, const SdpSettings& settings) {
  auto t0 = core::Clock::now();
  const int m = sdp.constraints();
  const auto nb = sdp.block_sizes.size();
  // Per (block, variable) merged entries; variable 0 is C, variable i + 1 is A_i. DSDP keeps the pointers it
  // is given until it is destroyed, so the arrays live here.
  std::vector<std::vector<std::map<int, double>>> merged(nb, std::vector<std::map<int, double>>(m + 1));
  for (const SdpEntry& e : sdp.c)
    merged[static_cast<std::size_t>(e.block)][0][packed(e.row, e.col)] += e.value;
  for (int i = 0; i < m; ++i)
    for (const SdpEntry& e : sdp.a[static_cast<std::size_t>(i)])
      merged[static_cast<std::size_t>(e.block)][static_cast<std::size_t>(i + 1)][packed(e.row, e.col)] +=
          e.value;
  std::vector<std::vector<std::vector<int>>> ind(nb, std::vector<std::vector<int>>(m + 1));
  std::vector<std::vector<std::vector<double>>> val(nb, std::vector<std::vector<double>>(m + 1));
  for (std::size_t k = 0; k < nb; ++k)
    for (std::size_t v = 0; v <= static_cast<std::size_t>(m); ++v)
      for (const auto& [idx, x] : merged[k][v])
        if (x != 0.0) ind[k][v].push_back(idx), val[k][v].push_back(x);

  std::lock_guard<std::mutex> lock(core::library_mutex("dsdp"));
  const double setup_s = core::seconds_since(t0);  // building the arrays, before waiting for the lock
  t0 = core::Clock::now();
  core::QuietStdout quiet;
  DSDP dsdp;
  ok(DSDPCreate(m, &dsdp), "DSDPCreate");
  SdpSolution out;
  try {
    for (int i = 0; i < m; ++i)
      ok(DSDPSetDualObjective(dsdp, i + 1, sdp.b[static_cast<std::size_t>(i)]), "DSDPSetDualObjective");
    SDPCone cone;
    ok(DSDPCreateSDPCone(dsdp, static_cast<int>(nb), &cone), "DSDPCreateSDPCone");
    for (std::size_t k = 0; k < nb; ++k) {
      const int n = sdp.block_sizes[k];
      ok(SDPConeSetBlockSize(cone, static_cast<int>(k), n), "SDPConeSetBlockSize");
      for (std::size_t v = 0; v <= static_cast<std::size_t>(m); ++v)
        if (!ind[k][v].empty())
          ok(SDPConeSetASparseVecMat(cone, static_cast<int>(k), static_cast<int>(v), n, 1.0, 0,
                                     ind[k][v].data(), val[k][v].data(), static_cast<int>(ind[k][v].size())),
             "SDPConeSetASparseVecMat");
    }
    ok(DSDPSetGapTolerance(dsdp, settings.gap_tolerance), "DSDPSetGapTolerance");
    ok(DSDPSetMaxIts(dsdp, settings.max_iterations), "DSDPSetMaxIts");
    ok(DSDPSetup(dsdp), "DSDPSetup");
    ok(DSDPSolve(dsdp), "DSDPSolve");
    ok(DSDPComputeX(dsdp), "DSDPComputeX");
    DSDPTerminationReason reason;
    DSDPSolutionType type;
    ok(DSDPStopReason(dsdp, &reason), "DSDPStopReason");
    ok(DSDPGetSolutionType(dsdp, &type), "DSDPGetSolutionType");
    out.y.resize(m);
    if (m > 0) ok(DSDPGetY(dsdp, out.y.data(), m), "DSDPGetY");
    ok(DSDPGetIts(dsdp, &out.iterations), "DSDPGetIts");
    for (std::size_t k = 0; k < nb; ++k) {
      double* xx = nullptr;
      int nn = 0;
      ok(SDPConeGetXArray(cone, static_cast<int>(k), &xx, &nn), "SDPConeGetXArray");
      const int n = sdp.block_sizes[k];
      if (nn != n * (n + 1) / 2)
        throw std::runtime_error("sos::solve_sdp: DSDP returned an X of the wrong size");
      Eigen::MatrixXd x(n, n);
      for (int r = 0; r < n; ++r)
        for (int c = 0; c <= r; ++c) x(r, c) = x(c, r) = xx[packed(r, c)];
      out.x.push_back(std::move(x));
    }
    out.claims_optimal = reason == DSDP_CONVERGED && type == DSDP_PDFEASIBLE;
    out.status = fmt::format("reason {}, solution type {}", static_cast<int>(reason), static_cast<int>(type));
  } catch (...) {
    DSDPDestroy(dsdp);
    throw;
  }
  DSDPDestroy(dsdp);
  out.time_s = setup_s + core::seconds_since(t0);  // time waiting for another thread's call excluded
  return out;
}

}  // namespace detail
}  // namespace keel::sos
