// keel::sos — a block-diagonal semidefinite program in one neutral form, two solvers from Debian behind it
// (DSDP 5 and SDPA 7), and a check that recomputes every optimality measure from the returned matrices, so
// that no result of keel depends on a solver's status word.
//
// Convention (DSDP's, and SDPA's with the roles of its primal and dual exchanged):
//   primal   min ⟨C, X⟩        s.t.  ⟨A_i, X⟩ = b_i  (i = 0 … m−1),   X ⪰ 0 (block diagonal)
//   dual     max bᵀy           s.t.  S = C − Σ_i y_i A_i ⪰ 0.
// Matrices are symmetric and given by their lower triangle: an entry (row, col, v) with row > col stands for
// v at both (row, col) and (col, row), so it counts twice in ⟨A, X⟩ = Σ_kl A_kl X_kl.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <string_view>
#include <vector>

namespace keel::sos {

struct SdpEntry {
  int block = 0, row = 0, col = 0;  // row ≥ col, both < the block's size
  double value = 0.0;
};

struct Sdp {
  std::vector<int> block_sizes;          // every block ≥ 1
  std::vector<SdpEntry> c;               // C
  std::vector<std::vector<SdpEntry>> a;  // A_i, one list per constraint (entries may repeat: they add)
  std::vector<double> b;                 // b_i, same count as a

  [[nodiscard]] int constraints() const { return static_cast<int>(a.size()); }
  // Throws std::invalid_argument naming the first bad entry (block or index out of range, row < col, a/b size
  // mismatch, an empty block list, a non-finite value).
  void validate() const;
};

enum class SdpSolver { dsdp, sdpa };
[[nodiscard]] std::string_view to_string(SdpSolver v);
[[nodiscard]] SdpSolver sdp_solver_from_string(std::string_view s);

struct SdpSettings {
  SdpSolver solver = SdpSolver::dsdp;  // which library solves
  double gap_tolerance = 1e-9;         // relative duality gap at which the solver may stop (> 0)
  int max_iterations = 500;            // interior-point iterations (> 0)
  void validate() const;               // throws std::invalid_argument naming the field and value
};

// What a solver returned. `x` and `y` are the solver's iterates; `claims_optimal` and `status` are its own
// words, kept for the record only (check_sdp() decides).
struct SdpSolution {
  std::vector<Eigen::MatrixXd> x;  // primal X, one dense symmetric matrix per block
  Eigen::VectorXd y;               // dual multipliers, one per constraint
  bool claims_optimal = false;
  std::string status;  // the solver's termination word, e.g. "DSDP_CONVERGED/PDFEASIBLE"
  int iterations = 0;
  double time_s = 0.0;  // wall time of the solver call (setup + solve + extraction)
};

// Optimality measures recomputed here from C, A, b, X and y.
struct SdpCheck {
  double primal_objective = 0.0;  // ⟨C, X⟩
  double dual_objective = 0.0;    // bᵀy
  double primal_residual = 0.0;   // max_i |⟨A_i, X⟩ − b_i| / (1 + max_i |b_i|)
  double x_min_eigenvalue = 0.0;  // smallest eigenvalue of X over all blocks
  double s_min_eigenvalue = 0.0;  // smallest eigenvalue of S = C − Σ y_i A_i over all blocks
  double relative_gap = 0.0;      // |⟨C, X⟩ − bᵀy| / (1 + |⟨C, X⟩| + |bᵀy|)
  // Slack matrices S recomputed from y, one per block (dual certificates).
  std::vector<Eigen::MatrixXd> s;
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
// Backends (sdp.cpp, sdpa.cpp); called by solve_sdp after validation.
SdpSolution solve_with_dsdp(const Sdp& sdp, const SdpSettings& settings);
SdpSolution solve_with_sdpa(const Sdp& sdp, const SdpSettings& settings);
}  // namespace detail

}  // namespace keel::sos
