// The Python module `cbps`: the library's scenes, simulation, systems (6.1, 6.2.9), solvers
// (6.2, 7) and stored problems for Python, with the names the C++ library and the command line
// use (docs/python.md lists every one). Errors are Python exceptions carrying the messages the
// command line prints after "cbps: ":
//   cbps.InputError (a ValueError)          bad input: a file, a JSON path, a spec, a value
//   cbps.ComputationError (a RuntimeError)  a computation that failed
//   cbps.DivergenceError (a ComputationError) a step that diverged; .step, .body, .row
#include <pybind11/pybind11.h>

#include "cbps/base/error.hpp"
#include "convert.hpp"

namespace cbps::python {
namespace {

/// The Python exception classes, created once at import (module lifetime).
PyObject* input_error = nullptr;
PyObject* computation_error = nullptr;
PyObject* divergence_error = nullptr;

/// A new exception class cbps.NAME deriving from `base`, with a docstring.
PyObject* new_exception(py::module_& m, const char* name, PyObject* base, const char* doc) {
  const std::string qualified = std::string("cbps.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base, nullptr);
  if (type == nullptr) throw py::error_already_set();
  m.add_object(name, py::handle(type));
  return type;
}

/// The library's exceptions as Python's: the most derived first.
void translate(std::exception_ptr p) {
  try {
    std::rethrow_exception(p);
  } catch (const DivergenceError& e) {
    // The instance carries the step, body and row of DivergenceError as attributes.
    py::object error = py::reinterpret_borrow<py::object>(divergence_error)(e.what());
    error.attr("step") = e.step();
    error.attr("body") = e.body();
    error.attr("row") = e.row();
    PyErr_SetObject(divergence_error, error.ptr());
  } catch (const ComputationError& e) {
    PyErr_SetString(computation_error, e.what());
  } catch (const InputError& e) {
    PyErr_SetString(input_error, e.what());
  }
}

}  // namespace
}  // namespace cbps::python

PYBIND11_MODULE(cbps, m) {
  namespace py = pybind11;
  using namespace cbps::python;
  m.doc() =
      "cbps: the constraint-based rigid-body solver of Tamis & Maggiore (2015) for Python.\n"
      "Scenes, simulations, each step's system (J, Minv, A = J Minv J^T, b of 6.2.9), the boxed\n"
      "LCP solvers (6.2, 7.1.1) on any (A, b, cmin, cmax), and stored problems. docs/python.md.";
  input_error = new_exception(m,
                              "InputError",
                              PyExc_ValueError,
                              "Bad input: what the command line reports with exit code 2; the "
                              "message names the file, JSON path, argument or value.");
  computation_error = new_exception(m,
                                    "ComputationError",
                                    PyExc_RuntimeError,
                                    "A computation that failed (the command line's exit code 1).");
  divergence_error = new_exception(m,
                                   "DivergenceError",
                                   computation_error,
                                   "A step whose values turned non-finite or exploded; the "
                                   "attributes step (0-based), body and row (-1: none) say where. "
                                   "The simulation stays as it was before that step.");
  py::register_exception_translator(&translate);
  m.attr("__version__") = CBPS_VERSION;
  bind_scenes(m);
  bind_simulation(m);
  bind_solve(m);
  bind_io(m);
}
