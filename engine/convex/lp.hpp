// keel::convex — a linear program kept between solves on COIN-OR CLP (Debian coinor-libclp-dev):
//
//     min cᵀx   s.t.   row_lo ≤ A x ≤ row_hi,   col_lo ≤ x ≤ col_hi,
//
// with rows added, changed or deleted between solves; each solve is CLP's dual simplex from the previous
// basis (a warm start: adding violated rows leaves the old basis dual feasible). keel.align's alignment LPs
// (lazy plane rows, sector and arc rows, the θ certificate) are built on it. One instance per thread.
#pragma once

#include <memory>
#include <vector>

class ClpSimplex;

namespace keel::convex {

inline constexpr double kLpInfinity =
    1.7976931348623157e308;  // an absent bound (CLP's infinity is max double)

// Rows in compressed form: row r has the entries (columns[k], values[k]) for k in [starts[r], starts[r + 1]).
struct LpRows {
  std::vector<double> lo, hi;  // one per row
  std::vector<int> starts{0};  // rows + 1 offsets into columns/values
  std::vector<int> columns;
  std::vector<double> values;
  [[nodiscard]] int size() const { return static_cast<int>(lo.size()); }
  // Appends a row with its non-zero entries (columns must be distinct).
  void add(double row_lo, double row_hi, const std::vector<int>& cols, const std::vector<double>& vals);
};

// cut_off: the dual simplex proved the optimum above the objective limit given to solve() and stopped there.
enum class LpStatus { optimal, infeasible, failed, cut_off };

struct LpOptions {
  // Dantzig's rule for the dual simplex's leaving row instead of CLP's steepest edge (about 20 % faster on
  // the alignment LPs, whose rows change between every solve).
  bool dantzig_dual_pricing = false;
  // CLP's scaling of rows and columns. Off where it misleads the dual simplex: on keel.align's LPs (objective
  // on the transform's columns of order 10³, unit elsewhere) CLP stopped with secondary status 3, "optimal"
  // for the scaled problem but dual infeasible unscaled, up to 2 % above the optimum. solve() reports such a
  // stop as LpStatus::failed, never as optimal.
  bool scaling = true;
};

class Lp {
 public:
  // Columns with their costs and bounds (±kLpInfinity for none), no rows yet.
  Lp(const std::vector<double>& cost, const std::vector<double>& col_lo, const std::vector<double>& col_hi,
     const LpOptions& options = {});
  ~Lp();
  Lp(Lp&&) noexcept;
  Lp& operator=(Lp&&) noexcept;
  Lp(const Lp&) = delete;
  Lp& operator=(const Lp&) = delete;

  [[nodiscard]] int rows() const;
  [[nodiscard]] int columns() const;
  // Appends rows; returns the index of the first.
  int add_rows(const LpRows& rows);
  void delete_rows(const std::vector<int>& rows);
  // Changes one coefficient of A, keeping the entry (and the basis) even when the value is zero.
  void set_coefficient(int row, int column, double value);
  void set_row_bounds(int row, double lo, double hi);
  void set_column_bounds(int column, double lo, double hi);

  // Re-solves by the dual simplex from the current basis. With an objective limit, the solve stops as soon as
  // the dual simplex proves the optimum is above it (its objective, a dual bound, exceeds the limit with no
  // variable at an artificial bound; CLP's dual objective limit) and returns LpStatus::cut_off.
  LpStatus solve(double objective_limit = kLpInfinity);
  // The basis (CLP's status of every column and row), and a restore of it: rows added since start with their
  // slack basic. Restoring a basis and then only tightening bounds or adding rows keeps it dual feasible, a
  // warm start for the dual simplex.
  [[nodiscard]] std::vector<unsigned char> basis() const;
  void set_basis(const std::vector<unsigned char>& basis);
  // Of the last solve: simplex iterations, objective cᵀx and the primal solution x (columns() entries).
  [[nodiscard]] int iterations() const;
  [[nodiscard]] double objective() const;
  [[nodiscard]] const double* solution() const;
  // Of the last solve: the row duals y (rows() entries), with cost = Aᵀy + reduced costs (CLP's convention).
  [[nodiscard]] const double* row_duals() const;

 private:
  std::unique_ptr<ClpSimplex> model_;
};

}  // namespace keel::convex
