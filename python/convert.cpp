// Eigen ↔ numpy / scipy.sparse for the Python module (convert.hpp).
#include "convert.hpp"

#include <cmath>
#include <optional>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/output_file.hpp"

namespace cbps::python {

namespace {

/// x as it appears in a message: its repr, cut short when long (Python refuses to print ints
/// of more than 4300 digits at all; such an int is named by its size).
std::string value_text(const py::handle& x) {
  std::string text;
  try {
    text = py::repr(x).cast<std::string>();
  } catch (const py::error_already_set&) {
    text.clear();
  }
  if (PyLong_Check(x.ptr()) && (text.empty() || text.size() > 40))
    return "(an integer of " + py::str(x.attr("bit_length")()).cast<std::string>() + " bits)";
  if (text.size() > 40) return text.substr(0, 37) + "...";
  return text.empty() ? "(a " + std::string(Py_TYPE(x.ptr())->tp_name) + ")" : text;
}

/// Whether x is a real number as Python sees one: an int, a float, a numpy scalar; never a bool
/// (True is an int to Python, but a number given as True is a mistake) nor a complex number.
bool is_real_number(PyObject* x) {
  return !PyBool_Check(x) && PyNumber_Check(x) != 0 && !PyComplex_Check(x);
}

/// The Python int a whole number stands for: an int or numpy integer as it is, a float
/// without a fraction as its value; nothing for anything else (10.5, nan, inf, True, text).
std::optional<py::int_> as_whole(const py::handle& x) {
  PyObject* p = x.ptr();
  if (!is_real_number(p)) return std::nullopt;
  if (PyIndex_Check(p)) {  // int, numpy integers
    PyObject* n = PyNumber_Index(p);
    if (n == nullptr) {
      PyErr_Clear();
      return std::nullopt;
    }
    return py::reinterpret_steal<py::int_>(n);
  }
  const double d = PyFloat_AsDouble(p);  // float, numpy floats
  if (d == -1.0 && PyErr_Occurred() != nullptr) {
    PyErr_Clear();
    return std::nullopt;
  }
  if (!std::isfinite(d) || std::floor(d) != d) return std::nullopt;
  return py::reinterpret_steal<py::int_>(PyLong_FromDouble(d));
}

/// lo <= n <= hi, compared as Python ints (no overflow whatever n is).
bool in_range(const py::int_& n, const py::int_& lo, const py::int_& hi) {
  return PyObject_RichCompareBool(n.ptr(), lo.ptr(), Py_GE) == 1 &&
         PyObject_RichCompareBool(n.ptr(), hi.ptr(), Py_LE) == 1;
}

InputError not_whole(const py::handle& x, const std::string& what, const std::string& range) {
  return InputError(what + " " + value_text(x) + ": must be a whole number from " + range);
}

}  // namespace

long long whole_from_python(const py::handle& x,
                            const std::string& what,
                            long long lo,
                            long long hi) {
  const std::optional<py::int_> n = as_whole(x);
  if (!n || !in_range(*n, py::int_(lo), py::int_(hi)))
    throw not_whole(x, what, std::to_string(lo) + " to " + std::to_string(hi));
  return PyLong_AsLongLong(n->ptr());
}

std::uint64_t unsigned_from_python(const py::handle& x,
                                   const std::string& what,
                                   std::uint64_t lo,
                                   std::uint64_t hi) {
  const std::optional<py::int_> n = as_whole(x);
  if (!n || !in_range(*n, py::int_(lo), py::int_(hi)))
    throw not_whole(x, what, std::to_string(lo) + " to " + std::to_string(hi));
  return PyLong_AsUnsignedLongLong(n->ptr());
}

double real_from_python(const py::handle& x, const std::string& what) {
  PyObject* p = x.ptr();
  if (is_real_number(p)) {
    const double d = PyFloat_AsDouble(p);
    if (!(d == -1.0 && PyErr_Occurred() != nullptr)) return d;
    PyErr_Clear();
    if (PyLong_Check(p))  // beyond 1.8e308
      throw InputError(what + " " + value_text(x) + ": too large for a double-precision number");
  }
  throw InputError(what + " " + value_text(x) + ": not a number");
}

py::array_t<double> to_numpy(const VecX& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  auto out = a.mutable_unchecked<1>();
  for (Eigen::Index k = 0; k < v.size(); ++k) out(k) = v(k);
  return a;
}

py::object to_csr(const SpMatRow& M) {
  // A compressed row-major Eigen matrix is CSR: row k's entries are values[indptr[k] ..
  // indptr[k+1]) in the columns indices[...] (scipy's (data, indices, indptr) triple).
  SpMatRow C = M;
  C.makeCompressed();
  const auto nnz = static_cast<py::ssize_t>(C.nonZeros());
  py::array_t<double> data(nnz);
  py::array_t<int> indices(nnz);
  py::array_t<int> indptr(static_cast<py::ssize_t>(C.rows()) + 1);
  std::copy(C.valuePtr(), C.valuePtr() + nnz, data.mutable_data());
  std::copy(C.innerIndexPtr(), C.innerIndexPtr() + nnz, indices.mutable_data());
  std::copy(C.outerIndexPtr(), C.outerIndexPtr() + C.rows() + 1, indptr.mutable_data());
  const py::object csr_matrix = py::module_::import("scipy.sparse").attr("csr_matrix");
  return csr_matrix(py::make_tuple(data, indices, indptr),
                    py::arg("shape") = py::make_tuple(C.rows(), C.cols()));
}

py::object to_csr(const SpMat& M) { return to_csr(SpMatRow(M)); }

py::object cones_dict(const FrictionContacts& cones) {
  if (cones.empty()) return py::none();
  py::dict d;
  d["law"] = std::string(cone_law_name(cones.law));
  d["normal_row"] = cones.normal;
  d["mu"] = to_numpy(cones.mu);
  return d;
}

SpMat sparse_from_python(const py::handle& M, const std::string& what) {
  const py::module_ sparse = py::module_::import("scipy.sparse");
  py::object csr;
  try {
    // Any scipy.sparse format converts itself; a dense array or nested lists go through numpy.
    const py::object source =
        sparse.attr("issparse")(M).cast<bool>()
            ? py::reinterpret_borrow<py::object>(M)
            : py::module_::import("numpy").attr("asarray")(M, py::arg("dtype") = "float64");
    csr = sparse.attr("csr_matrix")(source, py::arg("dtype") = "float64");
  } catch (const py::error_already_set& e) {
    throw InputError(what + ": not a matrix of numbers (" + std::string(e.what()) + ")");
  }
  csr.attr("sum_duplicates")();  // scipy's convention, as read_matrix_market_sparse
  const auto shape = csr.attr("shape").cast<py::tuple>();
  const auto rows = shape[0].cast<long>();
  const auto cols = shape[1].cast<long>();
  const auto data = csr.attr("data").cast<py::array_t<double, py::array::c_style>>();
  const auto indices =
      csr.attr("indices").cast<py::array_t<long, py::array::c_style | py::array::forcecast>>();
  const auto indptr =
      csr.attr("indptr").cast<py::array_t<long, py::array::c_style | py::array::forcecast>>();
  const auto d = data.unchecked<1>();
  const auto col = indices.unchecked<1>();
  const auto ptr = indptr.unchecked<1>();
  std::vector<Triplet> entries;
  entries.reserve(static_cast<std::size_t>(d.shape(0)));
  for (long i = 0; i < rows; ++i) {
    for (long k = ptr(i); k < ptr(i + 1); ++k) {
      if (!std::isfinite(d(k)))
        throw InputError(what + ": entry (" + std::to_string(i) + ", " + std::to_string(col(k)) +
                         ") is " + number_text(d(k)) + "; every entry must be finite");
      entries.emplace_back(static_cast<int>(i), static_cast<int>(col(k)), d(k));
    }
  }
  SpMat A(rows, cols);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

VecX vector_from_python(const py::handle& v, const std::string& what, long size, bool infinite_ok) {
  py::array_t<double, py::array::c_style> a;
  try {
    a = py::module_::import("numpy").attr("asarray")(v, py::arg("dtype") = "float64");
  } catch (const py::error_already_set& e) {
    throw InputError(what + ": not a vector of numbers (" + std::string(e.what()) + ")");
  }
  // A vector, or one column (scipy.io.mmread reads a vector as n×1).
  const bool column = a.ndim() == 2 && a.shape(1) == 1;
  if (a.ndim() != 1 && !column) {
    std::string shape;
    for (py::ssize_t k = 0; k < a.ndim(); ++k) {
      if (k > 0) shape += ", ";
      shape += std::to_string(a.shape(k));
    }
    throw InputError(what + ": expected a vector (1-D array or one column), got shape (" + shape +
                     ")");
  }
  const long n = static_cast<long>(a.shape(0));
  if (size >= 0 && n != size)
    throw InputError(what + ": has " + std::to_string(n) + " entries, expected " +
                     std::to_string(size));
  VecX out(n);
  const double* p = a.data();
  for (long k = 0; k < n; ++k) {
    if (std::isnan(p[k]) || (!infinite_ok && std::isinf(p[k])))
      throw InputError(
          what + ": entry " + std::to_string(k) + " is " + number_text(p[k]) +
          (infinite_ok ? "; bounds may be infinite, never NaN" : "; every entry must be finite"));
    out(k) = p[k];
  }
  return out;
}

py::dict summary_dict(const SolverSummary& s) {
  py::dict d;
  d["iterations"] = s.iterations;
  d["residual"] = s.residual;
  d["delta"] = s.delta;
  d["termination"] = to_string(s.termination);
  d["message"] = s.message;
  d["wall_time_s"] = s.wall_time_s;
  d["factorizations"] = s.factorizations;
  d["pivots"] = s.pivots;
  d["restarts"] = s.restarts;
  d["islands"] = s.islands;
  d["singular"] = s.singular;
  d["crossover"] = s.crossover;
  d["factor_nnz"] = s.factor_nnz;
  d["updates"] = s.updates;
  d["space"] = s.space;
  d["route"] = s.route;  // direct: "guess", "warm", "interior", "active-set", "linear"
  // A peer's own word and times (siconos:NAME, bullet:NAME); None for cbps's methods.
  const bool peer = !s.peer_status.empty();
  d["peer_status"] = peer ? py::object(py::str(s.peer_status)) : py::none();
  d["peer_said_ok"] = peer ? py::object(py::bool_(s.peer_said_ok)) : py::none();
  d["peer_iterations"] =
      peer && s.peer_iterations >= 0 ? py::object(py::int_(s.peer_iterations)) : py::none();
  d["convert_time_s"] = peer ? py::object(py::float_(s.convert_time_s)) : py::none();
  d["peer_solve_time_s"] = peer ? py::object(py::float_(s.peer_solve_time_s)) : py::none();
  return d;
}

py::dict step_report_dict(const StepReport& r) {
  py::dict d;
  d["rows"] = r.rows;
  d["warm_rows"] = r.warm_rows;
  d["contacts"] = r.contacts;
  // The friction the step solved, from its system's contacts (summary.json's contacts.solved).
  d["friction_contacts"] = r.friction_contacts;
  d["mu_min"] = r.friction_contacts > 0 ? py::object(py::float_(r.mu_min)) : py::none();
  d["mu_max"] = r.friction_contacts > 0 ? py::object(py::float_(r.mu_max)) : py::none();
  d["friction_law"] =
      r.friction_contacts > 0 ? py::object(py::str(std::string(law_name(r.law)))) : py::none();
  d["iterations"] = r.solver.iterations;
  d["residual"] = r.solver.residual;
  d["termination"] = to_string(r.solver.termination);
  d["solver"] = summary_dict(r.solver);
  d["position_solver"] = summary_dict(r.position_solver);
  d["max_constraint_error"] = r.max_constraint_error;
  d["max_penetration"] = r.max_penetration;
  d["cfm_acceleration_error"] = r.cfm_acceleration_error;
  d["wall_time_s"] = r.wall_time_s;
  py::dict times;
  times["broad_phase"] = r.times.broad_phase;
  times["narrow_phase"] = r.times.narrow_phase;
  times["rows"] = r.times.rows;
  times["assembly"] = r.times.assembly;
  times["solve"] = r.times.solve;
  times["integrate"] = r.times.integrate;
  d["stage_times_s"] = times;
  return d;
}

void write_atomically(const std::string& path,
                      const std::string& what,
                      bool force,
                      const std::function<void(const std::string&)>& write) {
  check_output_file(path, what, force, "force=True replaces it");
  write_file_atomically(path, what, write);
}

}  // namespace cbps::python
