// keel Python module — PYBIND11_MODULE(keel): the docstring, the exception classes and the topic bindings.
#include <exception>

#include "app/solver_log.hpp"
#include "bindings.hpp"
#include "datasets/manifest.hpp"
#include "graph/parse_error.hpp"
#include "keel_python_version.hpp"  // generated: KEEL_VERSION, KEEL_GIT_COMMIT (engine/python/version.cmake)

PYBIND11_MODULE(keel, m) {
  namespace py = pybind11;
  namespace kp = keel::python;
  m.doc() = R"doc(
keel: multi-agent SLAM building blocks (a reproduction of Mangelson's thesis) from Python.

Uncertain Lie-group poses (ch. 5: left perturbation T = exp(xi^) T_bar, eq. 5.14), pose-graph files (g2o and
iSAM text), batch maximum-likelihood solves (eq. 2.1), joint marginal covariances, pairwise consistency of
inter-robot loop closures (eq. 2.4), PCM's maximum-clique selection (eq. 2.5) and trajectory alignment without
data association (ch. 3, keel.align).

Conventions: arrays are numpy float64 copies; 2D poses are rows [x, y, theta] (radians, theta in (-pi, pi]),
3D poses rows [x, y, z, qx, qy, qz, qw] (Hamilton quaternion, qw >= 0); tangents are [rho_x, rho_y, theta]
(SE2) and [rho; phi] = translation part first, rotation vector last (SE3, eq. 5.6); times are seconds.
Errors, each naming the function and the argument: TypeError for an argument of the wrong type (a float
array where integer ids belong: ids are never truncated; a string where an array belongs); ValueError for a
refused value (shape, NaN, an information matrix that is not positive definite, unknown names: "unknown
pgo::InitialGuess 'lm' (valid: ...)"); IndexError for ids out of range (negative or not in the graph);
OverflowError for an integer the engine cannot hold (an id or count above 2**31 - 1, a negative threads or
seed); ParseError (a ValueError) for malformed files, with the engine's message "file:line: TAG field k
(name): ..."; DatasetError (a RuntimeError) when a data-set file cannot be found or verified;
FloatingPointError (an ArithmeticError) for a result that would hold NaN or infinity (finite inputs that
overflow double precision); OSError for a file that cannot be written; RuntimeError for other numerical
failures. Long computations release the GIL.

__version__ is keel's version, __git_commit__ the commit the module was built from ("+dirty": with changes).)doc";
  // Ceres's own log (glog, straight to stderr by default) is dropped: a solver's outcome is in the returned
  // summary (termination, message), as under `keel solve --quiet`.
  keel::app::route_solver_log({});
  m.attr("__version__") = KEEL_VERSION;
  m.attr("__git_commit__") = KEEL_GIT_COMMIT;

  static py::exception<keel::graph::ParseError> parse_error(m, "ParseError", PyExc_ValueError);
  parse_error.doc() =
      "A malformed graph or candidate file (keel::graph::ParseError). str(e) is the engine's message naming "
      "file, line and field; e.file and e.line (1-based, 0 for whole-file errors) hold them separately.";
  static py::exception<keel::datasets::DatasetError> dataset_error(m, "DatasetError", PyExc_RuntimeError);
  dataset_error.doc() =
      "A data-set file that is missing or fails its sha256 check (keel::datasets::DatasetError): the message "
      "lists "
      "every place tried and how to fetch the data.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const keel::graph::ParseError& e) {
      const py::object cls = parse_error;  // (exception<T>::operator() would set the error, not make one)
      py::object exc = cls(e.what());
      exc.attr("file") = e.file();
      exc.attr("line") = e.line();
      PyErr_SetObject(parse_error.ptr(), exc.ptr());
    } catch (const keel::datasets::DatasetError& e) {
      dataset_error(e.what());
    } catch (const kp::NonFiniteResult& e) {
      PyErr_SetString(PyExc_FloatingPointError, e.what());
    } catch (const kp::WriteError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });

  kp::bind_lie(m);
  kp::bind_graph(m);
  kp::bind_solve(m);
  kp::bind_pcm(m);
  kp::bind_align(m);
}
