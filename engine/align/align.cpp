#include "align/align.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "core/names.hpp"
#include "core/parallel.hpp"
#include "core/timing.hpp"

namespace keel::align {

namespace {

constexpr core::NameTable<Method, 4> kMethodNames{"align::Method",
                                                  {{{Method::proposed, "proposed"},
                                                    {Method::so_conv_hull, "so_conv_hull"},
                                                    {Method::symmetric, "symmetric"},
                                                    {Method::affine, "affine"}}}};

constexpr double kPi = 3.14159265358979323846;

Transform2 transform_from(Parameterization kind, const std::vector<double>& p) {
  if (kind == Parameterization::affine) return {p[0], p[1], p[2], p[3], p[4], p[5]};
  return {p[0], -p[1], p[1], p[0], p[2], p[3]};
}

struct Bounds {
  double x_lo, x_hi, y_lo, y_hi;
};
Bounds bounding_box(const std::vector<double>& x, const std::vector<double>& y) {
  Bounds b{x[0], x[0], y[0], y[0]};
  for (std::size_t i = 1; i < x.size(); ++i) {
    b.x_lo = std::min(b.x_lo, x[i]), b.x_hi = std::max(b.x_hi, x[i]);
    b.y_lo = std::min(b.y_lo, y[i]), b.y_hi = std::max(b.y_hi, y[i]);
  }
  return b;
}

bool gated(const AlignmentProblem& p, double gate, std::size_t i, std::size_t j) {
  return gate <= 0 || p.ref_z.empty() || std::abs(p.ref_z[i] - p.query_z[j]) <= gate;
}

// The reference points inside `box` that pass the depth gate for query point j, ascending.
std::vector<std::uint32_t> points_in_box(const AlignmentProblem& p, const AlignOptions& o, std::size_t j,
                                         const Box& box) {
  std::vector<std::uint32_t> in;
  for (std::size_t i = 0; i < p.reference_size(); ++i) {
    if (p.ref_x[i] < box.x_lo || p.ref_x[i] > box.x_hi || p.ref_y[i] < box.y_lo || p.ref_y[i] > box.y_hi)
      continue;
    if (!gated(p, o.depth_gate, i, j)) continue;
    in.push_back(static_cast<std::uint32_t>(i));
  }
  return in;
}

// Hull planes of query point j over the reference points `in`.
std::vector<Plane> planes_of(const AlignmentProblem& p, const AlignOptions& o, std::size_t j,
                             const std::vector<std::uint32_t>& in) {
  std::vector<double> x, y, c;
  x.reserve(in.size()), y.reserve(in.size()), c.reserve(in.size());
  for (const std::uint32_t i : in) {
    x.push_back(p.ref_x[i]);
    y.push_back(p.ref_y[i]);
    c.push_back(p.c(i, j));
  }
  return lower_hull_planes(x, y, c, o.hull);
}

// Hull planes of query point j over the reference points inside `box` (and the depth gate). Throws when the
// cloud is too small or degenerate (the caller then keeps the previous region). With a `cache`, a hull
// another method already computed over the same points is reused and `*charged_s` receives its compute time
// (0 on a miss, whose time the caller's clock already counts).
std::vector<Plane> planes_in_box(const AlignmentProblem& p, const AlignOptions& o, std::size_t j,
                                 const Box& box, std::size_t min_points, HullCache* cache = nullptr,
                                 double* charged_s = nullptr) {
  std::vector<std::uint32_t> in = points_in_box(p, o, j, box);
  if (in.size() < std::max<std::size_t>(min_points, 3))
    throw std::runtime_error(fmt::format("query point {}: {} reference points in its region", j, in.size()));
  if (!cache) return planes_of(p, o, j, in);
  if (const auto hit = cache->find(j, in)) {
    *charged_s = hit->time_s;
    return hit->planes;
  }
  *charged_s = 0;
  const auto t0 = core::Clock::now();
  HullCache::Entry e;
  e.planes = planes_of(p, o, j, in);
  e.time_s = core::seconds_since(t0);
  return cache->insert(j, std::move(in), std::move(e))->planes;
}

struct RoundSolution {
  LpSolution lp;
  int sector = -1;
  int solves = 0;
  int iterations = 0;
};

RoundSolution solve_round(const AlignmentProblem& p, const AlignOptions& o, const Regions& reg,
                          bool global_round, int previous_sector) {
  const Parameterization kind =
      o.method == Method::affine ? Parameterization::affine : Parameterization::rotation_like;
  LpSettings settings = o.lp;
  settings.disc_tolerance = o.method == Method::so_conv_hull ? o.disc_tolerance : 0.0;
  settings.lazy_boxes = global_round;  // later rounds' boxes bind (and rule out far sectors at once)
  RoundSolution out;
  if (o.method == Method::proposed) {
    // The eight sectors in one model (the plane rows generated for one sector are valid for all; sectors
    // differ only in the bounds of the same rows, see sector_rows). The most promising sector goes first —
    // the previous round's, or in round 0 the one holding the optimum of the filled octagon — then the others
    // in angular order from it. A sector is skipped, or its solve stopped, as soon as it provably cannot win:
    //   - the boxes alone rule it out (boxes_exclude_sector; its LP would be infeasible — in the shrinking
    //     rounds most sectors are; the margin leaves sectors near the edge of feasibility to the LP);
    //   - a Lagrangian minorant of an earlier optimal solve is at least the best cost on its whole edge;
    //   - the dual simplex proves its optimum above the best cost (LpStatus::cut_off).
    // The kept sector is the lowest cost, as if all eight were solved to the end (exact ties: the lowest
    // index among those solved; within 1e-9 relative, the first found). Sequential, so the answer does not
    // depend on threads.
    double extent = 0;
    for (const Box& b : reg.boxes)
      extent = std::max({extent, std::abs(b.x_lo), std::abs(b.x_hi), std::abs(b.y_lo), std::abs(b.y_hi)});
    std::array<bool, 8> excluded{};
    for (int k = 0; k < 8; ++k)
      excluded[k] = boxes_exclude_sector(p.query_x, p.query_y, reg.boxes, k, 1e-6 * (1 + extent));
    HullLp lp(kind, p.query_x, p.query_y, reg.planes, reg.boxes, settings);
    // The filled octagon first: every sector's rows are the octagon's with bounds tightened, so from the
    // octagon's optimal basis each sector's solve is a proper warm start of the dual simplex (dual feasible;
    // its objective a lower bound from the first iteration). From another sector's optimum it is not: that
    // sector's binding edge row would be relaxed, and CLP then finished the solve by the primal simplex, past
    // any objective limit.
    lp.set_cs_rows(octagon_rows());
    const LpSolution octagon = lp.solve();
    out.solves += octagon.solves, out.iterations += octagon.iterations;
    if (octagon.status == LpStatus::failed)
      throw std::runtime_error("align: the LP over the filled octagon failed (CLP did not prove optimality)");
    std::vector<unsigned char> octagon_basis;
    if (octagon.status == LpStatus::optimal) octagon_basis = lp.basis();
    int first = previous_sector;
    if (first < 0) {
      first = 0;
      if (octagon.status == LpStatus::optimal) {
        const double a = std::atan2(octagon.params[1], octagon.params[0]);
        first = std::clamp(static_cast<int>(std::floor((a < 0 ? a + 2 * kPi : a) / (kPi / 4))), 0, 7);
      }
    }
    std::array<int, 8> order{};
    for (int q = 0; q < 8; ++q) order[q] = (first + q) % 8;
    // Lagrangian minorants V(p) ≥ cost + λ · (p − p*) of every optimal solve (LpSolution::cs_gradient). A
    // sector on whose whole edge one of them is at least the best cost (less 1e-9 relative, the LP's
    // accuracy) cannot cost less: it is skipped. That includes the sectors next to the best when the
    // octagon's optimum lies on the best sector's edge (the minorant touches the best cost only at the shared
    // vertex), so a sector that ties the best within 1e-9 is not solved: the first best found is kept.
    struct Minorant {
      double cost, c, s, gc, gs;
    };
    std::vector<Minorant> minorants;
    const auto keep_minorant = [&](const LpSolution& s) {
      if (s.status == LpStatus::optimal)
        minorants.push_back({s.cost, s.params[0], s.params[1], s.cs_gradient[0], s.cs_gradient[1]});
    };
    if (!octagon_basis.empty()) keep_minorant(octagon);
    const double radius = 1.0 / kBarniDelta;
    const auto bounded_away = [&](int k, double best) {
      const double margin = 1e-9 * (1.0 + std::abs(best));
      for (const Minorant& m : minorants) {
        double low = std::numeric_limits<double>::infinity();
        for (int v = k; v <= k + 1; ++v) {  // a linear function's minimum on the edge is at a vertex
          const double c = radius * std::cos(v * kPi / 4), s = radius * std::sin(v * kPi / 4);
          low = std::min(low, m.cost + m.gc * (c - m.c) + m.gs * (s - m.s));
        }
        if (low > best - margin) return true;
      }
      return false;
    };
    for (const int k : order) {
      if (excluded[k]) continue;
      if (out.sector >= 0 && bounded_away(k, out.lp.cost)) continue;
      if (!octagon_basis.empty()) lp.set_basis(octagon_basis);
      lp.set_cs_rows(sector_rows(k));
      const LpSolution s = lp.solve(out.sector < 0 ? convex::kLpInfinity : out.lp.cost);
      out.solves += s.solves, out.iterations += s.iterations;
      if (s.status == LpStatus::failed)
        throw std::runtime_error(
            fmt::format("align: the LP of sector {} failed (CLP did not prove optimality)", k));
      if (s.status != LpStatus::optimal) continue;
      keep_minorant(s);
      if (out.sector < 0 || s.cost < out.lp.cost || (s.cost == out.lp.cost && k < out.sector))
        out.lp = s, out.sector = k;
    }
    if (out.sector < 0)
      throw std::runtime_error(
          "align: every sector LP is infeasible: no rotation places all query points inside their regions "
          "(is the query inside the reference?)");
    return out;
  }
  HullLp lp(kind, p.query_x, p.query_y, reg.planes, reg.boxes, settings);
  if (o.method == Method::so_conv_hull) {  // start from the circumscribed octagon; cuts refine it
    std::vector<CsRow> rows;
    for (int k = 0; k < 8; ++k) rows.push_back({std::cos(k * kPi / 4), std::sin(k * kPi / 4), -1e300, 1.0});
    lp.set_cs_rows(rows);
  }
  out.lp = lp.solve();
  out.solves = out.lp.solves, out.iterations = out.lp.iterations;
  if (out.lp.status == LpStatus::infeasible)
    throw std::runtime_error(fmt::format(
        "align ({}): the LP is infeasible: no transform places all query points inside their regions (is the "
        "query inside the reference?)",
        to_string(o.method)));
  if (out.lp.status != LpStatus::optimal)
    throw std::runtime_error(fmt::format("align ({}): CLP did not prove optimality", to_string(o.method)));
  return out;
}

}  // namespace

std::string_view to_string(Method m) { return kMethodNames.name(m); }
Method method_from_string(std::string_view text) { return kMethodNames.parse(text); }

void AlignmentProblem::validate() const {
  const std::size_t na = ref_x.size(), nb = query_x.size();
  if (ref_y.size() != na)
    throw std::invalid_argument(
        fmt::format("AlignmentProblem: ref_x has {} entries, ref_y {}", na, ref_y.size()));
  if (query_y.size() != nb)
    throw std::invalid_argument(
        fmt::format("AlignmentProblem: query_x has {} entries, query_y {}", nb, query_y.size()));
  if (na < 3)
    throw std::invalid_argument(fmt::format("AlignmentProblem: {} reference points (need at least 3)", na));
  if (nb < 1) throw std::invalid_argument("AlignmentProblem: no query point");
  if (ref_z.empty() != query_z.empty())
    throw std::invalid_argument("AlignmentProblem: depths given for one trajectory only (ref_z and query_z)");
  if (!ref_z.empty() && (ref_z.size() != na || query_z.size() != nb))
    throw std::invalid_argument(
        fmt::format("AlignmentProblem: ref_z has {} entries (want {}), query_z {} (want {})", ref_z.size(),
                    na, query_z.size(), nb));
  if (dissimilarity.size() != na * nb)
    throw std::invalid_argument(
        fmt::format("AlignmentProblem: dissimilarity has {} entries, want n_a × n_b = {} × {} = {}",
                    dissimilarity.size(), na, nb, na * nb));
  auto finite = [](const std::vector<double>& v, const char* name) {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i]))
        throw std::invalid_argument(
            fmt::format("AlignmentProblem: {}[{}] = {} is not finite", name, i, v[i]));
  };
  finite(ref_x, "ref_x"), finite(ref_y, "ref_y"), finite(ref_z, "ref_z");
  finite(query_x, "query_x"), finite(query_y, "query_y"), finite(query_z, "query_z");
  for (std::size_t k = 0; k < dissimilarity.size(); ++k)
    if (!std::isfinite(dissimilarity[k]))
      throw std::invalid_argument(fmt::format("AlignmentProblem: dissimilarity C({}, {}) = {} is not finite",
                                              k / nb, k % nb, dissimilarity[k]));
  // Collinear reference: the 2x2 scatter matrix is singular.
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < na; ++i) mx += ref_x[i], my += ref_y[i];
  mx /= static_cast<double>(na), my /= static_cast<double>(na);
  double sxx = 0, syy = 0, sxy = 0;
  for (std::size_t i = 0; i < na; ++i) {
    const double dx = ref_x[i] - mx, dy = ref_y[i] - my;
    sxx += dx * dx, syy += dy * dy, sxy += dx * dy;
  }
  const double tr = sxx + syy, det = sxx * syy - sxy * sxy;
  if (!(det > 1e-12 * tr * tr))
    throw std::invalid_argument(
        "AlignmentProblem: the reference positions are collinear (no 2D region to align in)");
  // The query must fit inside the reference: its diameter cannot exceed the reference's bounding-box
  // diagonal.
  const Bounds b = bounding_box(ref_x, ref_y);
  const double diag2 = (b.x_hi - b.x_lo) * (b.x_hi - b.x_lo) + (b.y_hi - b.y_lo) * (b.y_hi - b.y_lo);
  double qd2 = 0;
  for (std::size_t j = 0; j < nb; ++j)
    for (std::size_t k = j + 1; k < nb; ++k)
      qd2 = std::max(qd2, (query_x[j] - query_x[k]) * (query_x[j] - query_x[k]) +
                              (query_y[j] - query_y[k]) * (query_y[j] - query_y[k]));
  if (qd2 > diag2 * (1 + 1e-9))
    throw std::invalid_argument(
        fmt::format("AlignmentProblem: the query spans {:.3g} m but the reference's bounding box only {:.3g} "
                    "m: the query "
                    "cannot lie inside the reference",
                    std::sqrt(qd2), std::sqrt(diag2)));
}

std::vector<double> dissimilarity_matrix(std::size_t n_a, std::size_t n_b,
                                         const std::function<double(std::size_t, std::size_t)>& c) {
  std::vector<double> m(n_a * n_b);
  for (std::size_t i = 0; i < n_a; ++i)
    for (std::size_t j = 0; j < n_b; ++j) m[i * n_b + j] = c(i, j);
  return m;
}

std::vector<double> euclidean_dissimilarity(const std::vector<double>& fa, const std::vector<double>& fb,
                                            int dim) {
  if (dim < 1 || fa.size() % dim != 0 || fb.size() % dim != 0)
    throw std::invalid_argument(fmt::format(
        "euclidean_dissimilarity: feature arrays of {} and {} values are not multiples of dim = {}",
        fa.size(), fb.size(), dim));
  const std::size_t na = fa.size() / dim, nb = fb.size() / dim;
  std::vector<double> m(na * nb);
  for (std::size_t i = 0; i < na; ++i)
    for (std::size_t j = 0; j < nb; ++j) {
      double d2 = 0;
      for (int k = 0; k < dim; ++k) {
        const double d = fa[i * dim + k] - fb[j * dim + k];
        d2 += d * d;
      }
      m[i * nb + j] = std::sqrt(d2);
    }
  return m;
}

std::vector<double> feature_scales(const std::vector<double>& f, int dim) {
  if (dim < 1 || f.size() % static_cast<std::size_t>(dim) != 0)
    throw std::invalid_argument(
        fmt::format("feature_scales: {} feature values are not a multiple of dim = {}", f.size(), dim));
  const auto d = static_cast<std::size_t>(dim);
  const std::size_t n = f.size() / d;
  if (n == 0) throw std::invalid_argument("feature_scales: no feature vector");
  std::vector<double> scale(d, 0.0);
  for (std::size_t k = 0; k < d; ++k) {
    double mean = 0;
    for (std::size_t i = 0; i < n; ++i) mean += f[i * d + k];
    mean /= static_cast<double>(n);
    double ss = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double e = f[i * d + k] - mean;
      ss += e * e;
    }
    scale[k] = std::sqrt(ss / static_cast<double>(n));
  }
  return scale;
}

std::vector<double> standardize_features(std::vector<double> f, const std::vector<double>& scale) {
  const std::size_t d = scale.size();
  if (d == 0 || f.size() % d != 0)
    throw std::invalid_argument(
        fmt::format("standardize_features: {} feature values are not a multiple of {} scales", f.size(), d));
  for (std::size_t n = 0; n < f.size(); ++n) {
    const double s = scale[n % d];
    if (s > 0 && std::isfinite(s)) f[n] /= s;
  }
  return f;
}

void RegionOptions::validate() const {
  if (max_rounds < 0)
    throw std::invalid_argument(fmt::format("RegionOptions.max_rounds = {}: must be >= 0", max_rounds));
  if (!(shrink > 0 && shrink < 1))
    throw std::invalid_argument(fmt::format("RegionOptions.shrink = {}: must be in (0, 1)", shrink));
  if (!(min_half_width > 0))
    throw std::invalid_argument(
        fmt::format("RegionOptions.min_half_width = {}: must be > 0", min_half_width));
  if (min_points < 3)
    throw std::invalid_argument(fmt::format("RegionOptions.min_points = {}: must be >= 3", min_points));
}

void AlignOptions::validate() const {
  hull.validate();
  region.validate();
  if (!(disc_tolerance > 0))
    throw std::invalid_argument(fmt::format("AlignOptions.disc_tolerance = {}: must be > 0", disc_tolerance));
  if (!(depth_gate >= 0))
    throw std::invalid_argument(fmt::format("AlignOptions.depth_gate = {}: must be >= 0", depth_gate));
  if (!(lp.violation_tolerance > 0))
    throw std::invalid_argument(
        fmt::format("AlignOptions.lp.violation_tolerance = {}: must be > 0", lp.violation_tolerance));
  if (lp.max_generation_rounds < 1)
    throw std::invalid_argument(
        fmt::format("AlignOptions.lp.max_generation_rounds = {}: must be >= 1", lp.max_generation_rounds));
  if (!(lp.matrix_bound > 0))
    throw std::invalid_argument(
        fmt::format("AlignOptions.lp.matrix_bound = {}: must be > 0", lp.matrix_bound));
}

namespace {

// Signs of (c, s) in sector k and whether |c| ≥ |s| there.
struct SectorShape {
  double sc, ss;
  bool c_dominant;
};
SectorShape sector_shape(int k) {
  const int quadrant = k / 2;
  return {(quadrant == 0 || quadrant == 3) ? 1.0 : -1.0, quadrant < 2 ? 1.0 : -1.0,
          k == 0 || k == 3 || k == 4 || k == 7};
}

// The 12 rows of kSectorRowCount's layout, all free: c, s, c − s, c + s, then the eight edge rows.
std::vector<CsRow> free_rows() {
  constexpr double big = 1e300;
  std::vector<CsRow> rows{
      {1.0, 0.0, -big, big}, {0.0, 1.0, -big, big}, {1.0, -1.0, -big, big}, {1.0, 1.0, -big, big}};
  for (int e = 0; e < 8; ++e) {
    const SectorShape sh = sector_shape(e);
    const double ac = sh.c_dominant ? kBarniAlpha1 : kBarniAlpha2,
                 as = sh.c_dominant ? kBarniAlpha2 : kBarniAlpha1;
    rows.push_back({kBarniDelta * ac * sh.sc, kBarniDelta * as * sh.ss, -big, big});  // eq. 3.18 of edge e
  }
  return rows;
}

}  // namespace

std::vector<CsRow> octagon_rows() {
  std::vector<CsRow> rows = free_rows();
  for (std::size_t e = 4; e < kSectorRowCount; ++e) rows[e].hi = 1.0;
  return rows;
}

std::vector<CsRow> sector_rows(int k) {
  if (k < 0 || k > 7) throw std::invalid_argument(fmt::format("sector_rows: sector {} (valid: 0–7)", k));
  const SectorShape sh = sector_shape(k);
  std::vector<CsRow> rows = octagon_rows();
  auto at_least_zero = [](CsRow& r, double sign) { (sign > 0 ? r.lo : r.hi) = 0.0; };
  at_least_zero(rows[0], sh.sc);  // σc c ≥ 0
  at_least_zero(rows[1], sh.ss);  // σs s ≥ 0
  // Dominance of the larger magnitude: σc c − σs s ≥ 0 (c dominant) or σs s − σc c ≥ 0, on the row c − s
  // (σc σs > 0) or c + s (σc σs < 0), scaled by its sign.
  const double dominance = sh.c_dominant ? sh.sc : -sh.sc;  // coefficient of c in the dominance expression
  if (sh.sc * sh.ss > 0)
    at_least_zero(rows[2], dominance);  // dominance = ±(c − s)
  else
    at_least_zero(rows[3], dominance);             // dominance = ±(c + s)
  rows[4 + static_cast<std::size_t>(k)].lo = 1.0;  // eq. 3.18: on edge k
  return rows;
}

bool boxes_exclude_sector(const std::vector<double>& qx, const std::vector<double>& qy,
                          const std::vector<Box>& boxes, int k, double margin) {
  if (k < 0 || k > 7)
    throw std::invalid_argument(fmt::format("boxes_exclude_sector: sector {} (valid: 0–7)", k));
  const std::size_t n = qx.size();
  if (qy.size() != n || boxes.size() != n)
    throw std::invalid_argument(
        "boxes_exclude_sector: query positions and boxes must have one entry per point");
  if (n == 0) return false;
  const double radius = 1.0 / kBarniDelta;  // the octagon's vertices
  const double c0 = radius * std::cos(k * kPi / 4), s0 = radius * std::sin(k * kPi / 4);
  const double dc = radius * std::cos((k + 1) * kPi / 4) - c0, ds = radius * std::sin((k + 1) * kPi / 4) - s0;
  // (A p)_x = c x − s y and (A p)_y = s x + c y at (c, s) = (c0 + λ dc, s0 + λ ds).
  const auto excess = [&](double lambda) {
    const double c = c0 + lambda * dc, s = s0 + lambda * ds;
    double lo_x = -std::numeric_limits<double>::infinity(), hi_x = -lo_x, lo_y = lo_x, hi_y = hi_x;
    for (std::size_t j = 0; j < n; ++j) {
      const double ax = c * qx[j] - s * qy[j], ay = s * qx[j] + c * qy[j];
      lo_x = std::max(lo_x, boxes[j].x_lo - ax), hi_x = std::min(hi_x, boxes[j].x_hi - ax);
      lo_y = std::max(lo_y, boxes[j].y_lo - ay), hi_y = std::min(hi_y, boxes[j].y_hi - ay);
    }
    return std::max(lo_x - hi_x, lo_y - hi_y);
  };
  // Lipschitz constant of the excess in λ: each term moves by at most 2 max_j |d(A p_j)/dλ| per unit λ.
  double lipschitz = 0;
  for (std::size_t j = 0; j < n; ++j)
    lipschitz = std::max({lipschitz, std::abs(dc * qx[j] - ds * qy[j]), std::abs(ds * qx[j] + dc * qy[j])});
  lipschitz *= 2;
  double a = 0, b = 1;
  for (int it = 0; it < 80 && b - a > 1e-13; ++it) {  // ternary search on a convex function
    const double m1 = a + (b - a) / 3, m2 = b - (b - a) / 3;
    const double g1 = excess(m1), g2 = excess(m2);
    if (std::min(g1, g2) <= margin) return false;  // a point of the edge (nearly) fits: leave it to the LP
    if (g1 <= g2)
      b = m2;
    else
      a = m1;
  }
  // The minimum lies in [a, b]: G(λ) ≥ G(mid) − L (b − a) / 2 there.
  const double mid = 0.5 * (a + b);
  return excess(mid) - lipschitz * 0.5 * (b - a) > margin;
}

void singular_values(const Transform2& t, double& s1, double& s2) {
  const double q = 0.5 * std::hypot(t.a11 + t.a22, t.a21 - t.a12);
  const double r = 0.5 * std::hypot(t.a11 - t.a22, t.a21 + t.a12);
  s1 = q + r;
  s2 = std::abs(q - r);
}

bool approximately_valid(const Transform2& t, double tolerance) {
  double s1, s2;
  singular_values(t, s1, s2);
  const double det = t.a11 * t.a22 - t.a12 * t.a21;
  return det > 0 && std::abs(s1 - 1) <= tolerance && std::abs(s2 - 1) <= tolerance;
}

Rigid2 project_to_rigid(const Transform2& t, double cx, double cy) {
  // argmax_θ tr(R(θ)ᵀ A) = atan2(a21 − a12, a11 + a22): the closest rotation in the Frobenius norm.
  const double th = std::atan2(t.a21 - t.a12, t.a11 + t.a22);
  const double c = std::cos(th), s = std::sin(th);
  const double px = t.a11 * cx + t.a12 * cy + t.tx, py = t.a21 * cx + t.a22 * cy + t.ty;
  return {th, px - (c * cx - s * cy), py - (s * cx + c * cy)};
}

Regions global_regions(const AlignmentProblem& p, const AlignOptions& o) {
  const Bounds b = bounding_box(p.ref_x, p.ref_y);
  Regions reg;
  const std::size_t nb = p.query_size();
  reg.boxes.assign(nb, Box{b.x_lo, b.x_hi, b.y_lo, b.y_hi});
  reg.planes.resize(nb);
  core::parallel_for(
      nb, [&](std::size_t j) { reg.planes[j] = planes_in_box(p, o, j, reg.boxes[j], 3); }, o.threads);
  for (const auto& pl : reg.planes) reg.plane_count += pl.size();
  return reg;
}

std::size_t HullCache::KeyHash::operator()(const Key& k) const {
  std::uint64_t h = 1469598103934665603ull ^ k.j;  // FNV-1a over j and the indices
  for (const std::uint32_t i : k.indices) h = (h ^ i) * 1099511628211ull;
  return static_cast<std::size_t>(h);
}

std::shared_ptr<const HullCache::Entry> HullCache::find(std::size_t j,
                                                        const std::vector<std::uint32_t>& indices) const {
  const std::lock_guard lock(mutex_);
  const auto it = entries_.find(Key{j, indices});
  if (it == entries_.end()) return nullptr;
  ++hits_;
  return it->second;
}

std::shared_ptr<const HullCache::Entry> HullCache::insert(std::size_t j, std::vector<std::uint32_t> indices,
                                                          Entry entry) {
  auto stored = std::make_shared<const Entry>(std::move(entry));
  const std::lock_guard lock(mutex_);
  return entries_.try_emplace(Key{j, std::move(indices)}, std::move(stored)).first->second;
}

std::size_t HullCache::size() const {
  const std::lock_guard lock(mutex_);
  return entries_.size();
}

std::size_t HullCache::hits() const {
  const std::lock_guard lock(mutex_);
  return hits_;
}

AlignResult align(const AlignmentProblem& p, const AlignOptions& o, const Regions* global, HullCache* cache) {
  p.validate();
  o.validate();
  if (cache && !(cache->options() == o.hull))
    throw std::invalid_argument("align: the hull cache was made for other hull options");
  if (o.depth_gate > 0 && p.ref_z.empty())
    throw std::invalid_argument("align: depth_gate > 0 needs depths (ref_z, query_z)");
  const auto t0 = core::Clock::now();
  const Parameterization kind =
      o.method == Method::affine ? Parameterization::affine : Parameterization::rotation_like;
  AlignResult res;
  res.method = o.method;

  auto th = core::Clock::now();
  Regions reg = global ? *global : global_regions(p, o);
  if (reg.planes.size() != p.query_size() || reg.boxes.size() != p.query_size())
    throw std::invalid_argument("align: the given global regions do not belong to this problem");
  RoundTrace tr;
  const Bounds b = bounding_box(p.ref_x, p.ref_y);
  const double w0 = 0.5 * std::max(b.x_hi - b.x_lo, b.y_hi - b.y_lo);
  tr.half_width = w0;
  tr.hull_time_s = core::seconds_since(th);
  tr.planes = reg.plane_count;
  auto tl = core::Clock::now();
  RoundSolution sol = solve_round(p, o, reg, true, -1);
  tr.lp_time_s = core::seconds_since(tl);
  tr.cost = sol.lp.cost, tr.sector = sol.sector, tr.plane_rows = sol.lp.plane_rows, tr.solves = sol.solves,
  tr.iterations = sol.iterations;
  Transform2 T = transform_from(kind, sol.lp.params);
  tr.transform = T;
  res.rounds.push_back(tr);

  const std::size_t nb = p.query_size();
  double charged_total_s = 0;  // compute time of the cached hulls this method reused
  for (int r = 1; r <= o.region.max_rounds; ++r) {
    const double w = w0 * std::pow(o.region.shrink, r);
    if (w < o.region.min_half_width) break;
    th = core::Clock::now();
    Regions next;
    next.boxes.resize(nb);
    next.planes.resize(nb);
    std::vector<char> kept(nb, 0);
    std::vector<double> charged(nb, 0.0);
    core::parallel_for(
        nb,
        [&](std::size_t j) {
          const double px = T.a11 * p.query_x[j] + T.a12 * p.query_y[j] + T.tx;
          const double py = T.a21 * p.query_x[j] + T.a22 * p.query_y[j] + T.ty;
          const Box box{px - w, px + w, py - w, py + w};
          try {
            next.planes[j] = planes_in_box(p, o, j, box, o.region.min_points, cache, &charged[j]);
            next.boxes[j] = box;
          } catch (const std::runtime_error&) {  // too few or degenerate points: keep the previous region
            next.planes[j] = reg.planes[j];
            next.boxes[j] = reg.boxes[j];
            kept[j] = 1;
          }
        },
        o.threads);
    for (std::size_t j = 0; j < nb; ++j) next.kept += kept[j], next.plane_count += next.planes[j].size();
    reg = std::move(next);
    double charged_s = 0;
    for (const double s : charged) charged_s += s;
    charged_total_s += charged_s;
    tr = RoundTrace{};
    tr.half_width = w;
    tr.hull_time_s = core::seconds_since(th) + charged_s;
    tr.planes = reg.plane_count;
    tr.kept_boxes = reg.kept;
    tl = core::Clock::now();
    sol = solve_round(p, o, reg, false, sol.sector);
    tr.lp_time_s = core::seconds_since(tl);
    tr.cost = sol.lp.cost, tr.sector = sol.sector, tr.plane_rows = sol.lp.plane_rows, tr.solves = sol.solves,
    tr.iterations = sol.iterations;
    T = transform_from(kind, sol.lp.params);
    tr.transform = T;
    res.rounds.push_back(tr);
  }
  res.raw = T;
  res.cost = sol.lp.cost;
  res.sector = sol.sector;
  double cx = 0, cy = 0;
  for (std::size_t j = 0; j < nb; ++j) cx += p.query_x[j], cy += p.query_y[j];
  res.rigid = project_to_rigid(T, cx / static_cast<double>(nb), cy / static_cast<double>(nb));
  res.time_s = core::seconds_since(t0) + charged_total_s;
  return res;
}

}  // namespace keel::align
