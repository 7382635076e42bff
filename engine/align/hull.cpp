#include "align/hull.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

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
  std::vector<double> work = pts;  // qhull may reorder nothing, but keep the input intact for a retry
  int code = run_qhull(work, "qhull", raw, st, message);
  if (code != 0 || raw.empty()) {
    // Degenerate cloud (all C equal, collinear or repeated positions): joggle the input.
    raw.clear();
    st = HullStats{};
    st.joggled = true;
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
