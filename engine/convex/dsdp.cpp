// The DSDP 5 backend of keel::convex (Debian libdsdp-dev): DSDP solves the dual form of sdp.hpp directly,
// maximise bᵀy s.t. C − Σ y_i A_i ⪰ 0 with the orthant as its LP cone (column 0 the right-hand side c_lp,
// column i the vector a_lp,i), 2 × 2 and larger blocks in packed lower-triangular order.
#include <fmt/format.h>

#include <map>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "convex/sdp.hpp"
#include "core/quiet.hpp"
#include "core/timing.hpp"

extern "C" {
#include <dsdp5.h>
}

namespace keel::convex::detail {

namespace {
// DSDP keeps global state and prints with printf: calls are serialised with every other DSDP call in the
// process (core::library_mutex("dsdp")), and stdout points at /dev/null while one runs.
void ok(int code, const char* what) {
  if (code != 0) throw std::runtime_error(fmt::format("convex::solve_sdp: DSDP {} returned {}", what, code));
}

// DSDP's packed lower triangle: (row, col), row ≥ col, at row (row + 1) / 2 + col.
int packed(int row, int col) { return row * (row + 1) / 2 + col; }
}  // namespace

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

  // The orthant as DSDP's LP cone, column by column: column 0 is c_lp, column i + 1 is a_lp,i; rows
  // ascending, repeats summed, exact zeros dropped. DSDP keeps these pointers too.
  std::vector<int> lp_start{0}, lp_row;
  std::vector<double> lp_value;
  if (sdp.lp_size > 0) {
    auto column = [&](const std::vector<LpEntry>* entries) {
      std::map<int, double> merged_column;
      if (entries)
        for (const LpEntry& e : *entries) merged_column[e.row] += e.value;
      for (const auto& [r, v] : merged_column)
        if (v != 0.0) lp_row.push_back(r), lp_value.push_back(v);
      lp_start.push_back(static_cast<int>(lp_row.size()));
    };
    column(&sdp.lp_c);
    for (int i = 0; i < m; ++i) column(sdp.lp_a.empty() ? nullptr : &sdp.lp_a[static_cast<std::size_t>(i)]);
  }

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
    LPCone lp = nullptr;
    if (sdp.lp_size > 0) {
      ok(DSDPCreateLPCone(dsdp, &lp), "DSDPCreateLPCone");
      ok(LPConeSetData(lp, sdp.lp_size, lp_start.data(), lp_row.data(), lp_value.data()), "LPConeSetData");
    }
    SDPCone cone = nullptr;
    if (nb > 0) ok(DSDPCreateSDPCone(dsdp, static_cast<int>(nb), &cone), "DSDPCreateSDPCone");
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
    ok(DSDPGetDObjective(dsdp, &out.solver_dual_objective), "DSDPGetDObjective");
    if (sdp.lp_size > 0) {
      double* xl = nullptr;
      int nl = 0;
      ok(LPConeGetXArray(lp, &xl, &nl), "LPConeGetXArray");
      if (nl != sdp.lp_size)
        throw std::runtime_error("convex::solve_sdp: DSDP returned an x_lp of the wrong size");
      out.x_lp = Eigen::Map<const Eigen::VectorXd>(xl, nl);
    }
    for (std::size_t k = 0; k < nb; ++k) {
      double* xx = nullptr;
      int nn = 0;
      ok(SDPConeGetXArray(cone, static_cast<int>(k), &xx, &nn), "SDPConeGetXArray");
      const int n = sdp.block_sizes[k];
      if (nn != n * (n + 1) / 2)
        throw std::runtime_error("convex::solve_sdp: DSDP returned an X of the wrong size");
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

}  // namespace keel::convex::detail
