// The SDPA 7 backend of keel::convex (Debian libsdpa-dev).
//
// SDPA's own pair is   primal  min Σ_i c_i x_i  s.t.  Σ_i F_i x_i − F_0 ⪰ 0
//                      dual    max ⟨F_0, Y⟩      s.t.  ⟨F_i, Y⟩ = c_i,  Y ⪰ 0,
// so keel's form (sdp.hpp) maps onto it with the roles of primal and dual exchanged:
//   F_0 = −C,  F_i = A_i,  c_i = b_i;   keel's X = SDPA's Y (YMat),  keel's y = −SDPA's x (xVec),
// and SDPA's primal slack Σ F_i x_i − F_0 (XMat) is keel's S = C − Σ y_i A_i. SDPA reads the upper triangle
// of each symmetric F_i with 1-based indices, and an off-diagonal entry stands for both (i, j) and (j, i), as
// in keel. The orthant is one more block of SDPA's LP type (a diagonal block, entries (r, r)), after the PSD
// blocks.
#include "convex/sdp.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <tuple>

#include "core/timing.hpp"

// Last: SDPA's headers say `using namespace std;` at global scope and define macros (rError, NewArray, ...).
// rError prints and calls exit(): what SDPA checks that way is checked first (indices and sizes by
// Sdp::validate() in solve_sdp, m > 0 below).
#include <sdpa_call.h>

namespace keel::convex::detail {

namespace {
// SDPA's solver object is self-contained, but the library reports through std::cout and has never been
// documented as thread-safe: calls are serialised.
std::mutex sdpa_mutex;

// With no display file SDPA is silent except for its rMessage lines ("cannot move: step length is too short",
// "maxIteration is reached", ...), which go to std::cout. They are redirected into a buffer for the duration
// of a call; std::cout is a stream, so this touches neither file descriptor 1 nor the DSDP backend's
// redirection of it.
class CaptureCout {
 public:
  CaptureCout() : saved_(std::cout.rdbuf(buffer_.rdbuf())) {}
  ~CaptureCout() { std::cout.rdbuf(saved_); }
  CaptureCout(const CaptureCout&) = delete;
  CaptureCout& operator=(const CaptureCout&) = delete;

 private:
  std::ostringstream buffer_;
  std::streambuf* saved_;
};

// An entry as SDPA takes it: (block, row, col) 1-based with row ≤ col. Entries are summed per position first
// (SDPA would keep repeats as separate non-zeros) and exact zeros dropped.
struct Element {
  int block, row, col;
  double value;
};

// Sorted by (block, row, col), repeats summed, exact zeros dropped.
std::vector<Element> merged(std::vector<Element> out) {
  std::sort(out.begin(), out.end(), [](const Element& a, const Element& b) {
    return std::tie(a.block, a.row, a.col) < std::tie(b.block, b.row, b.col);
  });
  std::size_t n = 0;
  for (std::size_t k = 0; k < out.size(); ++k) {
    if (n > 0 && out[n - 1].block == out[k].block && out[n - 1].row == out[k].row &&
        out[n - 1].col == out[k].col)
      out[n - 1].value += out[k].value;
    else
      out[n++] = out[k];
  }
  out.resize(n);
  std::erase_if(out, [](const Element& e) { return e.value == 0.0; });
  return out;
}

// The upper triangle of one symmetric matrix as SDPA takes it, (block, row, col) 1-based with row ≤ col.
std::vector<Element> upper_triangle(const std::vector<SdpEntry>& entries, double sign) {
  std::vector<Element> out;
  out.reserve(entries.size());
  for (const SdpEntry& e : entries) out.push_back({e.block + 1, e.col + 1, e.row + 1, sign * e.value});
  return merged(std::move(out));
}

// The orthant's vector as the diagonal of SDPA's LP block `block` (1-based).
std::vector<Element> diagonal(const std::vector<LpEntry>& entries, int block, double sign) {
  std::vector<Element> out;
  out.reserve(entries.size());
  for (const LpEntry& e : entries) out.push_back({block, e.row + 1, e.row + 1, sign * e.value});
  return merged(std::move(out));
}

const double* result(const double* p, std::string_view what) {
  if (p == nullptr)
    throw std::runtime_error(fmt::format("convex::solve_sdp: SDPA {} returned no data", what));
  return p;
}
}  // namespace

SdpSolution solve_with_sdpa(const Sdp& sdp, const SdpSettings& settings) {
  const int m = sdp.constraints();
  const int blocks = static_cast<int>(sdp.block_sizes.size());
  const int lp_block = sdp.lp_size > 0 ? blocks + 1 : 0;  // 1-based SDPA block of the orthant, 0: none
  // SDPA ends the process (exit in its rError) on m = 0: refused here.
  if (m == 0) throw std::invalid_argument("convex::solve_sdp: SDPA needs at least one constraint (m = 0)");

  std::lock_guard<std::mutex> lock(sdpa_mutex);
  const auto t0 = core::Clock::now();  // after the lock: time_s is this call's work, not the wait for another
  CaptureCout quiet;
  SDPA sdpa;
  // No progress table, no result file (both default to none; set for clarity).
  sdpa.setDisplay(nullptr);
  sdpa.setResultFile(nullptr);
  // The stable set (initial point λ* I with λ* = 1e4 instead of 1e2, β̄ = 0.3, γ* = 0.8: shorter, safer
  // steps): with the default set SDPA once stopped as "pdOPT" 45 % off the optimum on a badly scaled
  // instance, and here it calls a circle problem scaled by 1e6 infeasible, which the stable set solves.
  sdpa.setParameterType(SDPA::PARAMETER_STABLE_BUT_SLOW);
  sdpa.setParameterEpsilonStar(settings.gap_tolerance);  // relative duality gap
  sdpa.setParameterEpsilonDash(settings.gap_tolerance);  // relative primal and dual infeasibility
  sdpa.setParameterMaxIteration(settings.max_iterations);
  // SDPA stops as "unbounded" once a feasible iterate's objective passes ±1e5 (its default bounds), which cut
  // off a feasible program with optimum 2.8e6; objectives are not bounded a priori here, so the test is off.
  sdpa.setParameterLowerBound(-1e100);
  sdpa.setParameterUpperBound(1e100);
  // SDPA's own threads only split the Schur complement; one keeps runs reproducible and leaves the cores to
  // keel's callers (BLAS threading is OpenBLAS's, unchanged).
  sdpa.setNumThreads(1);

  sdpa.inputConstraintNumber(m);
  sdpa.inputBlockNumber(blocks + (lp_block > 0 ? 1 : 0));
  for (int l = 0; l < blocks; ++l) {
    sdpa.inputBlockSize(l + 1, sdp.block_sizes[static_cast<std::size_t>(l)]);
    sdpa.inputBlockType(l + 1, SDPA::SDP);
  }
  if (lp_block > 0) {
    sdpa.inputBlockSize(lp_block, sdp.lp_size);
    sdpa.inputBlockType(lp_block, SDPA::LP);
  }
  sdpa.initializeUpperTriangleSpace();
  for (int i = 0; i < m; ++i) sdpa.inputCVec(i + 1, sdp.b[static_cast<std::size_t>(i)]);
  for (const Element& e : upper_triangle(sdp.c, -1.0)) sdpa.inputElement(0, e.block, e.row, e.col, e.value);
  for (int i = 0; i < m; ++i)
    for (const Element& e : upper_triangle(sdp.a[static_cast<std::size_t>(i)], 1.0))
      sdpa.inputElement(i + 1, e.block, e.row, e.col, e.value);
  if (lp_block > 0) {
    for (const Element& e : diagonal(sdp.lp_c, lp_block, -1.0))
      sdpa.inputElement(0, e.block, e.row, e.col, e.value);
    for (std::size_t i = 0; i < sdp.lp_a.size(); ++i)
      for (const Element& e : diagonal(sdp.lp_a[i], lp_block, 1.0))
        sdpa.inputElement(static_cast<int>(i) + 1, e.block, e.row, e.col, e.value);
  }
  sdpa.initializeUpperTriangle();
  sdpa.initializeSolve();
  sdpa.solve();

  SdpSolution out;
  out.x.reserve(static_cast<std::size_t>(blocks));
  for (int l = 0; l < blocks; ++l) {
    const int n = sdp.block_sizes[static_cast<std::size_t>(l)];
    // Dense, column-major, both triangles.
    const Eigen::Map<const Eigen::MatrixXd> y_mat(
        result(sdpa.getResultYMat(l + 1), fmt::format("getResultYMat({})", l + 1)), n, n);
    out.x.emplace_back(0.5 * (y_mat + y_mat.transpose()));
  }
  if (lp_block > 0)  // an LP block's YMat is its diagonal
    out.x_lp = Eigen::Map<const Eigen::VectorXd>(
        result(sdpa.getResultYMat(lp_block), fmt::format("getResultYMat({})", lp_block)), sdp.lp_size);
  out.y = -Eigen::Map<const Eigen::VectorXd>(result(sdpa.getResultXVec(), "getResultXVec()"), m);
  out.solver_dual_objective = -sdpa.getPrimalObj();  // SDPA's primal is keel's dual, with x = −y
  out.claims_optimal = sdpa.getPhaseValue() == SDPA::pdOPT;
  // SDPA's word as it prints it, in its own terms: "p" is SDPA's primal, which is keel's dual (and "d" keel's
  // primal). getPhaseValue() is not used for the word: it exchanges the infeasible and unbounded words a
  // second time and contradicts the printed phase.
  char phase[32] = {};
  sdpa.getPhaseString(phase);
  out.status = phase;
  while (!out.status.empty() && out.status.back() == ' ') out.status.pop_back();
  out.iterations = sdpa.getIteration();
  out.time_s = core::seconds_since(t0);
  return out;
}

}  // namespace keel::convex::detail
