// keel Python module — numpy <-> engine conversions (bindings.hpp).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "bindings.hpp"
#include "graph/build.hpp"
#include "lie/so3.hpp"

namespace keel::python {

namespace {

// A C-ordered float64 copy of `a` with the given number of dimensions (numeric_array), or ValueError.
Array as_array(const py::object& a, int ndim, const std::string& who, const char* what) {
  Array out = numeric_array(a, who, what);
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

// "[k, c]" of flat index `k` in an array of `shape` (empty for a 0-d array).
std::string location(std::size_t k, const std::vector<py::ssize_t>& shape) {
  std::vector<std::size_t> idx(shape.size());
  for (std::size_t d = shape.size(); d-- > 0;) {
    const auto n = static_cast<std::size_t>(shape[d]);
    idx[d] = k % n;
    k /= n;
  }
  return idx.empty() ? std::string() : fmt::format("[{}]", fmt::join(idx, ", "));
}

bool is_bool(const py::handle& o) {
  if (PyBool_Check(o.ptr())) return true;
  // numpy.bool_ has __index__ in numpy 1.x (deprecated): a bool is never an id or a count here.
  return py::hasattr(o, "dtype") && py::hasattr(o.attr("dtype"), "kind") &&
         py::str(o.attr("dtype").attr("kind")).cast<std::string>() == "b";
}

// The value of a Python int / numpy integer `o` (TypeError otherwise); `overflow` is set (and the value is
// meaningless) when it does not fit a long long, `text` then holds it in decimal.
long long integer_value(const py::handle& o, const std::string& who, const std::string& arg,
                        const char* expected, bool& overflow, std::string& text) {
  if (is_bool(o) || PyFloat_Check(o.ptr()) || !PyIndex_Check(o.ptr()))
    throw py::type_error(fmt::format("{}: {} must be {} (got {} {})", who, arg, expected, type_name(o),
                                     py::repr(o).cast<std::string>()));
  const auto v = py::reinterpret_steal<py::object>(PyNumber_Index(o.ptr()));
  if (!v) throw py::error_already_set();
  int over = 0;
  const long long x = PyLong_AsLongLongAndOverflow(v.ptr(), &over);
  if (x == -1 && PyErr_Occurred()) throw py::error_already_set();
  overflow = over != 0;
  text = py::str(v).cast<std::string>();
  return x;
}

using I64Array = py::array_t<long long, py::array::c_style | py::array::forcecast>;
using U64Array = py::array_t<unsigned long long, py::array::c_style | py::array::forcecast>;

constexpr long long kIntMax = std::numeric_limits<int>::max();
constexpr long long kIntMin = std::numeric_limits<int>::min();

// An id's checks: OverflowError beyond int, IndexError when negative or (n >= 0) not below n.
int checked_id(long long v, bool overflow, const std::string& text, const std::string& who,
               const std::string& at, long long n, const char* what) {
  if (overflow || v > kIntMax || v < kIntMin)
    throw std::overflow_error(fmt::format("{}: {} = {} is beyond the largest {} the engine holds ({})", who,
                                          at, text, what, kIntMax));
  if (v < 0)
    throw std::out_of_range(fmt::format("{}: {} = {} is not a {} (ids are >= 0)", who, at, text, what));
  if (n >= 0 && v >= n)
    throw std::out_of_range(fmt::format("{}: {} = {} is not a {} (the graph has {} poses{})", who, at, text,
                                        what, n, n > 0 ? fmt::format(": 0 … {}", n - 1) : std::string()));
  return static_cast<int>(v);
}

}  // namespace

std::string type_name(const py::handle& o) { return Py_TYPE(o.ptr())->tp_name; }

Array numeric_array(const py::object& a, const std::string& who, const char* what) {
  const py::array raw = py::array::ensure(a);
  if (!raw) PyErr_Clear();
  const char kind = raw ? raw.dtype().kind() : 'O';
  if (!raw || (kind != 'f' && kind != 'i' && kind != 'u' && raw.size() > 0))
    throw py::type_error(fmt::format("{}: {} must be a float array (got {}{})", who, what, type_name(a),
                                     raw ? " of dtype " + py::str(raw.dtype()).cast<std::string>() : ""));
  Array out = Array::ensure(raw);
  if (!out) {
    PyErr_Clear();
    throw py::type_error(fmt::format("{}: {} must be a float array (got {})", who, what, type_name(a)));
  }
  return out;
}

int int_arg(const py::handle& o, const std::string& who, const std::string& arg) {
  bool overflow = false;
  std::string text;
  const long long v = integer_value(o, who, arg, "an integer", overflow, text);
  if (overflow || v > kIntMax || v < kIntMin)
    throw std::overflow_error(
        fmt::format("{}: {} = {} is beyond the C++ int range ({} … {})", who, arg, text, kIntMin, kIntMax));
  return static_cast<int>(v);
}

unsigned long long uint_arg(const py::handle& o, const std::string& who, const std::string& arg,
                            unsigned long long max) {
  bool overflow = false;
  std::string text;
  const long long v = integer_value(o, who, arg, "an integer >= 0", overflow, text);
  unsigned long long u = 0;
  bool fits = !overflow && v >= 0;
  if (fits) {
    u = static_cast<unsigned long long>(v);
  } else if (overflow && !text.empty() && text[0] != '-') {  // beyond long long: parse the decimal text
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), u);
    fits = ec == std::errc() && end == text.data() + text.size();
  }
  if (!fits || u > max)
    throw std::overflow_error(fmt::format("{}: {} = {} is outside 0 … {}", who, arg, text, max));
  return u;
}

int index_arg(const py::handle& o, const std::string& who, const std::string& arg, std::size_t n) {
  const int i = int_arg(o, who, arg);
  if (i < 0 || static_cast<std::size_t>(i) >= n)
    throw std::out_of_range(
        fmt::format("{}: {} = {} is out of range (0 … {})", who, arg, i, static_cast<long long>(n) - 1));
  return i;
}

Ids ids_from_object(const py::object& o, const std::string& who, const std::string& arg, long long n,
                    const char* what) {
  // No dtype is forced: a float array stays one and is refused below instead of being truncated.
  const py::array a = py::array::ensure(o);
  if (!a) {
    PyErr_Clear();
    throw py::type_error(fmt::format("{}: {} must be an integer array or a sequence of integers (got {})",
                                     who, arg, type_name(o)));
  }
  Ids out;
  out.shape.assign(a.shape(), a.shape() + a.ndim());
  if (a.size() == 0) return out;
  const auto count = static_cast<std::size_t>(a.size());
  out.values.reserve(count);
  const char kind = a.dtype().kind();
  if (kind == 'i') {
    const auto c = I64Array::ensure(a);
    for (std::size_t k = 0; k < count; ++k)
      out.values.push_back(checked_id(c.data()[k], false, std::to_string(c.data()[k]), who,
                                      arg + location(k, out.shape), n, what));
  } else if (kind == 'u') {
    const auto c = U64Array::ensure(a);
    for (std::size_t k = 0; k < count; ++k) {
      const unsigned long long v = c.data()[k];
      out.values.push_back(
          checked_id(v > static_cast<unsigned long long>(kIntMax) ? 0 : static_cast<long long>(v),
                     v > static_cast<unsigned long long>(kIntMax), std::to_string(v), who,
                     arg + location(k, out.shape), n, what));
    }
  } else if (kind == 'O') {  // e.g. Python ints beyond 64 bits, or a mixture of types
    std::size_t k = 0;
    for (const py::handle h : a.attr("ravel")()) {
      const std::string at = arg + location(k++, out.shape);
      bool overflow = false;
      std::string text;
      const long long v =
          integer_value(h, who, at, fmt::format("an integer {}", what).c_str(), overflow, text);
      out.values.push_back(checked_id(v, overflow, text, who, at, n, what));
    }
  } else {
    throw py::type_error(fmt::format(
        "{}: {} must hold integer {}s (got an array of dtype {}; ids are never rounded or truncated: "
        "convert integral values with .astype(int))",
        who, arg, what, py::str(a.dtype()).cast<std::string>()));
  }
  return out;
}

void check_finite_result(const double* v, std::size_t count, const std::string& who,
                         const std::string& what) {
  for (std::size_t k = 0; k < count; ++k)
    if (!std::isfinite(v[k]))
      throw NonFiniteResult(fmt::format(
          "{}: {} holds a non-finite number ({}): the inputs overflow double precision or the problem is "
          "degenerate",
          who, what, v[k]));
}

lie::SE3 se3_from_quaternion(const double* t, const double* xyzw, const std::string& who) {
  lie::Mat3 R;
  std::string why;
  if (!graph::rotation_from_quaternion(xyzw, R, why))
    throw std::invalid_argument(fmt::format("{}: {}", who, why));
  return lie::SE3(lie::SO3::from_matrix_unchecked(R), lie::Vec3(t[0], t[1], t[2]));
}

void quaternion_of(const lie::SE3& T, double* xyzw) { graph::quaternion_from_rotation(T.rotation(), xyzw); }

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

// (m, 2) ids: the shape, else ValueError; an empty sequence is no edge.
Ids id_pairs(const py::object& o, const std::string& who, const std::string& arg, long long n,
             const char* expected) {
  Ids ids = ids_from_object(o, who, arg, n);
  const bool empty = ids.values.empty() && !ids.shape.empty() && ids.shape[0] == 0;
  if (!empty && (ids.shape.size() != 2 || ids.shape[1] != 2))
    throw std::invalid_argument(
        fmt::format("{}: {} must be {} (got shape ({}))", who, arg, expected, fmt::join(ids.shape, ", ")));
  return ids;
}

template <class Edge, class G, int D>
std::vector<Edge> edges_from_arrays(const py::object& ids_in, const std::vector<G>& z,
                                    const py::object& information, const std::string& who, long long n) {
  const Ids ids = id_pairs(ids_in, who, "edges", n, "an (m, 2) integer array of pose ids");
  const std::size_t m = ids.values.size() / 2;
  if (z.size() != m)
    throw std::invalid_argument(fmt::format("{}: {} edges but {} measurements", who, m, z.size()));
  std::vector<Edge> out(m);
  for (std::size_t k = 0; k < m; ++k) {
    out[k].i = ids.values[2 * k];
    out[k].j = ids.values[2 * k + 1];
    // The graph readers refuse such an edge too (its residual would not depend on the poses).
    if (n >= 0 && out[k].i == out[k].j)
      throw std::invalid_argument(
          fmt::format("{}: edges[{}] = ({}, {}) connects a pose to itself", who, k, out[k].i, out[k].j));
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
    // Symmetric (a file holds only the upper triangle; here a matrix that is not symmetric to rounding is a
    // mistake), then the readers' own check (graph::information_problem: finite and positive
    // definite), so that what read_graph refuses is refused here too.
    for (std::size_t k = 0; k < m; ++k) {
      const auto& W = out[k].information;
      if ((W - W.transpose()).cwiseAbs().maxCoeff() > 1e-12 * W.cwiseAbs().maxCoeff())
        throw std::invalid_argument(
            fmt::format("{}: information[{}] (edge {} -> {}) is not symmetric", who, k, out[k].i, out[k].j));
      if (const std::string why = graph::information_problem(W); !why.empty())
        throw std::invalid_argument(
            fmt::format("{}: information[{}] (edge {} -> {}) {}", who, k, out[k].i, out[k].j, why));
    }
  }
  return out;
}

}  // namespace

std::vector<graph::Edge2> edges2_from_arrays(const py::object& ids, const py::object& measurements,
                                             const py::object& information, const std::string& who,
                                             long long num_poses) {
  return edges_from_arrays<graph::Edge2, lie::SE2, 3>(
      ids, poses2_from_array(measurements, who + " (measurements)"), information, who, num_poses);
}

std::vector<graph::Edge3> edges3_from_arrays(const py::object& ids, const py::object& measurements,
                                             const py::object& information, const std::string& who,
                                             long long num_poses) {
  return edges_from_arrays<graph::Edge3, lie::SE3, 6>(
      ids, poses3_from_array(measurements, who + " (measurements)"), information, who, num_poses);
}

std::vector<std::pair<int, int>> pairs_from_object(const py::object& o, const std::string& who, long long n) {
  const Ids ids = id_pairs(o, who, "pairs", n, "an (m, 2) integer array or a list of (i, j)");
  std::vector<std::pair<int, int>> out;
  out.reserve(ids.values.size() / 2);
  for (std::size_t k = 0; k + 1 < ids.values.size(); k += 2)
    out.emplace_back(ids.values[k], ids.values[k + 1]);
  return out;
}

}  // namespace keel::python
