// keel Python module — SE(2), SE(3), uncertain poses and jointly distributed poses (thesis ch. 5).
#include <fmt/format.h>

#include <Eigen/LU>

#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "bindings.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/uncertain.hpp"

namespace keel::python {

namespace {

using lie::SE2;
using lie::SE3;
using U2 = lie::UncertainPose<SE2>;
using U3 = lie::UncertainPose<SE3>;
using J2 = lie::JointPoses<SE2>;
using J3 = lie::JointPoses<SE3>;

std::string repr(const SE2& T) {
  return fmt::format("SE2(x={:.17g}, y={:.17g}, theta={:.17g})", T.translation().x(), T.translation().y(),
                     T.angle());
}

std::string repr(const SE3& T) {
  double q[4];
  quaternion_of(T, q);
  const lie::Vec3& t = T.translation();
  return fmt::format("SE3.from_quaternion([{:.17g}, {:.17g}, {:.17g}], [{:.17g}, {:.17g}, {:.17g}, {:.17g}])",
                     t.x(), t.y(), t.z(), q[0], q[1], q[2], q[3]);
}

// Poses are never built from NaN or infinity: ValueError naming the constructor.
template <class M>
const M& finite(const M& v, const char* who) {
  if (!v.allFinite())
    throw std::invalid_argument(fmt::format("{}: the input holds a non-finite number", who));
  return v;
}

// A fixed-size Eigen argument taken as py::object (so that a wrong type is a TypeError naming the argument,
// not pybind11's "Unable to cast").
template <class M>
M fixed_arg(const py::object& o, const char* who, const char* arg) {
  py::detail::make_caster<M> c;
  if (!c.load(o, true)) {
    constexpr int rows = M::RowsAtCompileTime, cols = M::ColsAtCompileTime;
    throw py::type_error(fmt::format("{}: {} must be a float array of shape ({}{}) (got {})", who, arg, rows,
                                     cols == 1 ? std::string(",") : fmt::format(", {}", cols), type_name(o)));
  }
  return py::detail::cast_op<M>(std::move(c));
}

// A tolerance is a finite number >= 0 (NaN would make every comparison false): ValueError otherwise.
double tolerance(double tol, const char* who) {
  if (!(tol >= 0.0) || !std::isfinite(tol))
    throw std::invalid_argument(fmt::format("{}: tol must be a finite number >= 0 (got {})", who, tol));
  return tol;
}

// Results holding NaN or infinity (finite poses whose products overflow double precision) raise
// NonFiniteResult (FloatingPointError) naming the operation.
template <class Derived>
typename Derived::PlainObject result(const Eigen::MatrixBase<Derived>& v, const char* who) {
  if (!v.allFinite())
    throw NonFiniteResult(
        fmt::format("{}: the result holds a non-finite number (the inputs overflow double "
                    "precision)",
                    who));
  return v;
}
template <class G>
  requires std::is_same_v<G, SE2> || std::is_same_v<G, SE3>
G result(const G& T, const char* who) {
  (void)result(T.matrix(), who);
  return T;
}

void bind_se2(py::module_& m) {
  py::class_<SE2>(m, "SE2", R"doc(
A planar rigid motion T = [R(theta), t; 0, 1] (keel::lie::SE2).

Tangent (Lie algebra) order: [rho_x, rho_y, theta]; exp([rho; theta]) = [R(theta), V(theta) rho; 0, 1], so the
tangent's first two entries are NOT the translation unless theta = 0. theta is stored as an angle and reported in
(-pi, pi]. Units: whatever the translation is in (metres in the data sets), radians.)doc")
      .def(
          py::init([](double x, double y, double theta) {
            (void)finite(lie::Vec3(x, y, theta), "SE2");
            return SE2(x, y, theta);
          }),
          py::arg("x") = 0.0, py::arg("y") = 0.0, py::arg("theta") = 0.0,
          "The pose with translation (x, y) and heading theta (radians); ValueError for a non-finite number.")
      .def_static(
          "from_matrix", [](const lie::Mat3& T) { return SE2::from_matrix(finite(T, "SE2.from_matrix")); },
          py::arg("matrix"),
          "From a 3x3 homogeneous matrix. The rotation block must be orthonormal within 1e-5 (Frobenius norm "
          "of "
          "R^T R - I) and the bottom row [0, 0, 1]; ValueError otherwise. The rotation is projected onto "
          "SO(2).")
      .def_static(
          "exp", [](const lie::Vec3& xi) { return SE2::exp(finite(xi, "SE2.exp")); }, py::arg("xi"),
          "Exponential map of the tangent xi = [rho_x, rho_y, theta].")
      .def(
          "log", [](const SE2& T) -> lie::Vec3 { return result(T.log(), "SE2.log"); },
          "Logarithm: the tangent [rho_x, rho_y, theta] with theta in (-pi, pi], rho = V(theta)^-1 t.")
      .def(
          "matrix", [](const SE2& T) -> lie::Mat3 { return T.matrix(); }, "The 3x3 homogeneous matrix.")
      .def(
          "rotation", [](const SE2& T) -> lie::Mat2 { return T.rotation(); }, "The 2x2 rotation matrix.")
      .def(
          "translation", [](const SE2& T) -> lie::Vec2 { return T.translation(); }, "The translation [x, y].")
      .def_property_readonly(
          "x", [](const SE2& T) { return T.translation().x(); }, "Translation x.")
      .def_property_readonly(
          "y", [](const SE2& T) { return T.translation().y(); }, "Translation y.")
      .def_property_readonly("theta", &SE2::angle, "Heading in radians, in (-pi, pi].")
      .def(
          "adjoint", [](const SE2& T) -> lie::Mat3 { return T.adjoint(); },
          "Ad_T = [R, [t_y; -t_x]; 0, 1] for the tangent order [rho; theta].")
      .def(
          "inverse", [](const SE2& T) { return result(T.inverse(), "SE2.inverse"); }, "T^-1.")
      .def(
          "between", [](const SE2& a, const SE2& b) { return result(a.inverse() * b, "SE2.between"); },
          py::arg("other"),
          "a.between(b) = a^-1 b: the pose of b in the frame of a (the measurement convention of pose "
          "graphs).")
      .def(
          "compose", [](const SE2& a, const SE2& b) { return result(a * b, "SE2.compose"); },
          py::arg("other"), "a.compose(b) = a b.")
      .def(
          "__mul__", [](const SE2& a, const SE2& b) { return result(a * b, "SE2.__mul__"); },
          py::is_operator(), "a * b: composition.")
      .def(
          "act",
          [](const SE2& T, const lie::Vec2& p) -> lie::Vec2 {
            return result(T * finite(p, "SE2.act"), "SE2.act");
          },
          py::arg("point"), "R p + t for a point p = [x, y].")
      .def(
          "is_approx",
          [](const SE2& a, const SE2& b, double tol) {
            return a.is_approx(b, tolerance(tol, "SE2.is_approx"));
          },
          py::arg("other"), py::arg("tol") = 1e-9, "Whether the two poses agree within tol.")
      .def("__repr__", [](const SE2& T) { return repr(T); })
      .def(py::pickle(
          [](const SE2& T) { return py::make_tuple(T.translation().x(), T.translation().y(), T.angle()); },
          [](const py::tuple& t) {
            if (t.size() != 3) throw std::invalid_argument("SE2.__setstate__: expected (x, y, theta)");
            const lie::Vec3 v(py::float_(t[0]).cast<double>(), py::float_(t[1]).cast<double>(),
                              py::float_(t[2]).cast<double>());
            (void)finite(v, "SE2.__setstate__");
            return SE2(v[0], v[1], v[2]);
          }));
}

void bind_se3(py::module_& m) {
  py::class_<SE3>(m, "SE3", R"doc(
A rigid motion T = [R, t; 0, 1] (keel::lie::SE3, thesis eq. 5.1).

Tangent (Lie algebra) order: xi = [rho; phi] = [rho_x, rho_y, rho_z, phi_x, phi_y, phi_z], translation part
first, rotation vector last (thesis eq. 5.6); exp(xi) = [exp(phi^), J_l(phi) rho; 0, 1] (closed form of eq. 5.7).
Quaternions are [qx, qy, qz, qw] (Hamilton, as in g2o files); quaternion() returns w >= 0.)doc")
      .def(
          py::init([](const py::object& rotation, const py::object& translation) {
            const lie::Mat3 R = rotation.is_none() ? lie::Mat3::Identity()
                                                   : fixed_arg<lie::Mat3>(rotation, "SE3", "rotation");
            const lie::Vec3 t = translation.is_none()
                                    ? lie::Vec3::Zero()
                                    : fixed_arg<lie::Vec3>(translation, "SE3", "translation");
            return SE3(lie::SO3::from_matrix(finite(R, "SE3 (rotation)")), finite(t, "SE3 (translation)"));
          }),
          py::arg("rotation") = py::none(), py::arg("translation") = py::none(),
          "From a 3x3 rotation matrix (default identity; orthonormal within 1e-5, then projected onto SO(3); "
          "ValueError otherwise) and a translation (default zero).")
      .def_static(
          "from_matrix", [](const lie::Mat4& T) { return SE3::from_matrix(finite(T, "SE3.from_matrix")); },
          py::arg("matrix"),
          "From a 4x4 homogeneous matrix (rotation block orthonormal within 1e-5, bottom row [0, 0, 0, 1]; "
          "ValueError otherwise).")
      .def_static(
          "from_quaternion",
          [](const lie::Vec3& t, const lie::Vec4& q) {
            return se3_from_quaternion(finite(t, "SE3.from_quaternion (translation)").data(),
                                       finite(q, "SE3.from_quaternion (q)").data(), "SE3.from_quaternion");
          },
          py::arg("translation"), py::arg("q"),
          "From a translation and a quaternion q = [qx, qy, qz, qw] whose norm is within 1e-3 of 1 (it is "
          "normalised; ValueError otherwise) — exactly how the graph readers build VERTEX_SE3:QUAT poses.")
      .def_static(
          "exp", [](const lie::Vec6& xi) { return SE3::exp(finite(xi, "SE3.exp")); }, py::arg("xi"),
          "Exponential map of xi = [rho; phi] (translation part first, thesis eq. 5.6).")
      .def(
          "log", [](const SE3& T) -> lie::Vec6 { return result(T.log(), "SE3.log"); },
          "Logarithm: xi = [J_l(phi)^-1 t; log(R)], |phi| <= pi.")
      .def(
          "matrix", [](const SE3& T) -> lie::Mat4 { return T.matrix(); }, "The 4x4 homogeneous matrix.")
      .def(
          "rotation", [](const SE3& T) -> lie::Mat3 { return T.rotation(); }, "The 3x3 rotation matrix.")
      .def(
          "translation", [](const SE3& T) -> lie::Vec3 { return T.translation(); },
          "The translation [x, y, z].")
      .def(
          "quaternion",
          [](const SE3& T) {
            lie::Vec4 q;
            quaternion_of(T, q.data());
            return q;
          },
          "The rotation as [qx, qy, qz, qw] with qw >= 0.")
      .def(
          "adjoint", [](const SE3& T) -> lie::Mat6 { return T.adjoint(); },
          "Ad_T = [R, t^ R; 0, R] for the tangent order [rho; phi] (thesis eqs. 5.9-5.10).")
      .def(
          "inverse", [](const SE3& T) { return result(T.inverse(), "SE3.inverse"); }, "T^-1.")
      .def(
          "between", [](const SE3& a, const SE3& b) { return result(a.inverse() * b, "SE3.between"); },
          py::arg("other"), "a.between(b) = a^-1 b: the pose of b in the frame of a.")
      .def(
          "compose", [](const SE3& a, const SE3& b) { return result(a * b, "SE3.compose"); },
          py::arg("other"), "a.compose(b) = a b.")
      .def(
          "__mul__", [](const SE3& a, const SE3& b) { return result(a * b, "SE3.__mul__"); },
          py::is_operator(), "a * b: composition.")
      .def(
          "act",
          [](const SE3& T, const lie::Vec3& p) -> lie::Vec3 {
            return result(T * finite(p, "SE3.act"), "SE3.act");
          },
          py::arg("point"), "R p + t for a point p = [x, y, z].")
      .def(
          "is_approx",
          [](const SE3& a, const SE3& b, double tol) {
            return a.is_approx(b, tolerance(tol, "SE3.is_approx"));
          },
          py::arg("other"), py::arg("tol") = 1e-9, "Whether the two poses agree within tol.")
      .def("__repr__", [](const SE3& T) { return repr(T); });
}

template <class G>
void bind_uncertain(py::module_& m, const char* name, const char* group_name) {
  using U = lie::UncertainPose<G>;
  using Jac = typename G::Jacobian;
  const std::string doc = fmt::format(R"doc(
An uncertain {0} pose T = exp(xi^) mean with xi ~ N(0, covariance) (LEFT perturbation, thesis eq. 5.14).

The covariance is over the {0} tangent (see {0}.exp for its order) and must be symmetric positive
semi-definite (ValueError otherwise). Attributes are read-only; make a new object to change them.)doc",
                                      group_name);
  py::class_<U>(m, name, doc.c_str())
      .def(py::init([](const G& mean, const Jac& covariance) { return U(mean, covariance); }),
           py::arg("mean"), py::arg("covariance"),
           "From the mean pose and the tangent covariance (validated).")
      .def_static("known", &U::known, py::arg("mean"), "A certain pose (zero covariance).")
      .def_property_readonly(
          "mean", [](const U& u) { return u.mean; }, "The mean pose.")
      .def_property_readonly(
          "covariance", [](const U& u) -> Jac { return u.cov; },
          "The tangent covariance (left perturbation).")
      .def("__repr__", [name](const U& u) {
        return fmt::format("{}(mean={}, covariance=<{}x{}>)", name, repr(u.mean), u.cov.rows(), u.cov.cols());
      });
}

template <class G>
void bind_joint(py::module_& m, const char* name, const char* group_name, const char* uname) {
  using J = lie::JointPoses<G>;
  const std::string doc = fmt::format(R"doc(
n jointly distributed {0} poses (thesis eqs. 5.28-5.29): means T_1..T_n and the joint tangent covariance
Sigma_1:n ((d n) x (d n), d = {1}), block (i, j) = E[xi_i xi_j^T], left perturbation T_i = exp(xi_i^) mean_i.
Pose indices are 0-based integers; an index out of range raises IndexError, a non-integer one TypeError.)doc",
                                      group_name, G::DoF);
  py::class_<J>(m, name, doc.c_str())
      .def(py::init([](const std::vector<G>& means, const lie::MatX& covariance) {
             J j;
             j.means = means;
             j.cov = covariance;
             j.validate();
             return j;
           }),
           py::arg("means"), py::arg("covariance"),
           "From a list of mean poses and the joint covariance (symmetric PSD, (d n) x (d n); ValueError "
           "otherwise).")
      .def_static(
          "independent", &J::independent, py::arg("poses"),
          fmt::format("Block-diagonal joint distribution of a list of independent {}.", uname).c_str())
      .def_property_readonly(
          "means", [](const J& j) { return j.means; }, "The mean poses (a list; a copy).")
      .def_property_readonly(
          "covariance", [](const J& j) -> lie::MatX { return j.cov; }, "The joint covariance (a copy).")
      .def("__len__", &J::size)
      .def(
          "marginal",
          [fn = std::string(name) + ".marginal"](const J& j, const py::object& i) {
            return j.marginal(static_cast<std::size_t>(index_arg(i, fn, "i", j.size())));
          },
          py::arg("i"), "Pose i with its marginal covariance (block (i, i)).")
      .def(
          "cross",
          [fn = std::string(name) + ".cross"](const J& j, const py::object& a, const py::object& b) {
            return j.cross(static_cast<std::size_t>(index_arg(a, fn, "i", j.size())),
                           static_cast<std::size_t>(index_arg(b, fn, "j", j.size())));
          },
          py::arg("i"), py::arg("j"), "E[xi_i xi_j^T], block (i, j) of the covariance.")
      .def(
          "compose",
          [fn = std::string(name) + ".compose"](const J& j, const py::object& a, const py::object& b,
                                                bool use_cross) {
            return lie::compose(j, static_cast<std::size_t>(index_arg(a, fn, "i", j.size())),
                                static_cast<std::size_t>(index_arg(b, fn, "j", j.size())), use_cross);
          },
          py::arg("i"), py::arg("j"), py::arg("use_cross") = true,
          "T_i T_j with covariance by eq. 5.39 using cross(i, j) (use_cross=False: as if independent).")
      .def(
          "between",
          [fn = std::string(name) + ".between"](const J& j, const py::object& a, const py::object& k,
                                                bool use_cross) {
            return lie::relative(j, static_cast<std::size_t>(index_arg(a, fn, "i", j.size())),
                                 static_cast<std::size_t>(index_arg(k, fn, "k", j.size())), use_cross);
          },
          py::arg("i"), py::arg("k"), py::arg("use_cross") = true,
          "T_i^-1 T_k (mean eq. 5.48) with covariance by eq. 5.51 using cross(i, k) (use_cross=False: as if "
          "independent).")
      .def(
          "append_composition",
          [fn = std::string(name) + ".append_composition"](J& j, const py::object& a, const py::object& b) {
            return lie::append_composition(j, static_cast<std::size_t>(index_arg(a, fn, "i", j.size())),
                                           static_cast<std::size_t>(index_arg(b, fn, "j", j.size())));
          },
          py::arg("i"), py::arg("j"),
          "Appends T_i T_j with xi_new = xi_i + Ad(T_i) xi_j (repeated eq. 5.39), keeping every "
          "cross-covariance; "
          "returns its index.")
      .def(
          "append_inverse",
          [fn = std::string(name) + ".append_inverse"](J& j, const py::object& a) {
            return lie::append_inverse(j, static_cast<std::size_t>(index_arg(a, fn, "i", j.size())));
          },
          py::arg("i"), "Appends T_i^-1 with xi_new = -Ad(T_i^-1) xi_i (eq. 5.43); returns its index.")
      .def(
          "append_relative",
          [fn = std::string(name) + ".append_relative"](J& j, const py::object& a, const py::object& k) {
            return lie::append_relative(j, static_cast<std::size_t>(index_arg(a, fn, "i", j.size())),
                                        static_cast<std::size_t>(index_arg(k, fn, "k", j.size())));
          },
          py::arg("i"), py::arg("k"),
          "Appends T_i^-1 T_k with xi_new = Ad(T_i^-1)(xi_k - xi_i) (eq. 5.47); returns its index.")
      .def(
          "compose_chain", [](const J& j, bool use_cross) { return lie::compose_chain(j, use_cross); },
          py::arg("use_cross") = true,
          "T_1 T_2 ... T_n with Sigma = J Sigma_1:n J^T, J = [I, Ad(T_1), Ad(T_1 T_2), ...] (first order).")
      .def("__repr__", [name](const J& j) { return fmt::format("{}(<{} poses>)", name, j.size()); });
}

template <class G>
void bind_uncertain_functions(py::module_& m) {
  using U = lie::UncertainPose<G>;
  using Jac = typename G::Jacobian;
  m.def(
      "compose",
      [](const U& a, const U& b, const std::optional<Jac>& cross) {
        return cross ? lie::compose(a, b, finite(*cross, "compose (cross)")) : lie::compose(a, b);
      },
      py::arg("a"), py::arg("b"), py::arg("cross") = py::none(),
      "T_a T_b of two uncertain poses, to first order in the left perturbation. Mean: eq. 5.32. Covariance: "
      "Sigma_a + Ad(T_a) Sigma_b Ad(T_a)^T when independent (cross=None; Barfoot & Furgale 2014), eq. 5.39 "
      "when correlated with cross = E[xi_a xi_b^T] (3x3 for SE2, 6x6 for SE3).");
  m.def(
      "compose", [](const G& a, const U& b) { return lie::compose(a, b); }, py::arg("a"), py::arg("b"),
      "Known pose on the left (exact): K exp(xi) T = exp(Ad_K xi) K T, covariance Ad_K Sigma Ad_K^T.");
  m.def(
      "compose", [](const U& a, const G& b) { return lie::compose(a, b); }, py::arg("a"), py::arg("b"),
      "Known pose on the right (exact): the covariance is unchanged.");
  m.def(
      "inverse", [](const U& a) { return lie::inverse(a); }, py::arg("a"),
      "T^-1 of an uncertain pose, exact in the left perturbation: covariance Ad(T^-1) Sigma Ad(T^-1)^T "
      "(eqs. 5.43-5.45).");
  m.def(
      "between",
      [](const U& a, const U& b, const std::optional<Jac>& cross) {
        return cross ? lie::relative(a, b, finite(*cross, "between (cross)")) : lie::relative(a, b);
      },
      py::arg("a"), py::arg("b"), py::arg("cross") = py::none(),
      "T_a^-1 T_b (the engine's `relative`). Mean: eq. 5.48. Covariance: eq. 5.51, A (Sigma_a + Sigma_b - C "
      "- "
      "C^T) A^T with A = Ad(T_a^-1) and C = cross = E[xi_a xi_b^T] (zero when cross=None: independent).");
  m.def(
      "between", [](const G& a, const U& b) { return lie::relative(a, b); }, py::arg("a"), py::arg("b"),
      "Known T_a (exact): Ad(T_a^-1) Sigma_b Ad(T_a^-1)^T.");
  m.def(
      "between", [](const U& a, const G& b) { return lie::relative(a, b); }, py::arg("a"), py::arg("b"),
      "Known T_b (exact): Ad(T_a^-1) Sigma_a Ad(T_a^-1)^T.");
}

}  // namespace

void bind_lie(py::module_& m) {
  bind_se2(m);
  bind_se3(m);
  bind_uncertain<SE2>(m, "UncertainSE2", "SE2");
  bind_uncertain<SE3>(m, "UncertainSE3", "SE3");
  bind_joint<SE2>(m, "JointPosesSE2", "SE2", "UncertainSE2");
  bind_joint<SE3>(m, "JointPosesSE3", "SE3", "UncertainSE3");
  bind_uncertain_functions<SE2>(m);
  bind_uncertain_functions<SE3>(m);
  m.def(
      "compose_fourth_order", [](const U3& a, const U3& b) { return lie::compose_fourth_order(a, b); },
      py::arg("a"), py::arg("b"),
      "T_a T_b of INDEPENDENT uncertain SE3 poses with Barfoot & Furgale's (2014) fourth-order covariance "
      "Sigma_4th (Sec. III of their paper).");
}

}  // namespace keel::python
