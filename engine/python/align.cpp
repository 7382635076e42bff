// keel Python module — trajectory alignment without data association (thesis ch. 3; app::align_surveys, the
// function behind `keel align`, so both give bit-identical transforms).
#include <fmt/format.h>

#include <climits>
#include <cmath>
#include <iterator>
#include <optional>
#include <string>

#include "app/align.hpp"
#include "bindings.hpp"
#include "core/bound.hpp"

namespace keel::python {

namespace {

// A survey from (n, 2|3) positions and (n, k) features (a 1-D array: one feature per position).
app::Survey survey_of(const py::object& xy, const py::object& features, const std::string& who) {
  const Array p = numeric_array(xy, who, "positions"), f = numeric_array(features, who, "features");
  if (p.ndim() != 2 || (p.shape(1) != 2 && p.shape(1) != 3))
    throw std::invalid_argument(
        fmt::format("{}: positions must be an (n, 2) or (n, 3) array (x, y[, depth])", who));
  const auto n = static_cast<std::size_t>(p.shape(0));
  if ((f.ndim() != 1 && f.ndim() != 2) || static_cast<std::size_t>(f.shape(0)) != n)
    throw std::invalid_argument(fmt::format(
        "{}: features must be an (n, k) or (n,) array with one row per position ({} positions)", who, n));
  app::Survey s;
  s.name = who;
  s.dim = f.ndim() == 1 ? 1 : static_cast<int>(f.shape(1));
  if (s.dim < 1) throw std::invalid_argument(fmt::format("{}: no feature column", who));
  const double* pd = p.data();
  const auto cols = static_cast<std::size_t>(p.shape(1));
  for (std::size_t i = 0; i < n; ++i) {
    s.x.push_back(pd[i * cols]), s.y.push_back(pd[i * cols + 1]);
    if (cols == 3) s.z.push_back(pd[i * cols + 2]);
  }
  s.features.assign(f.data(), f.data() + n * static_cast<std::size_t>(s.dim));
  for (std::size_t k = 0; k < s.features.size(); ++k)
    if (!std::isfinite(s.features[k]))
      throw std::invalid_argument(
          fmt::format("{}: feature of position {} column {} is not finite", who, k / s.dim, k % s.dim));
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || (cols == 3 && !std::isfinite(s.z[i])))
      throw std::invalid_argument(fmt::format("{}: position {} is not finite", who, i));
  return s;
}

py::dict transform_dict(const align::Transform2& t) {
  py::dict d;
  Array a({py::ssize_t{2}, py::ssize_t{2}});
  auto r = a.mutable_unchecked<2>();
  r(0, 0) = t.a11, r(0, 1) = t.a12, r(1, 0) = t.a21, r(1, 1) = t.a22;
  Array tr(py::ssize_t{2});
  tr.mutable_at(0) = t.tx, tr.mutable_at(1) = t.ty;
  d["A"] = a;
  d["t"] = tr;
  return d;
}

py::dict align_py(const py::object& ref_xy, const py::object& ref_features, const py::object& query_xy,
                  const py::object& query_features, const std::string& method,
                  const std::string& dissimilarity, const py::object& rounds_obj, double shrink,
                  double min_half_width, double depth_gate, bool certify, const py::object& threads_obj) {
  const int rounds = int_arg(rounds_obj, "align", "rounds");
  const auto threads = static_cast<unsigned>(uint_arg(threads_obj, "align", "threads", UINT_MAX));
  app::AlignSurveysOptions o;
  o.method = align::method_from_string(method);
  o.dissimilarity = app::dissimilarity_from_string(dissimilarity);
  o.region.max_rounds = rounds, o.region.shrink = shrink, o.region.min_half_width = min_half_width;
  o.depth_gate = depth_gate, o.certify = certify, o.threads = threads;
  const app::Survey ref = survey_of(ref_xy, ref_features, "reference");
  const app::Survey query = survey_of(query_xy, query_features, "query");
  app::SurveyAlignment s;
  {
    py::gil_scoped_release release;
    s = app::align_surveys(ref, query, o);
  }
  const align::AlignResult& r = s.result;
  const double numbers[] = {r.raw.a11, r.raw.a12, r.raw.a21,     r.raw.a22,
                            r.raw.tx,  r.raw.ty,  r.rigid.theta, r.cost};
  check_finite_result(numbers, std::size(numbers), "align", "the transform or its cost");
  py::dict out = transform_dict(r.raw);
  out["theta"] = r.rigid.theta;
  out["rigid_t"] = Array(py::ssize_t{2}, std::vector<double>{r.rigid.tx, r.rigid.ty}.data());
  out["cost"] = r.cost;
  out["sector"] = r.sector;
  py::list rounds_out;
  for (const auto& t : r.rounds) {
    py::dict d = transform_dict(t.transform);
    d["half_width"] = t.half_width;
    d["cost"] = t.cost;
    d["sector"] = t.sector;
    rounds_out.append(d);
  }
  out["rounds"] = rounds_out;
  out["time_s"] = r.time_s;
  if (s.certificate) {
    const auto& c = *s.certificate;
    py::dict d;
    d["status"] = std::string(core::to_string(c.status));
    d["theta"] = c.theta;
    d["t"] = Array(py::ssize_t{2}, std::vector<double>{c.tx, c.ty}.data());
    d["lower_bound"] = c.bound.lower;
    d["upper_bound"] = c.bound.upper;
    d["nodes"] = c.nodes;
    out["certificate"] = d;
  } else {
    out["certificate"] = py::none();
  }
  return out;
}

}  // namespace

void bind_align(py::module_& m) {
  m.def("align", &align_py, py::arg("reference_xy"), py::arg("reference_features"), py::arg("query_xy"),
        py::arg("query_features"), py::kw_only(), py::arg("method") = "proposed",
        py::arg("dissimilarity") = "standardized", py::arg("rounds") = 8, py::arg("shrink") = 0.7,
        py::arg("min_half_width") = 3.0, py::arg("depth_gate") = 0.0, py::arg("certify") = false,
        py::arg("threads") = 1,
        R"doc(Align a query survey to a reference survey without data association (thesis ch. 3).

reference_xy, query_xy: (n, 2) positions [x, y] or (n, 3) [x, y, depth] (depths on both or neither), metres,
each in its own frame. reference_features, query_features: (n, k) feature vectors (or (n,) for k = 1).
method: "proposed" (Barni's octagon, eq. 3.19), "so_conv_hull", "symmetric" or "affine" (Table 3.1).
dissimilarity: "standardized" (Euclidean after dividing every feature column by its std over the reference)
or "euclidean" (raw feature vectors, as ch3_table3_1_alignment). rounds, shrink, min_half_width: the shrinking
region of interest (round 0 uses the whole reference). certify: also certify the optimum over SO(2) of round
0's objective (planar only).

Returns a dict: A (2x2) and t (2,) with p_ref = A p_query + t (eq. 3.1); theta and rigid_t, the closest rigid
transform (polar projection, the query centroid kept where A, t put it); cost; sector (proposed: 0-7); rounds,
one dict per round (A, t, half_width, cost, sector); certificate (status, theta, t, lower_bound, upper_bound,
nodes) or None; time_s. The same arguments give the transform `keel align` prints, bit for bit. Raises
ValueError for bad shapes, non-finite values, mismatched feature counts, or a query larger than the
reference.)doc");
}

}  // namespace keel::python
