// Lower convex hull of a dissimilarity point cloud (thesis §3.4.1, eqs. 3.3–3.4), by CGAL's 2D regular
// triangulation (the default) or qhull's reentrant interface.
//
// For one query point j the cloud is {(x_i, y_i, C_ij)} over the reference points i (eq. 3.3). Its lower hull
// (the facets whose outward normal has a negative C component) is a set of planes C = r x + s y + t, and
// c_j(x, y) = max_m (r_m x + s_m y + t_m) (eq. 3.4) is the largest convex function below every C_ij: a lower
// bound on the dissimilarity of query point j at any position of the reference frame, exact at the hull
// vertices.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace keel::align {

// One plane of a lower hull: C = r x + s y + t.
struct Plane {
  double r = 0.0, s = 0.0, t = 0.0;
  [[nodiscard]] double at(double x, double y) const { return r * x + s * y + t; }
};

// What computes the lower hull of the points the prefilter keeps. The envelopes agree to rounding; the
// triangulation takes about half qhull's time on Table 3.1's clouds (30–140 points after the prefilter, where
// qhull's set-up per call dominates: docs/measurements/2026-12-07-hull-regular-triangulation.md).
enum class HullBackend {
  qhull,                  // qhull's 3D hull ('Q5'), its lower facets
  regular_triangulation,  // CGAL's 2D regular triangulation of the positions weighted by x² + y² − C (the
                          // lower hull's projection); qhull where the positions span no triangle
};

struct HullOptions {
  // Facets steeper than this (|∇C| = hypot(r, s), dissimilarity units per metre) are dropped: they are the
  // near-vertical walls at the edge of the cloud, badly conditioned as LP rows. Dropping a plane keeps c_j a
  // valid lower bound (a max over fewer planes).
  double max_slope = 1e3;
  // Planes whose (r, s, t) agree within this (relative to the cloud's scale) are kept once.
  double duplicate_tolerance = 1e-9;
  // Run qhull only on the points that can be vertices of the lower hull: points above the segment of two
  // others on a straight run of the input (survey lines sampled along x) and points above four lower points
  // around them (a grid test) are dropped; the lower facets are the same. false: every point goes to qhull.
  bool prefilter = true;
  HullBackend backend = HullBackend::regular_triangulation;
  void validate() const;  // throws std::invalid_argument naming the field
  bool operator==(const HullOptions&) const = default;
};

struct HullStats {
  std::size_t facets = 0;       // lower facets qhull returned
  std::size_t steep = 0;        // dropped as near-vertical
  std::size_t duplicates = 0;   // dropped as duplicates
  bool joggled = false;         // qhull needed 'QJ' (degenerate cloud, e.g. collinear positions)
  std::size_t hull_points = 0;  // points given to qhull (after the prefilter)
};

// The planes of the lower hull of {(x[i], y[i], c[i])}. Needs at least 3 points that are not collinear in
// (x, y); degenerate clouds (coplanar, duplicate points) are retried with qhull's joggle. Throws
// std::runtime_error with qhull's reason when no hull can be built. Deterministic.
[[nodiscard]] std::vector<Plane> lower_hull_planes(std::span<const double> x, std::span<const double> y,
                                                   std::span<const double> c, const HullOptions& options = {},
                                                   HullStats* stats = nullptr);

}  // namespace keel::align
