// Eigen ↔ numpy / scipy.sparse for the Python module (convert.hpp).
#include "convert.hpp"

#include <cmath>
#include <string>

#include "cbps/error.hpp"
#include "cbps/io/output_file.hpp"

namespace cbps::python {

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
  return d;
}

py::dict step_report_dict(const StepReport& r) {
  py::dict d;
  d["rows"] = r.rows;
  d["warm_rows"] = r.warm_rows;
  d["contacts"] = r.contacts;
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
