#include "align/lp.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace keel::align {

namespace {

// Coefficients of f_j = (A p + t)_x and g_j = (A p + t)_y on the parameter columns.
struct Lin {
  double v[6] = {0, 0, 0, 0, 0, 0};
};

void coordinate_rows(Parameterization kind, double x, double y, Lin& f, Lin& g) {
  f = Lin{};
  g = Lin{};
  if (kind == Parameterization::affine) {  // (a11, a12, a21, a22, tx, ty)
    f.v[0] = x, f.v[1] = y, f.v[4] = 1;
    g.v[2] = x, g.v[3] = y, g.v[5] = 1;
  } else {  // (c, s, tx, ty): f = c x − s y + tx, g = s x + c y + ty
    f.v[0] = x, f.v[1] = -y, f.v[2] = 1;
    g.v[0] = y, g.v[1] = x, g.v[3] = 1;
  }
}

constexpr double kInf = convex::kLpInfinity;

}  // namespace

HullLp::HullLp(Parameterization kind, const std::vector<double>& qx, const std::vector<double>& qy,
               const std::vector<std::vector<Plane>>& planes, const std::vector<Box>& boxes,
               const LpSettings& settings)
    : kind_(kind), qx_(qx), qy_(qy), planes_(planes), boxes_(boxes), settings_(settings) {
  const std::size_t nb = qx.size();
  if (qy.size() != nb || planes.size() != nb || boxes.size() != nb)
    throw std::invalid_argument(
        "HullLp: query positions, planes and boxes must have one entry per query point");
  const int k = static_cast<int>(parameter_count());
  const int ncol = k + static_cast<int>(nb);
  // The base plane m0_j of each query point: the one maximal at the centre of its box (in the shrinking
  // rounds, where the previous round put the point). The epigraph variable is written u_j = v_j +
  // plane_m0_j(f_j, g_j) with v_j ≥ 0, so the base plane's row r f + s g − u ≤ −t is the bound v_j ≥ 0 and
  // the objective Σ u_j = Σ v_j + Σ_j plane_m0_j(f_j, g_j) gains linear terms on the parameters and a
  // constant. Every column is then bounded below or boxed and the starting basis (all v_j at 0, parameters at
  // the bound their cost points to) is dual feasible: the dual simplex starts from a proper basis instead of
  // CLP's artificial bounds on free columns, and a point whose base plane stays active costs no pivot.
  base_.resize(nb);
  in_model_.resize(nb);
  for (std::size_t j = 0; j < nb; ++j) {
    if (planes[j].empty()) throw std::invalid_argument(fmt::format("HullLp: query point {} has no plane", j));
    in_model_[j].assign(planes[j].size(), false);
    const Box& b = boxes[j];
    const double cx = 0.5 * (b.x_lo + b.x_hi), cy = 0.5 * (b.y_lo + b.y_hi);
    std::size_t best = 0;
    double bv = -kInf;
    for (std::size_t m = 0; m < planes[j].size(); ++m) {
      const double v = planes[j][m].at(cx, cy);
      if (v > bv) bv = v, best = m;
    }
    base_[j] = best;
    in_model_[j][best] = true;
    ++plane_rows_;
  }
  std::vector<double> collb(ncol, -kInf), colub(ncol, kInf), obj(ncol, 0.0);
  const int nmat = kind == Parameterization::affine ? 4 : 2;
  for (int p = 0; p < nmat; ++p) collb[p] = -settings.matrix_bound, colub[p] = settings.matrix_bound;
  constant_ = 0;
  for (std::size_t j = 0; j < nb; ++j) {
    obj[k + j] = 1.0;
    collb[k + j] = 0.0;
    const Plane& pl = planes[j][base_[j]];
    Lin f, g;
    coordinate_rows(kind, qx[j], qy[j], f, g);
    for (int p = 0; p < k; ++p) obj[p] += pl.r * f.v[p] + pl.s * g.v[p];
    constant_ += pl.t;
  }
  // Translation bounds implied by the boxes: t_x = f_j − (A p_j)_x with f_j in box j and |entries of A| ≤ B,
  // so t_x ∈ [x_lo − B(|x_j| + |y_j|), x_hi + B(|x_j| + |y_j|)] for every j; the tightest j bounds the LP
  // before its box rows arrive.
  {
    double tx_lo = -kInf, tx_hi = kInf, ty_lo = -kInf, ty_hi = kInf;
    for (std::size_t j = 0; j < nb; ++j) {
      const double reach = settings.matrix_bound * (std::abs(qx[j]) + std::abs(qy[j]));
      tx_lo = std::max(tx_lo, boxes[j].x_lo - reach), tx_hi = std::min(tx_hi, boxes[j].x_hi + reach);
      ty_lo = std::max(ty_lo, boxes[j].y_lo - reach), ty_hi = std::min(ty_hi, boxes[j].y_hi + reach);
    }
    const int tcol = k - 2;
    collb[tcol] = tx_lo, colub[tcol] = tx_hi, collb[tcol + 1] = ty_lo, colub[tcol + 1] = ty_hi;
  }
  convex::LpOptions lp_options;
  lp_options.dantzig_dual_pricing = true;  // about 20 % faster than CLP's steepest edge here (bench_align)
  lp_options.scaling = false;              // see convex::LpOptions::scaling
  model_ = std::make_unique<convex::Lp>(obj, collb, colub, lp_options);

  // Box rows lo ≤ f_j ≤ hi, lo ≤ g_j ≤ hi are added lazily too, when the solution leaves a box.
  box_in_model_.assign(2 * nb, false);
  if (!settings.lazy_boxes) {
    std::vector<std::size_t> all(2 * nb);
    for (std::size_t w = 0; w < all.size(); ++w) all[w] = w;
    add_box_rows(all);
  }
}

HullLp::~HullLp() = default;

void HullLp::add_planes(const std::vector<std::pair<std::size_t, std::size_t>>& rows) {
  if (rows.empty()) return;
  const int k = static_cast<int>(parameter_count());
  convex::LpRows add;
  std::vector<double> el;
  std::vector<int> col;
  for (const auto& [j, m] : rows) {
    if (in_model_[j][m]) continue;
    in_model_[j][m] = true;
    const Plane& pl = planes_[j][m];
    const Plane& base = planes_[j][base_[j]];
    Lin f, g;
    coordinate_rows(kind_, qx_[j], qy_[j], f, g);
    col.clear();
    el.clear();
    for (int p = 0; p < k; ++p) {
      const double v = (pl.r - base.r) * f.v[p] + (pl.s - base.s) * g.v[p];
      if (v != 0) col.push_back(p), el.push_back(v);
    }
    col.push_back(k + static_cast<int>(j));
    el.push_back(-1.0);
    // plane_m(f, g) ≤ u = v + plane_m0(f, g):  (r − r0) f + (s − s0) g − v ≤ t0 − t
    add.add(-kInf, base.t - pl.t, col, el);
    ++plane_rows_;
  }
  model_->add_rows(add);
}

void HullLp::add_box_rows(const std::vector<std::size_t>& which) {
  if (which.empty()) return;
  const int k = static_cast<int>(parameter_count());
  convex::LpRows add;
  std::vector<double> el;
  std::vector<int> col;
  for (std::size_t w : which) {
    const std::size_t j = w / 2;
    const bool is_x = w % 2 == 0;
    box_in_model_[w] = true;
    Lin f, g;
    coordinate_rows(kind_, qx_[j], qy_[j], f, g);
    const Lin& l = is_x ? f : g;
    col.clear();
    el.clear();
    for (int p = 0; p < k; ++p)
      if (l.v[p] != 0) col.push_back(p), el.push_back(l.v[p]);
    add.add(is_x ? boxes_[j].x_lo : boxes_[j].y_lo, is_x ? boxes_[j].x_hi : boxes_[j].y_hi, col, el);
  }
  model_->add_rows(add);
}

void HullLp::set_cs_rows(const std::vector<CsRow>& rows) {
  if (kind_ != Parameterization::rotation_like)
    throw std::logic_error("HullLp::set_cs_rows: only for the rotation-like parameterisation");
  if (cs_row_index_.size() == rows.size()) {
    // Same number of rows: change bounds and (only where they differ) coefficients in place, so the basis
    // survives; with equal coefficients it stays dual feasible, a proper warm start for the dual simplex.
    // The elements of (c, s) are kept even when zero.
    for (std::size_t k = 0; k < rows.size(); ++k) {
      if (rows[k].a_c != cs_rows_[k].a_c) model_->set_coefficient(cs_row_index_[k], 0, rows[k].a_c);
      if (rows[k].a_s != cs_rows_[k].a_s) model_->set_coefficient(cs_row_index_[k], 1, rows[k].a_s);
      model_->set_row_bounds(cs_row_index_[k], rows[k].lo, rows[k].hi);
    }
    cs_rows_ = rows;
    return;
  }
  model_->delete_rows(cs_row_index_);
  cs_row_index_.clear();
  cs_rows_ = rows;
  if (rows.empty()) return;
  convex::LpRows add;
  const int base = model_->rows();
  for (const CsRow& r : rows) {
    add.add(r.lo, r.hi, {0, 1}, {r.a_c, r.a_s});
    cs_row_index_.push_back(base + static_cast<int>(cs_row_index_.size()));
  }
  model_->add_rows(add);
}

void HullLp::fix_cs(double c, double s) {
  model_->set_column_bounds(0, c, c);
  model_->set_column_bounds(1, s, s);
}

void HullLp::free_cs() {
  model_->set_column_bounds(0, -settings_.matrix_bound, settings_.matrix_bound);
  model_->set_column_bounds(1, -settings_.matrix_bound, settings_.matrix_bound);
}

LpSolution HullLp::solve(double cutoff) {
  LpSolution out;
  const std::size_t nb = qx_.size();
  const int k = static_cast<int>(parameter_count());
  std::vector<std::pair<std::size_t, std::size_t>> add;
  std::vector<std::size_t> box_add;
  for (int round = 0; round <= settings_.max_generation_rounds; ++round) {
    const convex::LpStatus status = model_->solve(cutoff < kInf ? cutoff - constant_ : kInf);
    ++out.solves;
    out.iterations += model_->iterations();
    if (status == convex::LpStatus::cut_off) {
      out.status = LpStatus::cut_off;
      out.cost = model_->objective() + constant_;
      return out;
    }
    if (status == convex::LpStatus::infeasible) {
      out.status = LpStatus::infeasible;
      return out;
    }
    if (status != convex::LpStatus::optimal) {
      out.status = LpStatus::failed;
      return out;
    }
    if (model_->objective() + constant_ > cutoff) {
      out.status = LpStatus::cut_off;
      out.cost = model_->objective() + constant_;
      return out;
    }
    const double* x = model_->solution();
    add.clear();
    box_add.clear();
    for (std::size_t j = 0; j < nb; ++j) {
      Lin f, g;
      coordinate_rows(kind_, qx_[j], qy_[j], f, g);
      double fx = 0, gx = 0;
      for (int p = 0; p < k; ++p) fx += f.v[p] * x[p], gx += g.v[p] * x[p];
      const double u = x[k + j] + planes_[j][base_[j]].at(fx, gx);
      std::size_t best = 0;
      double bv = -kInf;
      for (std::size_t m = 0; m < planes_[j].size(); ++m) {
        const double v = planes_[j][m].at(fx, gx);
        if (v > bv) bv = v, best = m;
      }
      if (bv - u > settings_.violation_tolerance * (1.0 + std::abs(u)) && !in_model_[j][best])
        add.emplace_back(j, best);
      const Box& b = boxes_[j];
      const double tol = settings_.violation_tolerance;
      if (!box_in_model_[2 * j] &&
          (fx < b.x_lo - tol * (1 + std::abs(b.x_lo)) || fx > b.x_hi + tol * (1 + std::abs(b.x_hi))))
        box_add.push_back(2 * j);
      if (!box_in_model_[2 * j + 1] &&
          (gx < b.y_lo - tol * (1 + std::abs(b.y_lo)) || gx > b.y_hi + tol * (1 + std::abs(b.y_hi))))
        box_add.push_back(2 * j + 1);
    }
    bool cut = false;
    if (settings_.disc_tolerance > 0 && kind_ == Parameterization::rotation_like) {
      const double n = std::hypot(x[0], x[1]);
      if (n > 1.0 + settings_.disc_tolerance) {  // tangent of the unit circle at the angle of (c, s)
        const double a = std::atan2(x[1], x[0]);
        convex::LpRows tangent;
        tangent.add(-kInf, 1.0, {0, 1}, {std::cos(a), std::sin(a)});
        model_->add_rows(tangent);
        ++cuts_;
        cut = true;
      }
    }
    if (add.empty() && box_add.empty() && !cut) {
      out.status = LpStatus::optimal;
      out.cost = model_->objective() + constant_;
      out.params.assign(x, x + k);
      if (const double* y = model_->row_duals(); y != nullptr)
        for (std::size_t r = 0; r < cs_row_index_.size(); ++r) {
          out.cs_gradient[0] += y[cs_row_index_[r]] * cs_rows_[r].a_c;
          out.cs_gradient[1] += y[cs_row_index_[r]] * cs_rows_[r].a_s;
        }
      out.plane_rows = plane_rows_;
      out.cuts = cuts_;
      solved_once_ = true;
      return out;
    }
    add_planes(add);
    add_box_rows(box_add);
  }
  out.status = LpStatus::failed;
  return out;
}

}  // namespace keel::align
