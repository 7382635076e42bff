// The lower hull of a dissimilarity cloud by CGAL's 2D regular triangulation (align/hull.hpp,
// HullBackend::regular_triangulation). Internal to keel.align: one translation unit holds CGAL's headers.
#pragma once

#include <cstddef>
#include <vector>

#include "align/hull.hpp"

namespace keel::align::detail {

// The planes of the lower hull of the 3-column cloud `pts` (x, y, C per point, x and y centred by the
// caller), one per triangle of the regular triangulation of the positions (x, y) weighted by w = x² + y² − C:
// that triangulation is the projection of the lower hull of the lifted points (x, y, x² + y² − w) = (x, y, C)
// (power diagram duality), and a point above the hull is hidden (no vertex). Each plane goes through its
// triangle's three points. Coplanar facets come out as several triangles of one plane (the caller
// deduplicates). `faces` receives the triangle count. Returns false, with no plane, when the positions span
// no triangle (fewer than three distinct positions, or all on one line).
bool regular_triangulation_planes(const std::vector<double>& pts, std::vector<Plane>& planes,
                                  std::size_t& faces);

}  // namespace keel::align::detail
