// keel Python module (pybind11) — what the binding files share: numpy <-> engine conversions and the entry
// points of each topic (lie.cpp, graph.cpp, solve.cpp, pcm.cpp, align.cpp; module.cpp holds PYBIND11_MODULE).
//
// The module includes the engine's ordinary headers and links the keel_<area>_impl libraries (like the unit
// tests), not the named-module facades: pybind11/eigen.h instantiates Eigen broadly, which the clang-19
// module bugs of docs/TOOLCHAIN.md do not tolerate.
//
// Array conventions (all float64, C order, copies — never views into engine objects):
//   2D poses  rows [x, y, theta]               (theta = SE2::angle() in (-pi, pi])
//   3D poses  rows [x, y, z, qx, qy, qz, qw]   (Hamilton quaternion, w >= 0, as the graph writers print it)
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "graph/pose_graph.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"

namespace keel::python {

namespace py = pybind11;

/// A float64 array in C order (numpy inputs of other dtypes or layouts are converted on the way in).
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

void bind_lie(py::module_& m);
void bind_graph(py::module_& m);
void bind_solve(py::module_& m);
void bind_pcm(py::module_& m);
void bind_align(py::module_& m);

// ---- single poses
// -------------------------------------------------------------------------------------------
/// SE(3) from (t, q = [qx, qy, qz, qw]) exactly as the graph readers build it (the quaternion is normalised;
/// its norm must be within 1e-3 of 1, else std::invalid_argument naming `who`).
lie::SE3 se3_from_quaternion(const double* t, const double* xyzw, const std::string& who);
/// [qx, qy, qz, qw] with w >= 0, exactly as the graph writers print it.
void quaternion_of(const lie::SE3& T, double* xyzw);

// ---- pose lists <-> (n, 3) / (n, 7) arrays
// ------------------------------------------------------------------
Array poses_to_array(const std::vector<lie::SE2>& poses);
Array poses_to_array(const std::vector<lie::SE3>& poses);
/// Throws std::invalid_argument naming `who` unless the array is (n, 3) (resp. (n, 7)) and finite;
/// py::type_error unless it is a numeric (float or integer) array.
std::vector<lie::SE2> poses2_from_array(const py::object& a, const std::string& who);
std::vector<lie::SE3> poses3_from_array(const py::object& a, const std::string& who);

// ---- edges
// ----------------------------------------------------------------------------------------------------
/// (m, 2) int64 [i, j] of the edges.
template <class E>
py::array_t<long long> edge_ids(const std::vector<E>& edges) {
  py::array_t<long long> out({static_cast<py::ssize_t>(edges.size()), py::ssize_t{2}});
  auto r = out.mutable_unchecked<2>();
  for (std::size_t k = 0; k < edges.size(); ++k) {
    r(k, 0) = edges[k].i;
    r(k, 1) = edges[k].j;
  }
  return out;
}
Array edge_measurements(const std::vector<graph::Edge2>& edges);  // (m, 3)
Array edge_measurements(const std::vector<graph::Edge3>& edges);  // (m, 7)
Array edge_information(const std::vector<graph::Edge2>& edges);   // (m, 3, 3)
Array edge_information(const std::vector<graph::Edge3>& edges);   // (m, 6, 6)
/// Edges from (m, 2) ids, (m, 3|7) measurements and (m, d, d) information (None: identity), named in errors
/// as `who`: ids as in ids_from_object (num_poses >= 0: every id below it, and no edge from a pose to
/// itself); every information matrix finite and positive definite as the graph readers demand
/// (graph::information_problem), else ValueError naming the edge; non-finite numbers: ValueError.
std::vector<graph::Edge2> edges2_from_arrays(const py::object& ids, const py::object& measurements,
                                             const py::object& information, const std::string& who,
                                             long long num_poses);
std::vector<graph::Edge3> edges3_from_arrays(const py::object& ids, const py::object& measurements,
                                             const py::object& information, const std::string& who,
                                             long long num_poses);

// ---- arguments
// ----------------------------------------------------------------------------------------------------
// Every refusal names the function (`who`) and the argument. The exception types (pybind11 translates the
// standard ones): py::type_error -> TypeError for a wrong type (a float where an integer id belongs, a string
// where an array belongs); std::overflow_error -> OverflowError for an integer beyond the engine's int range;
// std::out_of_range -> IndexError for an id outside the graph (or negative); std::invalid_argument ->
// ValueError for a refused value of the right type; NonFiniteResult -> FloatingPointError (an
// ArithmeticError) for a result that holds NaN or infinity, WriteError -> OSError for a file that cannot be
// written (module.cpp registers both).

/// A computation whose result holds NaN or infinity, e.g. because finite inputs overflowed double precision.
struct NonFiniteResult : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A file that cannot be written (OSError in Python; module.cpp registers it).
struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The name of o's type for messages ("float", "numpy.float64", "str").
std::string type_name(const py::handle& o);

/// A C-ordered float64 copy of a numeric array (float or integer dtype, or a sequence numpy reads as one;
/// an empty one of any dtype): TypeError naming `who` and `what` otherwise.
Array numeric_array(const py::object& a, const std::string& who, const char* what);

/// A Python int or numpy integer, never a bool or a float (2.0 is refused like 2.5: nothing is truncated);
/// TypeError otherwise, OverflowError outside the C++ int range.
int int_arg(const py::handle& o, const std::string& who, const std::string& arg);
/// A Python int or numpy integer in [0, max] (a count, a seed, a number of threads): TypeError as int_arg,
/// OverflowError for a negative number or one above max (as Python converts to an unsigned C type).
unsigned long long uint_arg(const py::handle& o, const std::string& who, const std::string& arg,
                            unsigned long long max);
/// int_arg, then IndexError unless 0 <= i < n.
int index_arg(const py::handle& o, const std::string& who, const std::string& arg, std::size_t n);

/// The integer ids of an array or nested sequence (any shape, flattened in C order). The dtype must be an
/// integer one (numpy int8..int64, uint8..uint64, or Python ints): TypeError otherwise (float arrays are
/// refused even when every value is integral, so that no id is ever rounded or truncated). OverflowError for
/// a value beyond the engine's int range, IndexError for a negative one or, when n >= 0, one >= n. `what`
/// names one id in messages ("pose id").
struct Ids {
  std::vector<int> values;
  std::vector<py::ssize_t> shape;
};
Ids ids_from_object(const py::object& o, const std::string& who, const std::string& arg, long long n,
                    const char* what = "pose id");

/// (m, 2) ids or a sequence of pairs -> pairs (ids_from_object with n = num_poses; ValueError for another
/// shape).
std::vector<std::pair<int, int>> pairs_from_object(const py::object& o, const std::string& who, long long n);

/// A float array's values checked finite, or NonFiniteResult naming `who` and `what` (results only).
void check_finite_result(const double* v, std::size_t count, const std::string& who, const std::string& what);

/// A (rows, cols) float64 array copied from an Eigen matrix (column-major in memory) in row-major order.
template <class M>
Array matrix_to_array(const M& m) {
  Array out({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(out.mutable_data(),
                                                                                     m.rows(), m.cols()) = m;
  return out;
}
/// (k, rows, cols) from k matrices of that size (row-major copies; one strided copy per matrix).
template <class M>
Array matrices_to_array(const std::vector<M>& ms, py::ssize_t rows, py::ssize_t cols) {
  Array out({static_cast<py::ssize_t>(ms.size()), rows, cols});
  double* p = out.mutable_data();
  using RowMajor = Eigen::Matrix<double, M::RowsAtCompileTime, M::ColsAtCompileTime,
                                 M::ColsAtCompileTime == 1 ? Eigen::ColMajor : Eigen::RowMajor>;
  for (const M& m : ms) {
    if (m.rows() != rows || m.cols() != cols) throw std::logic_error("matrices_to_array: size mismatch");
    Eigen::Map<RowMajor>(p, rows, cols) = m;
    p += rows * cols;
  }
  return out;
}
/// (k, rows, cols) view of k fixed-size matrices without copying: the vector is moved into a capsule that the
/// array owns, and the strides read each column-major matrix in place (so the array is not C-contiguous).
template <class M>
py::array matrices_as_array(std::vector<M>&& ms) {
  static_assert(M::RowsAtCompileTime > 0 && M::ColsAtCompileTime > 0 && !M::IsRowMajor);
  static_assert(sizeof(M) == sizeof(double) * M::RowsAtCompileTime * M::ColsAtCompileTime);
  auto* holder = new std::vector<M>(std::move(ms));
  py::capsule owner(holder, [](void* p) { delete static_cast<std::vector<M>*>(p); });
  constexpr auto d = static_cast<py::ssize_t>(sizeof(double));
  return py::array_t<double>({static_cast<py::ssize_t>(holder->size()), py::ssize_t{M::RowsAtCompileTime},
                              py::ssize_t{M::ColsAtCompileTime}},
                             {static_cast<py::ssize_t>(sizeof(M)), d, d * M::RowsAtCompileTime},
                             holder->empty() ? nullptr : holder->front().data(), owner);
}

}  // namespace keel::python
