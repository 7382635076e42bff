// keel Python module (pybind11) — what the binding files share: numpy <-> engine conversions and the entry
// points of each topic (lie.cpp, graph.cpp, solve.cpp, pcm.cpp, align.cpp; module.cpp holds PYBIND11_MODULE).
//
// The module includes the engine's ordinary headers and links the keel_<area>_impl libraries (like the unit
// tests), not the named-module facades: pybind11/eigen.h instantiates Eigen broadly, which the clang-19
// module bugs of docs/DESIGN.md do not tolerate.
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
using IntArray = py::array_t<long long, py::array::c_style | py::array::forcecast>;

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
/// Throws std::invalid_argument naming `who` unless the array is (n, 3) (resp. (n, 7)) and finite.
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
/// Edges from (m, 2) ids, (m, 3|7) measurements and (m, d, d) information (None: identity). Throws
/// std::invalid_argument naming `who` on a shape mismatch, a negative id or a non-finite number.
std::vector<graph::Edge2> edges2_from_arrays(const py::object& ids, const py::object& measurements,
                                             const py::object& information, const std::string& who);
std::vector<graph::Edge3> edges3_from_arrays(const py::object& ids, const py::object& measurements,
                                             const py::object& information, const std::string& who);

/// (m, 2) int array or sequence of pairs -> pairs; throws std::invalid_argument naming `who`.
std::vector<std::pair<int, int>> pairs_from_object(const py::object& o, const std::string& who);

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
