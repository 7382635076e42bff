#include "align/hull.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "align/hull_cgal.hpp"

namespace keel::align {

void HullOptions::validate() const {
  if (!(max_slope > 0))
    throw std::invalid_argument(fmt::format("HullOptions.max_slope = {}: must be > 0", max_slope));
  if (!(duplicate_tolerance >= 0))
    throw std::invalid_argument(
        fmt::format("HullOptions.duplicate_tolerance = {}: must be >= 0", duplicate_tolerance));
}

namespace {

// One qhull run on the 3-column cloud `pts`; fills `planes` with the lower facets (centred coordinates).
// Returns qhull's exit code; `message` gets qhull's error text.
int run_qhull(std::vector<double>& pts, const char* flags, std::vector<Plane>& planes, HullStats& st,
              std::string& message) {
  char* buf = nullptr;
  std::size_t len = 0;
  FILE* err = open_memstream(&buf, &len);
  qhT qh_qh;
  qhT* qh = &qh_qh;
  qh_zero(qh, err);
  std::string cmd = flags;
  const int n = static_cast<int>(pts.size() / 3);
  const int code = qh_new_qhull(qh, 3, n, pts.data(), False, cmd.data(), nullptr, err);
  if (code == 0) {
    facetT* facet;
    FORALLfacets {
      const double nz = facet->normal[2];
      if (!(nz < 0)) continue;  // upper or vertical facet
      ++st.facets;
      // n·p + offset = 0  ->  C = −(n_x x + n_y y + offset) / n_z
      planes.push_back({-facet->normal[0] / nz, -facet->normal[1] / nz, -facet->offset / nz});
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  std::fclose(err);
  if (buf) {
    message.assign(buf, len);
    std::free(buf);
  }
  return code;
}

// Marks the points lying above a segment of two others on an exactly straight run of the input: consecutive
// points with the same y and strictly monotone x (a survey line sampled as a lawn-mower). Along such a run
// the lower chain of (x, C) is found by Andrew's monotone chain; a point strictly above it (by `margin`) lies
// above the segment of two other points of the cloud and is no vertex of the lower hull. O(n), input order
// only.
void mark_above_straight_runs(const std::vector<double>& pts, double margin, std::vector<char>& above) {
  const std::size_t n = pts.size() / 3;
  std::vector<std::size_t> chain;
  for (std::size_t s = 0; s < n;) {
    std::size_t e = s + 1;
    const double dir = e < n ? pts[3 * e] - pts[3 * s] : 0.0;
    while (e < n && pts[3 * e + 1] == pts[3 * s + 1] && (pts[3 * e] - pts[3 * (e - 1)]) * dir > 0) ++e;
    if (e - s >= 3) {
      chain.clear();
      for (std::size_t i = s; i < e; ++i) {  // lower chain, x monotone (increasing or decreasing)
        while (chain.size() >= 2) {
          const std::size_t a = chain[chain.size() - 2], b = chain.back();
          // b is above (or on) segment a–i: the cross product of (b − a) and (i − a) in (x, C), signed by dir
          const double cross = (pts[3 * b] - pts[3 * a]) * (pts[3 * i + 2] - pts[3 * a + 2]) -
                               (pts[3 * b + 2] - pts[3 * a + 2]) * (pts[3 * i] - pts[3 * a]);
          if (cross * dir <= 0)
            chain.pop_back();
          else
            break;
        }
        chain.push_back(i);
      }
      for (std::size_t k = 0; k + 1 < chain.size(); ++k) {
        const std::size_t a = chain[k], b = chain[k + 1];
        for (std::size_t i = a + 1; i < b; ++i) {
          const double t = (pts[3 * i] - pts[3 * a]) / (pts[3 * b] - pts[3 * a]);
          if (pts[3 * i + 2] > pts[3 * a + 2] + t * (pts[3 * b + 2] - pts[3 * a + 2]) + margin) above[i] = 1;
        }
      }
    }
    s = e;
  }
}

// Points that cannot be vertices of the lower hull, found without qhull in O(n + G²): those above a straight
// run of the input (mark_above_straight_runs), and those that fail a grid test. Point q is dropped when
// each of its four open quadrants ({x > x_q, y > y_q} and the other three) holds a point lower than q. Those
// four points contain q's position in their convex hull (every closed half-plane through q contains a whole
// quadrant, so no line separates q from them), so the lower hull of the other points is at q at most the
// largest of their C, below C_q: q lies strictly above it and is no vertex of the lower hull, whose planes
// are then those of the remaining points. (`c_range`: the cloud's range of C, for the runs' margin.) The
// quadrants are searched coarsely: the (x, y) bounding box is cut into G × G cells and each quadrant replaced
// by the block of cells strictly beyond q's row and column (a subset of it), whose minimum C comes from a
// table of block minima. "Lower" keeps a relative margin, so a point within rounding of that bound is kept.
// Returns the indices kept, in input order.
std::vector<std::size_t> lower_hull_candidates(const std::vector<double>& pts, double c_range) {
  const std::size_t n = pts.size() / 3;
  double x0 = pts[0], x1 = pts[0], y0 = pts[1], y1 = pts[1];
  for (std::size_t i = 1; i < n; ++i) {
    x0 = std::min(x0, pts[3 * i]), x1 = std::max(x1, pts[3 * i]);
    y0 = std::min(y0, pts[3 * i + 1]), y1 = std::max(y1, pts[3 * i + 1]);
  }
  std::vector<std::size_t> all(n);
  for (std::size_t i = 0; i < n; ++i) all[i] = i;
  if (!(x1 > x0) || !(y1 > y0)) return all;
  // About two points per cell.
  const auto g = static_cast<std::size_t>(std::clamp(std::sqrt(static_cast<double>(n) / 2.0), 2.0, 64.0));
  const double sx = static_cast<double>(g) / (x1 - x0), sy = static_cast<double>(g) / (y1 - y0);
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<std::size_t> cell(n);
  std::vector<double> cmin(g * g, inf);
  for (std::size_t i = 0; i < n; ++i) {
    const auto a = std::min(g - 1, static_cast<std::size_t>((pts[3 * i] - x0) * sx));
    const auto b = std::min(g - 1, static_cast<std::size_t>((pts[3 * i + 1] - y0) * sy));
    cell[i] = a * g + b;
    cmin[cell[i]] = std::min(cmin[cell[i]], pts[3 * i + 2]);
  }
  // Block minima for the four corners of the grid, (g + 1)² with an empty border: ne[a][b] = min over
  // cells a' ≥ a, b' ≥ b, and likewise nw (a' ≤ a, b' ≥ b), sw, se (indices shifted by one).
  const std::size_t w = g + 2;
  std::vector<double> ne(w * w, inf), nw(w * w, inf), sw(w * w, inf), se(w * w, inf);
  const auto at = [w](std::size_t a, std::size_t b) { return a * w + b; };  // a, b in 0 … g + 1
  for (std::size_t a = g; a >= 1; --a)
    for (std::size_t b = g; b >= 1; --b)
      ne[at(a, b)] = std::min({cmin[(a - 1) * g + (b - 1)], ne[at(a + 1, b)], ne[at(a, b + 1)]});
  for (std::size_t a = 1; a <= g; ++a)
    for (std::size_t b = g; b >= 1; --b)
      nw[at(a, b)] = std::min({cmin[(a - 1) * g + (b - 1)], nw[at(a - 1, b)], nw[at(a, b + 1)]});
  for (std::size_t a = 1; a <= g; ++a)
    for (std::size_t b = 1; b <= g; ++b)
      sw[at(a, b)] = std::min({cmin[(a - 1) * g + (b - 1)], sw[at(a - 1, b)], sw[at(a, b - 1)]});
  for (std::size_t a = g; a >= 1; --a)
    for (std::size_t b = 1; b <= g; ++b)
      se[at(a, b)] = std::min({cmin[(a - 1) * g + (b - 1)], se[at(a + 1, b)], se[at(a, b - 1)]});
  std::vector<char> above(n, 0);
  mark_above_straight_runs(pts, 1e-9 * std::max(1.0, c_range), above);
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i) {
    if (above[i]) continue;
    const std::size_t a = cell[i] / g + 1, b = cell[i] % g + 1;  // shifted cell indices
    const double cq = pts[3 * i + 2];
    const double bound = cq - 1e-12 * (1.0 + std::abs(cq));
    const bool dropped = ne[at(a + 1, b + 1)] < bound && nw[at(a - 1, b + 1)] < bound &&
                         sw[at(a - 1, b - 1)] < bound && se[at(a + 1, b - 1)] < bound;
    if (!dropped) kept.push_back(i);
  }
  return kept;
}

std::string first_line(const std::string& s) {
  const auto start = s.find("QH");
  std::string line = s.substr(start == std::string::npos ? 0 : start);
  const auto end = line.find('\n');
  return end == std::string::npos ? line : line.substr(0, end);
}

}  // namespace

std::vector<Plane> lower_hull_planes(std::span<const double> x, std::span<const double> y,
                                     std::span<const double> c, const HullOptions& options,
                                     HullStats* stats) {
  options.validate();
  const std::size_t n = x.size();
  if (y.size() != n || c.size() != n)
    throw std::invalid_argument(fmt::format(
        "lower_hull_planes: x, y, c have sizes {}, {}, {} (must be equal)", x.size(), y.size(), c.size()));
  if (n < 3) throw std::invalid_argument(fmt::format("lower_hull_planes: {} points (need at least 3)", n));
  // Centre (x, y) for conditioning; planes are shifted back at the end.
  double mx = 0, my = 0, cmin = c[0], cmax = c[0];
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(c[i]))
      throw std::invalid_argument(
          fmt::format("lower_hull_planes: point {} is not finite ({}, {}, {})", i, x[i], y[i], c[i]));
    mx += x[i];
    my += y[i];
    cmin = std::min(cmin, c[i]);
    cmax = std::max(cmax, c[i]);
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  std::vector<double> pts(3 * n);
  double extent = 0;
  for (std::size_t i = 0; i < n; ++i) {
    pts[3 * i] = x[i] - mx;
    pts[3 * i + 1] = y[i] - my;
    pts[3 * i + 2] = c[i];
    extent = std::max({extent, std::abs(pts[3 * i]), std::abs(pts[3 * i + 1])});
  }
  HullStats st;
  std::vector<Plane> raw;
  std::string message;
  int code = 1;
  std::vector<double> work;
  if (options.prefilter && n > 16) {  // the hull of the points that can be lower-hull vertices only
    const std::vector<std::size_t> kept = lower_hull_candidates(pts, cmax - cmin);
    if (kept.size() >= 4 && kept.size() < n) {
      work.resize(3 * kept.size());
      for (std::size_t k = 0; k < kept.size(); ++k)
        for (int d = 0; d < 3; ++d) work[3 * k + d] = pts[3 * kept[k] + d];
      if (options.backend == HullBackend::regular_triangulation) {
        if (detail::regular_triangulation_planes(work, raw, st.facets)) code = 0;
      } else {
        code = run_qhull(work, "qhull Q5", raw, st, message);
      }
      st.hull_points = kept.size();
      if (code != 0 || raw.empty()) raw.clear(), st = HullStats{};
    }
  }
  if (code != 0 && options.backend == HullBackend::regular_triangulation) {  // every point
    if (detail::regular_triangulation_planes(pts, raw, st.facets)) {
      code = 0;
      st.hull_points = n;
    } else {
      raw.clear(), st = HullStats{};  // no triangle: qhull below, with its joggle
    }
  }
  // 'Q5': qhull skips the outer planes (a check of its own output); the facets are the same.
  if (code != 0 || raw.empty()) {
    work = pts;  // qhull may reorder nothing, but keep the input intact for a retry
    code = run_qhull(work, "qhull Q5", raw, st, message);
    st.hull_points = n;
  }
  if (code != 0 || raw.empty()) {
    // Degenerate cloud (all C equal, collinear or repeated positions): joggle the input.
    raw.clear();
    st = HullStats{};
    st.joggled = true;
    st.hull_points = n;
    work = pts;
    std::string m2;
    code = run_qhull(work, "qhull QJ", raw, st, m2);
    if (code != 0)
      throw std::runtime_error(
          fmt::format("lower_hull_planes: qhull failed on {} points even with joggle: {}", n,
                      first_line(m2.empty() ? message : m2)));
  }
  // Drop near-vertical facets, shift back to the original coordinates, deduplicate.
  std::vector<Plane> planes;
  planes.reserve(raw.size());
  for (const Plane& p : raw) {
    if (!(std::hypot(p.r, p.s) <= options.max_slope)) {
      ++st.steep;
      continue;
    }
    planes.push_back({p.r, p.s, p.t - p.r * mx - p.s * my});
  }
  std::sort(planes.begin(), planes.end(), [](const Plane& a, const Plane& b) {
    if (a.r != b.r) return a.r < b.r;
    if (a.s != b.s) return a.s < b.s;
    return a.t < b.t;
  });
  const double scale_c = std::max(1.0, cmax - cmin), scale_x = std::max(1.0, extent);
  std::vector<Plane> unique;
  unique.reserve(planes.size());
  for (const Plane& p : planes) {
    bool dup = false;
    for (auto it = unique.rbegin();
         it != unique.rend() && p.r - it->r <= options.duplicate_tolerance * scale_c; ++it) {
      if (std::abs(p.s - it->s) <= options.duplicate_tolerance * scale_c &&
          std::abs(p.t - it->t) <= options.duplicate_tolerance * scale_c * scale_x) {
        dup = true;
        break;
      }
    }
    if (dup)
      ++st.duplicates;
    else
      unique.push_back(p);
  }
  if (unique.empty())
    throw std::runtime_error(
        fmt::format("lower_hull_planes: no usable lower facet among {} (all steeper than max_slope = {})",
                    st.facets, options.max_slope));
  if (stats) *stats = st;
  return unique;
}

}  // namespace keel::align
