#include "align/hull_cgal.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Regular_triangulation_2.h>
#include <CGAL/Regular_triangulation_face_base_2.h>
#include <CGAL/Regular_triangulation_vertex_base_2.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <utility>

namespace keel::align::detail {

namespace {

// Exact predicates (the orientation and power tests decide the combinatorics exactly, so hidden points and
// coplanar facets are found without tolerances), inexact constructions (none are used: the planes are
// computed below from the input coordinates). Each vertex keeps the index of its input point.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase =
    CGAL::Triangulation_vertex_base_with_info_2<std::size_t, Kernel,
                                                CGAL::Regular_triangulation_vertex_base_2<Kernel>>;
using FaceBase = CGAL::Regular_triangulation_face_base_2<Kernel>;
using Triangulation =
    CGAL::Regular_triangulation_2<Kernel, CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>>;

}  // namespace

bool regular_triangulation_planes(const std::vector<double>& pts, std::vector<Plane>& planes,
                                  std::size_t& faces) {
  const std::size_t n = pts.size() / 3;
  std::vector<std::pair<Kernel::Weighted_point_2, std::size_t>> input;
  input.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = pts[3 * i], y = pts[3 * i + 1], c = pts[3 * i + 2];
    input.emplace_back(Kernel::Weighted_point_2(Kernel::Point_2(x, y), x * x + y * y - c), i);
  }
  Triangulation rt;
  rt.insert(input.begin(), input.end());  // spatially sorted first
  faces = 0;
  if (rt.dimension() < 2) return false;
  for (auto f = rt.finite_faces_begin(); f != rt.finite_faces_end(); ++f) {
    const double* a = &pts[3 * f->vertex(0)->info()];
    const double* b = &pts[3 * f->vertex(1)->info()];
    const double* c = &pts[3 * f->vertex(2)->info()];
    // C = r x + s y + t through the three points (Cramer's rule on the differences from a).
    const double bx = b[0] - a[0], by = b[1] - a[1], bc = b[2] - a[2];
    const double cx = c[0] - a[0], cy = c[1] - a[1], cc = c[2] - a[2];
    const double det = bx * cy - by * cx;
    ++faces;
    if (det == 0.0) continue;  // no plane through a flat triangle (it cannot be a face; kept for safety)
    const double r = (bc * cy - by * cc) / det, s = (bx * cc - bc * cx) / det;
    planes.push_back({r, s, a[2] - r * a[0] - s * a[1]});
  }
  return !planes.empty();
}

}  // namespace keel::align::detail
