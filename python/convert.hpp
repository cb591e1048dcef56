// The Python module `cbps` (docs/python.md): conversions between the library's Eigen types and
// numpy / scipy.sparse, and the registration functions of the module's parts. Every matrix
// handed to Python is a copy (scipy.sparse.csr_matrix from its data, indices and indptr arrays),
// so nothing in Python refers to storage the library may reuse or free.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "cbps/base/types.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"

namespace cbps::python {

namespace py = pybind11;

/// A vector as a new 1-D float64 numpy array.
py::array_t<double> to_numpy(const VecX& v);
/// A sparse matrix as a new scipy.sparse.csr_matrix of the same shape and entries.
py::object to_csr(const SpMatRow& M);
py::object to_csr(const SpMat& M);

/// The contacts in Coulomb's cone (docs/cones.md) as a dict {"law": "coulomb"|"ccp",
/// "normal_row": [k, ...] (rows k, k + 1, k + 2: normal, t1, t2), "mu": numpy array}, or None
/// for a problem without them (the paper's boxes).
py::object cones_dict(const FrictionContacts& cones);

/// A Python matrix (scipy.sparse of any format, or anything numpy.asarray takes: a 2-D array or
/// nested lists) as a sparse matrix; `what` names it in errors (InputError "<what>: <why>"),
/// which reject NaN and infinite entries.
SpMat sparse_from_python(const py::handle& M, const std::string& what);
/// A Python vector (1-D, or one column) of numbers; `size` −1 takes any length, else InputError
/// unless it has that many. NaN is refused; ±inf only where `infinite_ok` (the bounds).
VecX vector_from_python(const py::handle& v,
                        const std::string& what,
                        long size,
                        bool infinite_ok = false);

/// A whole number given from Python for the argument `what`: an int, a numpy integer, or a
/// float without a fraction (1e6), in [lo, hi]. Anything else (10.5, 2**40 beyond hi, -1 below
/// lo, nan, True, 'ten', None) is InputError "<what> <value>: must be a whole number from <lo> to
/// <hi>", never pybind11's TypeError.
long long whole_from_python(const py::handle& x,
                            const std::string& what,
                            long long lo,
                            long long hi);
/// The same for the unsigned 64-bit range (seeds: 0 to 2**64 - 1).
std::uint64_t unsigned_from_python(const py::handle& x,
                                   const std::string& what,
                                   std::uint64_t lo,
                                   std::uint64_t hi);
/// A real number given from Python (an int, a float, a numpy scalar) as a double; InputError
/// "<what> <value>: not a number" for anything else (True, 'ten', None, a complex number) and
/// for an int too large for a double. The range is the caller's to check (NaN and ±inf pass).
double real_from_python(const py::handle& x, const std::string& what);

/// A body's state as a dict: name, shape, static, mass (kg; None when static), x (m), q (w, x,
/// y, z), v (m/s), omega (rad/s), the columns of `cbps run`'s trajectory.csv.
py::dict body_dict(const Body& b);

/// A SolverSummary as a dict: iterations, residual (N), delta (N), termination, message,
/// wall_time_s and the exact paths' counts (factorizations, pivots, restarts, islands, singular,
/// crossover, factor_nnz, updates, space).
py::dict summary_dict(const SolverSummary& s);
/// A StepReport as a dict (rows, warm_rows, contacts, the solve's summary fields, ...).
py::dict step_report_dict(const StepReport& r);

/// Writes the file `path` by calling write(temporary) on a temporary file beside it, then
/// renames that to `path`: the file is either whole or untouched. An existing file is replaced
/// only with `force` (as `cbps scenes --export --force`). InputError "<what>: <why>" otherwise.
void write_atomically(const std::string& path,
                      const std::string& what,
                      bool force,
                      const std::function<void(const std::string&)>& write);

/// The parts of the module, each in its own file.
void bind_scenes(py::module_& m);      // scenes.cpp: Scene, scene(), load_scene(), scenes()
void bind_simulation(py::module_& m);  // simulation.cpp: Simulation, System
void bind_solve(py::module_& m);       // solve.cpp: solve(), methods(), parse_solver_spec()
void bind_io(py::module_& m);          // io.cpp: Matrix Market, Siconos, stored problems, verify

}  // namespace cbps::python
