// Stored problems for Python: the readers `cbps lcp` and `cbps converge` use (a `cbps matrices`
// folder, a Siconos .dat file, single Matrix Market files) and writers for the same formats, so
// a problem made in Python can be handed to the command line; and `cbps verify`'s checks. Every
// file is written to a temporary name beside it and renamed into place.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cbps/base/error.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/studies/verify.hpp"
#include "convert.hpp"

namespace cbps::python {

namespace {

namespace fs = std::filesystem;

/// The text of a number that reads back to the same double.
std::string exact(double x) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

void write_text_file(const std::string& path, const std::string& text, bool force) {
  write_atomically(path, path, force, [&](const std::string& temp) {
    std::ofstream out(temp);
    out << text;
    out.close();
    if (!out) throw std::runtime_error("cannot write " + temp);
  });
}

void write_sparse(const std::string& path, const SpMat& M, const std::string& comment, bool force) {
  write_atomically(
      path, path, force, [&](const std::string& temp) { write_matrix_market(temp, M, comment); });
}

void write_vector(const std::string& path, const VecX& v, const std::string& comment, bool force) {
  write_atomically(
      path, path, force, [&](const std::string& temp) { write_matrix_market(temp, v, comment); });
}

/// write_problem: the files `cbps matrices` writes that read_problem and `cbps lcp` read.
void write_problem(const std::string& folder,
                   const py::object& A_in,
                   const py::object& b_in,
                   const py::object& cmin_in,
                   const py::object& cmax_in,
                   const py::object& J_in,
                   const py::object& Minv_in,
                   const py::object& v1_in,
                   const py::object& fext_in,
                   const py::object& dt_in,
                   const py::object& cfm_in,
                   bool force) {
  const double cfm = real_from_python(cfm_in, "cfm");
  const SpMat A = sparse_from_python(A_in, "A");
  const long c = A.rows();
  if (A.cols() != c) throw InputError("A: must be square");
  const VecX b = vector_from_python(b_in, "b", c);
  const VecX cmin = vector_from_python(cmin_in, "cmin", c, true);
  const VecX cmax = vector_from_python(cmax_in, "cmax", c, true);
  const bool bodies = !J_in.is_none() || !Minv_in.is_none() || !v1_in.is_none() ||
                      !fext_in.is_none() || !dt_in.is_none();
  if (bodies && (J_in.is_none() || Minv_in.is_none() || v1_in.is_none() || fext_in.is_none() ||
                 dt_in.is_none()))
    throw InputError("write_problem: J, Minv, v1, fext and dt go together (all or none)");
  if (!(cfm >= 0.0) || !std::isfinite(cfm))
    throw InputError("cfm " + number_text(cfm) + ": must be a finite number >= 0");
  // What read_problem refuses (cmin[k] > cmax[k]: no lambda fits, 5.1), refused before any
  // file is written, in the reader's words.
  check_bounds(b, cmin, cmax, "write_problem", "write_problem", "write_problem");
  StoredProblem p;
  p.A = A;
  p.b = b;
  p.cmin = cmin;
  p.cmax = cmax;
  p.cfm = cfm;
  if (bodies) {
    const SpMat J = sparse_from_python(J_in, "J");
    const SpMat Minv = sparse_from_python(Minv_in, "Minv");
    if (J.rows() != c || Minv.rows() != J.cols() || Minv.cols() != J.cols())
      throw InputError("J, Minv: J must be c x 6n and Minv 6n x 6n, c = " + std::to_string(c));
    p.J = J;
    p.Minv = Minv;
    p.v1 = vector_from_python(v1_in, "v1", J.cols());
    p.fext = vector_from_python(fext_in, "fext", J.cols());
    p.dt = real_from_python(dt_in, "dt");
    if (!(p.dt > 0.0) || !std::isfinite(p.dt))
      throw InputError("dt " + number_text(p.dt) + ": must be a positive finite time in s");
  }
  std::error_code ec;
  if (!fs::is_directory(folder, ec) && !fs::create_directory(folder, ec))
    throw InputError(folder + ": cannot make the folder: " + ec.message());
  cbps::write_problem(p, [&](const std::string& name, const auto& write) {
    const std::string path = (fs::path(folder) / name).string();
    write_atomically(path, path, force, write);
  });
}

/// write_siconos: the dense layout siconos.hpp reads, M = A, q = −b (and lb = cmin, ub = cmax
/// for a relay problem). M's lines are its columns (Siconos' column-major order).
void write_siconos(const std::string& path,
                   const py::object& A_in,
                   const py::object& b_in,
                   const py::object& cmin_in,
                   const py::object& cmax_in,
                   bool force) {
  const MatX M = MatX(sparse_from_python(A_in, "A"));
  const long n = M.rows();
  if (M.cols() != n) throw InputError("A: must be square");
  if (n < 1 || n > kMaxSiconosSize)
    throw InputError("A: " + std::to_string(n) + " rows; a Siconos file holds 1 to " +
                     std::to_string(kMaxSiconosSize));
  const VecX b = vector_from_python(b_in, "b", n);
  const bool given = !cmin_in.is_none() || !cmax_in.is_none();
  if (given && (cmin_in.is_none() || cmax_in.is_none()))
    throw InputError("write_siconos: give both cmin and cmax, or neither (a standard LCP)");
  const VecX lb = given ? vector_from_python(cmin_in, "cmin", n, true) : VecX::Zero(n);
  const VecX ub = given ? vector_from_python(cmax_in, "cmax", n, true) : VecX::Constant(n, kInf);
  check_bounds(b, lb, ub, "write_siconos", "write_siconos", "write_siconos");  // as the reader
  const bool relay = !((lb.array() == 0.0).all() && (ub.array() == kInf).all());
  if (relay && !(lb.allFinite() && ub.allFinite()))
    throw InputError(
        "write_siconos: a relay problem's bounds must be finite in a Siconos file; "
        "only the standard LCP (cmin = 0, cmax = inf) may be unbounded");
  std::string text = std::to_string(n) + "\n0\n" + std::to_string(n) + " " + std::to_string(n) +
                     "\n" + std::to_string(n) + " " + std::to_string(n) + "\n";
  const auto line = [&](const auto& entry) {
    for (long i = 0; i < n; ++i) {
      if (i > 0) text += ' ';
      text += exact(entry(i));
    }
    text += "\n";
  };
  for (long j = 0; j < n; ++j) line([&](long i) { return M(i, j); });  // column j of M
  line([&](long i) { return -b(i); });                                 // q = −b
  if (relay) {
    line([&](long i) { return lb(i); });
    line([&](long i) { return ub(i); });
  }
  write_text_file(path, text, force);
}

SiconosKind kind_of(const std::string& kind) { return parse_siconos_kind(kind, "kind"); }

/// cbps.Problem: a stored boxed problem's matrices and vectors.
void bind_problem(py::module_& m) {
  py::class_<StoredProblem>(m,
                            "Problem",
                            "A stored boxed problem (6.2): A (csr), b, cmin, cmax; J and Minv "
                            "where it has them (a `cbps matrices` folder, an FCLIB global "
                            "problem of rigid bodies), v1, fext, dt from a folder with all of "
                            "them (else None), and cfm.")
      .def_property_readonly("A", [](const StoredProblem& p) { return to_csr(p.A); })
      .def_property_readonly("b", [](const StoredProblem& p) { return to_numpy(p.b); })
      .def_property_readonly("cmin", [](const StoredProblem& p) { return to_numpy(p.cmin); })
      .def_property_readonly("cmax", [](const StoredProblem& p) { return to_numpy(p.cmax); })
      .def_property_readonly("J",
                             [](const StoredProblem& p) -> py::object {
                               return p.has_jacobian() ? to_csr(p.J) : py::none();
                             })
      .def_property_readonly("Minv",
                             [](const StoredProblem& p) -> py::object {
                               return p.has_jacobian() ? to_csr(p.Minv) : py::none();
                             })
      .def_property_readonly("v1",
                             [](const StoredProblem& p) -> py::object {
                               return p.has_bodies() ? py::object(to_numpy(p.v1)) : py::none();
                             })
      .def_property_readonly("fext",
                             [](const StoredProblem& p) -> py::object {
                               return p.has_bodies() ? py::object(to_numpy(p.fext)) : py::none();
                             })
      .def_property_readonly("dt",
                             [](const StoredProblem& p) -> py::object {
                               return p.has_bodies() ? py::object(py::float_(p.dt)) : py::none();
                             })
      .def_property_readonly(
          "cones",
          [](const StoredProblem& p) { return cones_dict(p.cones); },
          "the contacts in Coulomb's cone (a folder's cones.json, an FCLIB file): {'law', "
          "'normal_row', 'mu'}; None for a boxed problem")
      .def_readonly("cfm", &StoredProblem::cfm, "eps of the folder's cfm.txt, 1/kg (0: none)")
      .def_readonly("folder", &StoredProblem::folder, "read from a `cbps matrices` folder")
      .def_property_readonly("rows", &StoredProblem::rows)
      .def("__repr__", [](const StoredProblem& p) {
        return "<cbps.Problem: " + std::to_string(p.rows()) + " rows" +
               (p.has_bodies() ? ", with J and Minv>" : ">");
      });
}

/// The readers: a problem folder or file, a Siconos file, Matrix Market files.
void bind_readers(py::module_& m) {
  // The Siconos kind as text ("auto", "lcp", "relay"), as `cbps lcp --siconos`.
  m.def(
      "read_problem",
      [](const std::string& path, const std::string& kind) {
        return read_problem(path, kind_of(kind));
      },
      py::arg("path"),
      py::arg("kind") = "auto",
      "a `cbps matrices` folder or a Siconos .dat file (kind: auto, lcp or relay), as `cbps lcp` "
      "reads it; InputError naming the file and line");
  m.def(
      "read_siconos",
      [](const std::string& path, const std::string& kind) {
        const StoredLcp lcp = read_siconos(path, kind_of(kind));
        StoredProblem p;  // M = A, q = −b, lb = cmin, ub = cmax (stored_problem.hpp)
        p.A = lcp.M.sparseView();
        p.b = -lcp.q;
        p.cmin = lcp.lb;
        p.cmax = lcp.ub;
        return p;
      },
      py::arg("path"),
      py::arg("kind") = "auto",
      "a Siconos .dat file as a Problem (A = M, b = -q, cmin = lb, cmax = ub)");
  m.def(
      "read_matrix_market_sparse",
      [](const std::string& path) { return to_csr(read_matrix_market_sparse(path)); },
      py::arg("path"),
      "a coordinate Matrix Market file as scipy.sparse.csr_matrix");
  m.def(
      "read_matrix_market_vector",
      [](const std::string& path) { return to_numpy(read_matrix_market_vector(path)); },
      py::arg("path"),
      "an n x 1 array Matrix Market file as a 1-D array (inf and -inf allowed)");
}

/// The writers: Matrix Market files, a problem folder, a Siconos file.
void bind_writers(py::module_& m) {
  m.def(
      "write_matrix_market",
      [](const std::string& path, const py::object& M, const std::string& comment, bool force) {
        const bool sparse = py::module_::import("scipy.sparse").attr("issparse")(M).cast<bool>();
        const auto ndim = sparse ? 2 : py::module_::import("numpy").attr("ndim")(M).cast<int>();
        if (ndim == 2) {
          write_sparse(path, sparse_from_python(M, path), comment, force);
        } else {
          write_vector(path, vector_from_python(M, path, -1, true), comment, force);
        }
      },
      py::arg("path"),
      py::arg("M"),
      py::arg("comment") = "",
      py::arg("force") = false,
      "a matrix (scipy.sparse or 2-D) as coordinate Matrix Market, a 1-D vector as array; an "
      "existing file is replaced only with force=True");
  m.def("write_problem",
        &write_problem,
        py::arg("folder"),
        py::arg("A"),
        py::arg("b"),
        py::arg("cmin"),
        py::arg("cmax"),
        py::kw_only(),
        py::arg("J") = py::none(),
        py::arg("Minv") = py::none(),
        py::arg("v1") = py::none(),
        py::arg("fext") = py::none(),
        py::arg("dt") = py::none(),
        py::arg("cfm") = 0.0,
        py::arg("force") = false,
        "writes a problem folder as `cbps matrices` does (A.mtx, b.mtx, cmin.mtx, cmax.mtx; "
        "J.mtx, Minv.mtx, v1.mtx, fext.mtx, dt.txt when J is given; cfm.txt when cfm > 0), "
        "which read_problem, `cbps lcp` and `cbps converge` read");
  m.def("write_siconos",
        &write_siconos,
        py::arg("path"),
        py::arg("A"),
        py::arg("b"),
        py::arg("cmin") = py::none(),
        py::arg("cmax") = py::none(),
        py::kw_only(),
        py::arg("force") = false,
        "writes a dense Siconos .dat file: an LCP (M = A, q = -b) when the bounds are 0 and "
        "inf (or not given), else a relay problem (finite bounds only)");
}

}  // namespace

void bind_io(py::module_& m) {
  bind_problem(m);
  bind_readers(m);
  bind_writers(m);
  m.def(
      "verify",
      [] {
        std::vector<Check> checks;
        {
          const py::gil_scoped_release release;
          checks = run_derivation_checks();
        }
        py::list out;
        for (const Check& c : checks) {
          py::dict d;
          d["equation"] = c.equation;
          d["what"] = c.what;
          d["error"] = c.error;
          d["tolerance"] = c.tolerance;
          d["pass"] = c.pass();
          out.append(d);
        }
        return out;
      },
      "the derivation checks of `cbps verify`: dicts of equation, what, error, tolerance, pass");
}

}  // namespace cbps::python
