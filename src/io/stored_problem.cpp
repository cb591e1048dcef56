// Stored problems (stored_problem.hpp): `cbps matrices` folders and Siconos files.
#include "cbps/io/stored_problem.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/siconos.hpp"

namespace cbps {

namespace {

namespace fs = std::filesystem;

/// The one number of a one-line text file such as dt.txt or cfm.txt.
double read_number_file(const std::string& path, const char* what) {
  std::ifstream in(path);
  std::string text;
  in >> text;
  double x = 0.0;
  if (!parse_number(text, x) || !std::isfinite(x))
    throw InputError(path + ": line 1: '" + text + "' is not " + what);
  return x;
}

StoredProblem read_folder(const std::string& dir) {
  const auto file = [&](const char* name) { return (fs::path(dir) / name).string(); };
  StoredProblem p;
  p.folder = true;
  p.A = read_matrix_market_sparse(file("A.mtx"));
  p.b = read_matrix_market_vector(file("b.mtx"));
  p.cmin = read_matrix_market_vector(file("cmin.mtx"));
  p.cmax = read_matrix_market_vector(file("cmax.mtx"));
  const long c = p.A.rows();
  if (p.A.cols() != c)
    throw InputError(file("A.mtx") + ": A is " + std::to_string(c) + " x " +
                     std::to_string(p.A.cols()) + ", not square");
  for (const auto& [name, v] : {std::pair<const char*, const VecX*>{"b.mtx", &p.b},
                                {"cmin.mtx", &p.cmin},
                                {"cmax.mtx", &p.cmax}}) {
    if (v->size() != c)
      throw InputError(file(name) + ": has " + std::to_string(v->size()) + " rows, A has " +
                       std::to_string(c));
  }
  check_bounds(p.b, p.cmin, p.cmax, file("cmin.mtx"), file("cmax.mtx"), file("b.mtx"));
  p.cfm = read_cfm(dir);
  return p;
}

StoredProblem read_dat(const std::string& path, SiconosKind kind) {
  const StoredLcp s = read_siconos(path, kind);
  StoredProblem p;
  p.without_jacobian = "a Siconos file carries no J and Minv";
  p.A = s.M.sparseView(0.0, 0.0);
  p.b = -s.q;
  p.cmin = s.lb;
  p.cmax = s.ub;
  check_bounds(p.b, p.cmin, p.cmax, path + " (lb)", path + " (ub)", path + " (q)");
  return p;
}

/// The system's own matrices (6.1): J and Minv whenever the folder has both (what body space
/// needs), v1, fext and dt when it has those three as well (what v2 needs).
void read_bodies(const std::string& dir, StoredProblem& p) {
  const auto file = [&](const char* name) { return (fs::path(dir) / name).string(); };
  const auto present = [&](const char* name) {
    std::error_code ec;
    return fs::is_regular_file(file(name), ec);
  };
  const bool has_J = present("J.mtx"), has_Minv = present("Minv.mtx");
  if (!has_J || !has_Minv) {
    p.without_jacobian = !has_J && !has_Minv ? "no J.mtx and no Minv.mtx in the folder"
                         : !has_J            ? "no J.mtx in the folder"
                                             : "no Minv.mtx in the folder";
    return;
  }
  p.J = read_matrix_market_sparse(file("J.mtx"));
  p.Minv = read_matrix_market_sparse(file("Minv.mtx"));
  const long n6 = p.J.cols();
  if (p.J.rows() != p.rows() || p.Minv.rows() != n6 || p.Minv.cols() != n6)
    throw InputError(dir + ": J and Minv do not fit each other or A (J is " +
                     std::to_string(p.J.rows()) + " x " + std::to_string(n6) + ", Minv " +
                     std::to_string(p.Minv.rows()) + " x " + std::to_string(p.Minv.cols()) +
                     ", A has " + std::to_string(p.rows()) + " rows)");
  if (p.rows() == 0) p.without_jacobian = "no rows";
  for (const char* name : {"v1.mtx", "fext.mtx", "dt.txt"})
    if (!present(name)) return;
  const double dt = read_number_file(file("dt.txt"), "a positive time step in s");
  if (!(dt > 0.0))
    throw InputError(file("dt.txt") + ": line 1: " + number_text(dt) +
                     " is not a positive time step");
  p.v1 = read_matrix_market_vector(file("v1.mtx"));
  p.fext = read_matrix_market_vector(file("fext.mtx"));
  p.dt = dt;
  if (p.v1.size() != n6 || p.fext.size() != n6)
    throw InputError(dir + ": v1 and fext do not fit J (J is " + std::to_string(p.J.rows()) +
                     " x " + std::to_string(n6) + ", v1 has " + std::to_string(p.v1.size()) +
                     " rows, fext " + std::to_string(p.fext.size()) + ")");
}

}  // namespace

void check_bounds(const VecX& b,
                  const VecX& cmin,
                  const VecX& cmax,
                  const std::string& cmin_file,
                  const std::string& cmax_file,
                  const std::string& b_file,
                  long first_row) {
  const auto fail =
      [first_row](
          const std::string& file, const char* name, Eigen::Index k, double x, const char* why) {
        std::ostringstream msg;
        msg << file << ": " << name << "[" << first_row + k << "] = " << number_text(x) << ": "
            << why;
        throw InputError(msg.str());
      };
  for (Eigen::Index k = 0; k < b.size(); ++k) {
    if (std::isnan(cmin(k)) || cmin(k) == kInf)
      fail(cmin_file, "cmin", k, cmin(k), "a lower bound must be a number or -inf");
    if (std::isnan(cmax(k)) || cmax(k) == -kInf)
      fail(cmax_file, "cmax", k, cmax(k), "an upper bound must be a number or +inf");
    if (cmin(k) > cmax(k)) fail(cmin_file, "cmin", k, cmin(k), "above cmax, no lambda fits");
    if (!std::isfinite(b(k))) fail(b_file, "b", k, b(k), "not finite");
  }
}

double read_cfm(const std::string& dir) {
  const std::string path = (fs::path(dir) / "cfm.txt").string();
  std::error_code ec;
  if (!fs::exists(path, ec)) return 0.0;
  const double cfm = read_number_file(path, "a constraint-force mixing eps >= 0 in kg^-1");
  if (cfm < 0.0)
    throw InputError(path + ": line 1: eps = " + number_text(cfm) + " kg^-1 is negative");
  return cfm;
}

StoredProblem read_problem(const std::string& path, SiconosKind kind) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return read_dat(path, kind);
  StoredProblem p = read_folder(path);
  read_bodies(path, p);
  return p;
}

void require_symmetric(const StoredProblem& p, const std::string& what) {
  const double asymmetry = max_asymmetry(p.A);
  if (asymmetry > symmetry_tolerance(p.A))
    throw InputError(what +
                     ": needs a symmetric A (the direct path solves the QP of 6.2); max |A - "
                     "A^T| = " +
                     number_text(asymmetry) + "; `cbps lcp --solver lemke` solves any square A");
}

}  // namespace cbps
