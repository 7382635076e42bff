// keel Python module — numpy <-> engine conversions (bindings.hpp).
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "bindings.hpp"
#include "graph/build.hpp"
#include "lie/so3.hpp"

namespace keel::python {

namespace {

// A C-ordered float64 copy of `a` with the given number of dimensions, or std::invalid_argument.
Array as_array(const py::object& a, int ndim, const std::string& who, const char* what) {
  Array out = Array::ensure(a);
  if (!out) {
    PyErr_Clear();
    throw std::invalid_argument(fmt::format("{}: {} must be a float64-convertible array", who, what));
  }
  if (out.ndim() != ndim)
    throw std::invalid_argument(
        fmt::format("{}: {} must have {} dimensions (got {})", who, what, ndim, out.ndim()));
  return out;
}

void check_finite(double v, const std::string& who, const char* what, py::ssize_t row) {
  if (!std::isfinite(v))
    throw std::invalid_argument(
        fmt::format("{}: {} row {} holds a non-finite number ({})", who, what, row, v));
}

}  // namespace

lie::SE3 se3_from_quaternion(const double* t, const double* xyzw, const std::string& who) {
  lie::Mat3 R;
  std::string why;
  if (!graph::detail::rotation_from_quaternion(xyzw, R, why))
    throw std::invalid_argument(fmt::format("{}: {}", who, why));
  return lie::SE3(lie::SO3::from_matrix_unchecked(R), lie::Vec3(t[0], t[1], t[2]));
}

void quaternion_of(const lie::SE3& T, double* xyzw) {
  graph::detail::quaternion_from_rotation(T.rotation(), xyzw);
}

Array poses_to_array(const std::vector<lie::SE2>& poses) {
  Array out({static_cast<py::ssize_t>(poses.size()), py::ssize_t{3}});
  auto r = out.mutable_unchecked<2>();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    r(k, 0) = poses[k].translation().x();
    r(k, 1) = poses[k].translation().y();
    r(k, 2) = poses[k].angle();
  }
  return out;
}

Array poses_to_array(const std::vector<lie::SE3>& poses) {
  Array out({static_cast<py::ssize_t>(poses.size()), py::ssize_t{7}});
  auto r = out.mutable_unchecked<2>();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const lie::Vec3& t = poses[k].translation();
    for (int c = 0; c < 3; ++c) r(k, c) = t[c];
    quaternion_of(poses[k], r.mutable_data(k, 3));
  }
  return out;
}

std::vector<lie::SE2> poses2_from_array(const py::object& a, const std::string& who) {
  const Array p = as_array(a, 2, who, "2D poses");
  if (p.shape(1) != 3)
    throw std::invalid_argument(
        fmt::format("{}: 2D poses must be an (n, 3) array of [x, y, theta] (got (n, {}))", who, p.shape(1)));
  auto r = p.unchecked<2>();
  std::vector<lie::SE2> out;
  out.reserve(static_cast<std::size_t>(p.shape(0)));
  for (py::ssize_t k = 0; k < p.shape(0); ++k) {
    for (int c = 0; c < 3; ++c) check_finite(r(k, c), who, "2D poses", k);
    out.emplace_back(r(k, 0), r(k, 1), r(k, 2));
  }
  return out;
}

std::vector<lie::SE3> poses3_from_array(const py::object& a, const std::string& who) {
  const Array p = as_array(a, 2, who, "3D poses");
  if (p.shape(1) != 7)
    throw std::invalid_argument(fmt::format(
        "{}: 3D poses must be an (n, 7) array of [x, y, z, qx, qy, qz, qw] (got (n, {}))", who, p.shape(1)));
  auto r = p.unchecked<2>();
  std::vector<lie::SE3> out;
  out.reserve(static_cast<std::size_t>(p.shape(0)));
  for (py::ssize_t k = 0; k < p.shape(0); ++k) {
    for (int c = 0; c < 7; ++c) check_finite(r(k, c), who, "3D poses", k);
    out.push_back(se3_from_quaternion(r.data(k, 0), r.data(k, 3), fmt::format("{}: 3D pose {}", who, k)));
  }
  return out;
}

Array edge_measurements(const std::vector<graph::Edge2>& edges) {
  std::vector<lie::SE2> z;
  z.reserve(edges.size());
  for (const auto& e : edges) z.push_back(e.measurement);
  return poses_to_array(z);
}

Array edge_measurements(const std::vector<graph::Edge3>& edges) {
  std::vector<lie::SE3> z;
  z.reserve(edges.size());
  for (const auto& e : edges) z.push_back(e.measurement);
  return poses_to_array(z);
}

Array edge_information(const std::vector<graph::Edge2>& edges) {
  std::vector<lie::Mat3> w;
  w.reserve(edges.size());
  for (const auto& e : edges) w.push_back(e.information);
  return matrices_to_array(w, 3, 3);
}

Array edge_information(const std::vector<graph::Edge3>& edges) {
  std::vector<lie::Mat6> w;
  w.reserve(edges.size());
  for (const auto& e : edges) w.push_back(e.information);
  return matrices_to_array(w, 6, 6);
}

namespace {

template <class Edge, class G, int D>
std::vector<Edge> edges_from_arrays(const py::object& ids_in, const std::vector<G>& z,
                                    const py::object& information, const std::string& who) {
  IntArray ids = IntArray::ensure(ids_in);
  if (!ids || ids.ndim() != 2 || ids.shape(1) != 2) {
    PyErr_Clear();
    throw std::invalid_argument(fmt::format("{}: edges must be an (m, 2) integer array of pose ids", who));
  }
  const auto m = static_cast<std::size_t>(ids.shape(0));
  if (z.size() != m)
    throw std::invalid_argument(fmt::format("{}: {} edges but {} measurements", who, m, z.size()));
  std::vector<Edge> out(m);
  auto id = ids.unchecked<2>();
  for (std::size_t k = 0; k < m; ++k) {
    if (id(k, 0) < 0 || id(k, 1) < 0 || id(k, 0) > INT32_MAX || id(k, 1) > INT32_MAX)
      throw std::invalid_argument(
          fmt::format("{}: edge {} has a pose id out of range ({}, {})", who, k, id(k, 0), id(k, 1)));
    out[k].i = static_cast<int>(id(k, 0));
    out[k].j = static_cast<int>(id(k, 1));
    out[k].measurement = z[k];
  }
  if (!information.is_none()) {
    const Array w = as_array(information, 3, who, "information");
    if (static_cast<std::size_t>(w.shape(0)) != m || w.shape(1) != D || w.shape(2) != D)
      throw std::invalid_argument(fmt::format("{}: information must be an ({}, {}, {}) array", who, m, D, D));
    auto r = w.unchecked<3>();
    for (std::size_t k = 0; k < m; ++k)
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j) {
          check_finite(r(k, i, j), who, "information", static_cast<py::ssize_t>(k));
          out[k].information(i, j) = r(k, i, j);
        }
  }
  return out;
}

}  // namespace

std::vector<graph::Edge2> edges2_from_arrays(const py::object& ids, const py::object& measurements,
                                             const py::object& information, const std::string& who) {
  return edges_from_arrays<graph::Edge2, lie::SE2, 3>(
      ids, poses2_from_array(measurements, who + " (measurements)"), information, who);
}

std::vector<graph::Edge3> edges3_from_arrays(const py::object& ids, const py::object& measurements,
                                             const py::object& information, const std::string& who) {
  return edges_from_arrays<graph::Edge3, lie::SE3, 6>(
      ids, poses3_from_array(measurements, who + " (measurements)"), information, who);
}

std::vector<std::pair<int, int>> pairs_from_object(const py::object& o, const std::string& who) {
  // Ids are integers: a float (or other non-integer) array would be truncated by the conversion below.
  if (const py::array any = py::array::ensure(o); any) {
    const char kind = any.dtype().kind();
    if (any.size() > 0 && kind != 'i' && kind != 'u')
      throw std::invalid_argument(fmt::format("{}: pairs must be integers (got an array of dtype {})", who,
                                              py::str(any.dtype()).cast<std::string>()));
  } else {
    PyErr_Clear();
  }
  IntArray a = IntArray::ensure(o);
  if (!a || a.ndim() != 2 || a.shape(1) != 2) {
    PyErr_Clear();
    throw std::invalid_argument(
        fmt::format("{}: pairs must be an (m, 2) integer array or a list of (i, j)", who));
  }
  auto r = a.unchecked<2>();
  std::vector<std::pair<int, int>> out;
  out.reserve(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t k = 0; k < a.shape(0); ++k) {
    if (r(k, 0) < INT32_MIN || r(k, 0) > INT32_MAX || r(k, 1) < INT32_MIN || r(k, 1) > INT32_MAX)
      throw std::out_of_range(fmt::format("{}: pair {} ({}, {}) is out of range", who, k, r(k, 0), r(k, 1)));
    out.emplace_back(static_cast<int>(r(k, 0)), static_cast<int>(r(k, 1)));
  }
  return out;
}

}  // namespace keel::python
