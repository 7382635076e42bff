// keel::convex — a semidefinite program in one neutral form (PSD blocks and a nonnegative orthant), two
// solvers from Debian behind it (DSDP 5 and SDPA 7), and a check that recomputes every optimality measure
// from the returned iterates, so that no result of keel depends on a solver's status word. keel.sos (the
// moment relaxations of chapter 4) and keel.align (SOConvHull as an SDP, chapter 3) both solve through it.
//
// Convention (DSDP's, and SDPA's with the roles of its primal and dual exchanged):
//   primal   min ⟨C, X⟩ + c_lpᵀ x_lp   s.t.  ⟨A_i, X⟩ + a_lp,iᵀ x_lp = b_i  (i = 0 … m−1),
//                                            X ⪰ 0 (block diagonal),  x_lp ≥ 0
//   dual     max bᵀy                   s.t.  S = C − Σ_i y_i A_i ⪰ 0,  s_lp = c_lp − Σ_i y_i a_lp,i ≥ 0.
// Matrices are symmetric and given by their lower triangle: an entry (row, col, v) with row > col stands for
// v at both (row, col) and (col, row), so it counts twice in ⟨A, X⟩ = Σ_kl A_kl X_kl. The orthant is DSDP's
// LP cone and SDPA's LP (diagonal) block.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <string_view>
#include <vector>

namespace keel::convex {

struct SdpEntry {
  int block = 0, row = 0, col = 0;  // row ≥ col, both < the block's size
  double value = 0.0;
};

// An entry of a vector on the orthant: row < Sdp::lp_size.
struct LpEntry {
  int row = 0;
  double value = 0.0;
};

struct Sdp {
  std::vector<int> block_sizes;            // every block ≥ 1 (none when the program is an LP)
  std::vector<SdpEntry> c;                 // C
  std::vector<std::vector<SdpEntry>> a;    // A_i, one list per constraint (entries may repeat: they add)
  std::vector<double> b;                   // b_i, same count as a
  int lp_size = 0;                         // dimension of the orthant (0: none)
  std::vector<LpEntry> lp_c;               // c_lp
  std::vector<std::vector<LpEntry>> lp_a;  // a_lp,i: empty, or one list per constraint (entries may repeat)

  [[nodiscard]] int constraints() const { return static_cast<int>(a.size()); }
  // Throws std::invalid_argument naming the first bad entry (block or index out of range, row < col, a/b/lp_a
  // size mismatch, neither a block nor an orthant, a non-finite value).
  void validate() const;
};

enum class SdpSolver { dsdp, sdpa };
[[nodiscard]] std::string_view to_string(SdpSolver v);
[[nodiscard]] SdpSolver sdp_solver_from_string(std::string_view s);

struct SdpSettings {
  SdpSolver solver = SdpSolver::dsdp;  // which library solves
  double gap_tolerance = 1e-9;         // relative duality gap at which the solver may stop (> 0)
  int max_iterations = 500;            // interior-point iterations (> 0; DSDP's own default is 500)
  void validate() const;               // throws std::invalid_argument naming the field and value
};

// What a solver returned. `x`, `x_lp` and `y` are the solver's iterates; `claims_optimal`, `status` and
// `solver_dual_objective` are its own words, kept for the record only (check_sdp() decides).
struct SdpSolution {
  std::vector<Eigen::MatrixXd> x;  // primal X, one dense symmetric matrix per block
  Eigen::VectorXd x_lp;            // primal x_lp (size lp_size)
  Eigen::VectorXd y;               // dual multipliers, one per constraint
  bool claims_optimal = false;
  std::string status;                  // the solver's termination word, e.g. "reason 1, solution type 1"
  double solver_dual_objective = 0.0;  // bᵀy as the solver computes it (DSDP: DSDPGetDObjective)
  int iterations = 0;
  double time_s = 0.0;  // wall time of the solver call (setup + solve + extraction)
};

// Optimality measures recomputed here from the program and the returned iterates.
struct SdpCheck {
  double primal_objective = 0.0;  // ⟨C, X⟩ + c_lpᵀ x_lp
  double dual_objective = 0.0;    // bᵀy
  double primal_residual = 0.0;   // max_i |⟨A_i, X⟩ + a_lp,iᵀ x_lp − b_i| / (1 + max_i |b_i|)
  double x_min_eigenvalue = 0.0;  // smallest eigenvalue of X over all blocks, and of x_lp's entries
  double s_min_eigenvalue = 0.0;  // smallest eigenvalue of S = C − Σ y_i A_i over all blocks, and of s_lp
  double relative_gap = 0.0;      // |primal − dual| / (1 + |primal| + |dual|)
  // Slack matrices S recomputed from y, one per block (dual certificates), and the orthant's slack s_lp.
  std::vector<Eigen::MatrixXd> s;
  Eigen::VectorXd s_lp;
};

// Solves `sdp` with the chosen library. Throws std::invalid_argument for an invalid program or settings and
// std::runtime_error when the library reports an error code (naming the call). A solver that merely stops
// short of optimality returns normally: check the result with check_sdp().
[[nodiscard]] SdpSolution solve_sdp(const Sdp& sdp, const SdpSettings& settings = {});

[[nodiscard]] SdpCheck check_sdp(const Sdp& sdp, const SdpSolution& solution);

// Dense blocks of a symmetric matrix given by lower-triangle entries (for tests and the checks).
[[nodiscard]] std::vector<Eigen::MatrixXd> dense_blocks(const std::vector<int>& block_sizes,
                                                        const std::vector<SdpEntry>& entries);

namespace detail {
// Backends (dsdp.cpp, sdpa.cpp); called by solve_sdp after validation.
SdpSolution solve_with_dsdp(const Sdp& sdp, const SdpSettings& settings);
SdpSolution solve_with_sdpa(const Sdp& sdp, const SdpSettings& settings);
}  // namespace detail

}  // namespace keel::convex
