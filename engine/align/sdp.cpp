#include "align/sdp.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "convex/sdp.hpp"
#include "core/timing.hpp"

namespace keel::align {

SdpSolution so_conv_hull_sdp(const AlignmentProblem& p, const Regions& reg, double gap_tolerance) {
  const auto t0 = core::Clock::now();
  const std::size_t nb = p.query_size();
  if (reg.planes.size() != nb || reg.boxes.size() != nb)
    throw std::invalid_argument("so_conv_hull_sdp: the regions do not belong to this problem");
  // The dual form of convex::Sdp: maximise bᵀy s.t. C − Σ y_i A_i ⪰ 0 (the 2 × 2 block) and
  // c_lp − Σ y_i a_lp,i ≥ 0 (every plane and box as a row of the orthant). y = (c, s, tx, ty, u_1 … u_nb),
  // b = (0, 0, 0, 0, −1 … −1).
  const int m = static_cast<int>(4 + nb);
  convex::Sdp sdp;
  sdp.b.assign(static_cast<std::size_t>(m), 0.0);
  for (int i = 4; i < m; ++i) sdp.b[static_cast<std::size_t>(i)] = -1.0;
  // C − c A_c − s A_s = [[1 + c, s], [s, 1 − c]]: C = I, A_c = diag(−1, 1), A_s = −[[0, 1], [1, 0]].
  sdp.block_sizes = {2};
  sdp.c = {{0, 0, 0, 1.0}, {0, 1, 1, 1.0}};
  sdp.a.assign(static_cast<std::size_t>(m), {});
  sdp.a[0] = {{0, 0, 0, -1.0}, {0, 1, 1, 1.0}};
  sdp.a[1] = {{0, 1, 0, -1.0}};
  // LP rows a·y ≤ rhs: row r of the orthant is rhs − a·y ≥ 0, so c_lp(r) = rhs and a_lp,i(r) = a_i.
  sdp.lp_a.assign(static_cast<std::size_t>(m), {});
  int rows = 0;
  auto add = [&](const double lin[4], int u, double rhs) {
    if (rhs != 0) sdp.lp_c.push_back({rows, rhs});
    for (int k = 0; k < 4; ++k)
      if (lin[k] != 0) sdp.lp_a[static_cast<std::size_t>(k)].push_back({rows, lin[k]});
    if (u >= 0) sdp.lp_a[static_cast<std::size_t>(4 + u)].push_back({rows, -1.0});
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
  sdp.lp_size = rows;

  convex::SdpSettings settings;
  settings.solver = convex::SdpSolver::dsdp;
  settings.gap_tolerance = gap_tolerance;
  const convex::SdpSolution solved = convex::solve_sdp(sdp, settings);
  SdpSolution out;
  out.converged = solved.claims_optimal;
  out.cost = -solved.solver_dual_objective;
  out.params.assign(solved.y.data(), solved.y.data() + 4);
  out.iterations = solved.iterations;
  out.time_s = core::seconds_since(t0);
  return out;
}

}  // namespace keel::align
