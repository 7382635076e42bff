// The alignment linear program of eqs. 3.5–3.8 and 3.19 on COIN-OR CLP (convex::Lp), with lazy rows.
//
// Columns: the transform parameters, then one epigraph variable u_j per query point. For the rotation-like
// parameterisations the parameters are (c, s, tx, ty) with A = [[c, −s], [s, c]] (eq. 3.11 without the norm
// constraint); for the affine one (a11, a12, a21, a22, tx, ty). Query point j maps to (f_j, g_j) = A p_j + t
// (eqs. 3.6–3.7), and every plane m of its lower hull gives the row
//     r_m f_j + s_m g_j + t_m − u_j ≤ 0                                                     (eq. 3.8)
// which is linear in (A, t, u). The objective is Σ_j u_j (eq. 3.19). Each transformed point is also kept
// inside its region-of-interest box lo ≤ (f_j, g_j) ≤ hi (two ranged rows per point): the planes are lower
// bounds of the dissimilarity only over the box their cloud was taken from.
//
// Rows are generated lazily. Each query point starts with its base plane m0_j (the one maximal at the centre
// of its box) held as a bound: the model's column is v_j = u_j − plane_m0_j(f_j, g_j) ≥ 0, so the starting
// basis is dual feasible and a point whose base plane stays active costs no pivot (see the constructor).
// After each solve the most violated plane of every query point (and each box row the solution violates) is
// added and the LP re-solved warm by the dual simplex, until nothing is violated. The result is the optimum
// of the full LP (every omitted row is satisfied). One ClpSimplex per instance: instances are not shared
// between threads.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "align/hull.hpp"
#include "convex/lp.hpp"

namespace keel::align {

enum class Parameterization { rotation_like, affine };

// A linear constraint lo ≤ a_c c + a_s s ≤ hi on the (c, s) columns (rotation-like parameterisations only).
struct CsRow {
  double a_c = 0.0, a_s = 0.0, lo = 0.0, hi = 0.0;
};

// An axis-aligned box lo ≤ (x, y) ≤ hi of the reference frame.
struct Box {
  double x_lo = 0.0, x_hi = 0.0, y_lo = 0.0, y_hi = 0.0;
};

struct LpSettings {
  double violation_tolerance =
      1e-9;                         // a plane is violated when it exceeds u_j by more than this × (1 + |u_j|)
  int max_generation_rounds = 500;  // re-solves allowed before giving up
  double matrix_bound = 10.0;       // |entries of A| ≤ this (the boxes bound them anyway; keeps LPs bounded)
  bool lazy_boxes = true;           // box rows only once violated (false: all from the start; better when the
                                    // boxes bind, as in the shrinking rounds)
  double disc_tolerance = 0.0;      // > 0: keep (c, s) in the unit disc by tangent cuts until
                                    // hypot(c, s) ≤ 1 + disc_tolerance (conv SO(2), eq. 3.12)
};

// cut_off: a relaxation of the LP (its rows so far) already has an optimum above the cutoff given to solve(),
// so the LP's own optimum is above it too; the solve stopped there.
enum class LpStatus { optimal, infeasible, failed, cut_off };

struct LpSolution {
  LpStatus status = LpStatus::failed;
  double cost = 0.0;           // Σ u_j
  std::vector<double> params;  // (c, s, tx, ty) or (a11, a12, a21, a22, tx, ty)
  int solves = 0;              // LP solves (1 + generation rounds)
  int iterations = 0;          // simplex iterations over all solves
  std::size_t plane_rows = 0;  // plane rows in the model at the end
  std::size_t cuts = 0;        // disc tangent cuts in the model at the end
  // Optimal solves of the rotation-like parameterisation with (c, s) rows: λ = Σ_i y_i (a_c, a_s)_i over
  // those rows, their multipliers' gradient. Relaxing the rows with their multipliers bounds the LP without
  // them (plane, box and column bounds only) at every (c, s) = p: V(p) ≥ cost + λ · (p − (c, s)*) (Lagrangian
  // duality; exact up to the solver's tolerances).
  double cs_gradient[2] = {0.0, 0.0};
};

class HullLp {
 public:
  // `planes[j]` is the lower hull of query point j over its box `boxes[j]`; (qx, qy) are the query positions
  // in the query frame. Planes and boxes are referenced, not copied: they must outlive the instance.
  HullLp(Parameterization kind, const std::vector<double>& qx, const std::vector<double>& qy,
         const std::vector<std::vector<Plane>>& planes, const std::vector<Box>& boxes,
         const LpSettings& settings);
  ~HullLp();
  HullLp(const HullLp&) = delete;
  HullLp& operator=(const HullLp&) = delete;

  // Replaces the extra (c, s) rows (sector constraints, arc relaxations); rotation-like only.
  void set_cs_rows(const std::vector<CsRow>& rows);
  // Fixes (c, s) to a value (both bounds), or frees them to ±matrix_bound.
  void fix_cs(double c, double s);
  void free_cs();

  // Solves with lazy plane rows (and disc cuts when settings.disc_tolerance > 0). Every intermediate solve is
  // the optimum of a relaxation (a subset of the rows), hence a lower bound on the LP's optimum: once one
  // exceeds `cutoff` the solve stops with LpStatus::cut_off (used to skip sectors that cannot win).
  [[nodiscard]] LpSolution solve(double cutoff = convex::kLpInfinity);

  // The model's basis and a restore of it (convex::Lp::basis); rows added since start with their slack basic.
  [[nodiscard]] std::vector<unsigned char> basis() const { return model_->basis(); }
  void set_basis(const std::vector<unsigned char>& b) { model_->set_basis(b); }

  [[nodiscard]] std::size_t parameter_count() const { return kind_ == Parameterization::affine ? 6 : 4; }

 private:
  void add_plane_row(std::size_t j, std::size_t m);
  void add_planes(const std::vector<std::pair<std::size_t, std::size_t>>& rows);
  void add_box_rows(const std::vector<std::size_t>& which);

  Parameterization kind_;
  const std::vector<double>& qx_;
  const std::vector<double>& qy_;
  const std::vector<std::vector<Plane>>& planes_;
  const std::vector<Box>& boxes_;
  LpSettings settings_;
  std::unique_ptr<convex::Lp> model_;
  std::vector<std::vector<bool>> in_model_;  // plane (j, m) has a row (or is j's base plane)
  std::vector<std::size_t> base_;            // base plane m0_j of each query point (u_j = v_j + plane_m0_j)
  double constant_ = 0;                      // Σ_j t of the base planes: the objective's constant
  std::vector<bool> box_in_model_;           // box row 2j (x) / 2j + 1 (y) is in the model
  std::size_t plane_rows_ = 0, cuts_ = 0;
  std::vector<int> cs_row_index_;  // rows holding the current CsRows
  std::vector<CsRow> cs_rows_;     // their coefficients and bounds
  bool solved_once_ = false;
};

}  // namespace keel::align
