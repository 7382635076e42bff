#include "align/sdp.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <mutex>
#include <stdexcept>

#include "core/quiet.hpp"
#include "core/timing.hpp"

extern "C" {
#include <dsdp5.h>
}

namespace keel::align {

namespace {
// DSDP keeps global state and prints with printf: calls are serialised with every other area's DSDP calls
// (core::library_mutex("dsdp")), and stdout points at /dev/null while one runs.
void ok(int code, const char* what) {
  if (code != 0) throw std::runtime_error(fmt::format("so_conv_hull_sdp: DSDP {} returned {}", what, code));
}
}  // namespace

SdpSolution so_conv_hull_sdp(const AlignmentProblem& p, const Regions& reg, double gap_tolerance) {
  const auto t0 = core::Clock::now();
  const std::size_t nb = p.query_size();
  if (reg.planes.size() != nb || reg.boxes.size() != nb)
    throw std::invalid_argument("so_conv_hull_sdp: the regions do not belong to this problem");
  // DSDP's dual form: maximise bᵀy s.t. C − Σ y_i A_i ⪰ 0 and c − Σ y_i a_i ≥ 0 (LP cone). y = (c, s, tx, ty,
  // u_1 … u_nb), b = (0, 0, 0, 0, −1 … −1).
  const int m = static_cast<int>(4 + nb);
  // LP inequalities a·y ≤ rhs, stored by variable (DSDP's LP cone takes columns: column 0 is rhs, column i is
  // the coefficient vector of y_i).
  std::vector<std::vector<std::pair<int, double>>> column(m + 1);
  int rows = 0;
  auto add = [&](const double lin[4], int u, double rhs) {
    if (rhs != 0) column[0].emplace_back(rows, rhs);
    for (int k = 0; k < 4; ++k)
      if (lin[k] != 0) column[1 + k].emplace_back(rows, lin[k]);
    if (u >= 0) column[1 + 4 + u].emplace_back(rows, -1.0);
    ++rows;
  };
  for (std::size_t j = 0; j < nb; ++j) {
    const double x = p.query_x[j], y = p.query_y[j];
    const double f[4] = {x, -y, 1, 0}, g[4] = {y, x, 0, 1};  // (c, s, tx, ty) -> f_j, g_j
    for (const Plane& pl : reg.planes[j]) {
      double lin[4];
      for (int k = 0; k < 4; ++k) lin[k] = pl.r * f[k] + pl.s * g[k];
      add(lin, static_cast<int>(j), -pl.t);  // r f + s g − u ≤ −t
    }
    const Box& b = reg.boxes[j];
    double nf[4], ng[4];
    for (int k = 0; k < 4; ++k) nf[k] = -f[k], ng[k] = -g[k];
    add(f, -1, b.x_hi), add(nf, -1, -b.x_lo), add(g, -1, b.y_hi), add(ng, -1, -b.y_lo);
  }
  std::vector<int> ik{0}, cols;
  std::vector<double> vals;
  for (const auto& c : column) {
    for (const auto& [r, v] : c) cols.push_back(r), vals.push_back(v);
    ik.push_back(static_cast<int>(cols.size()));
  }

  std::lock_guard<std::mutex> lock(core::library_mutex("dsdp"));
  core::QuietStdout quiet;
  DSDP dsdp;
  ok(DSDPCreate(m, &dsdp), "DSDPCreate");
  SdpSolution out;
  try {
    for (int i = 5; i <= m; ++i) ok(DSDPSetDualObjective(dsdp, i, -1.0), "DSDPSetDualObjective");
    LPCone lp;
    ok(DSDPCreateLPCone(dsdp, &lp), "DSDPCreateLPCone");
    ok(LPConeSetData(lp, rows, ik.data(), cols.data(), vals.data()), "LPConeSetData");
    SDPCone sdp;
    ok(DSDPCreateSDPCone(dsdp, 1, &sdp), "DSDPCreateSDPCone");
    ok(SDPConeSetBlockSize(sdp, 0, 2), "SDPConeSetBlockSize");
    // Packed lower triangle of a 2 × 2 block: index 0 = (0,0), 1 = (1,0), 2 = (1,1).
    // C − c A_c − s A_s = [[1 + c, s], [s, 1 − c]]: C = I, A_c = diag(−1, 1), A_s = −[[0, 1], [1, 0]].
    static const int ind_c[2] = {0, 2}, ind_s[1] = {1};
    static const double val_C[2] = {1.0, 1.0}, val_c[2] = {-1.0, 1.0}, val_s[1] = {-1.0};
    ok(SDPConeSetASparseVecMat(sdp, 0, 0, 2, 1.0, 0, ind_c, val_C, 2), "SDPConeSetASparseVecMat(C)");
    ok(SDPConeSetASparseVecMat(sdp, 0, 1, 2, 1.0, 0, ind_c, val_c, 2), "SDPConeSetASparseVecMat(c)");
    ok(SDPConeSetASparseVecMat(sdp, 0, 2, 2, 1.0, 0, ind_s, val_s, 1), "SDPConeSetASparseVecMat(s)");
    ok(DSDPSetGapTolerance(dsdp, gap_tolerance), "DSDPSetGapTolerance");
    ok(DSDPSetup(dsdp), "DSDPSetup");
    ok(DSDPSolve(dsdp), "DSDPSolve");
    DSDPTerminationReason reason;
    DSDPSolutionType type;
    ok(DSDPStopReason(dsdp, &reason), "DSDPStopReason");
    ok(DSDPGetSolutionType(dsdp, &type), "DSDPGetSolutionType");
    std::vector<double> y(m);
    ok(DSDPGetY(dsdp, y.data(), m), "DSDPGetY");
    double dobj = 0;
    ok(DSDPGetDObjective(dsdp, &dobj), "DSDPGetDObjective");
    ok(DSDPGetIts(dsdp, &out.iterations), "DSDPGetIts");
    out.converged = reason == DSDP_CONVERGED && type == DSDP_PDFEASIBLE;
    out.cost = -dobj;
    out.params.assign(y.begin(), y.begin() + 4);
  } catch (...) {
    DSDPDestroy(dsdp);
    throw;
  }
  DSDPDestroy(dsdp);
  out.time_s = core::seconds_since(t0);
  return out;
}

}  // namespace keel::align
