// Stored problems (problem.hpp): `cbps matrices` folders and Siconos files.
#include "problem.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cbps/error.hpp"
#include "cbps/matrix_market.hpp"
#include "cbps/scenes.hpp"
#include "cbps/siconos.hpp"

namespace cbps::cli {

namespace {

namespace fs = std::filesystem;

Problem read_folder(const std::string& dir) {
  const auto file = [&](const char* name) { return (fs::path(dir) / name).string(); };
  Problem p;
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
  for (long k = 0; k < c; ++k) {
    if (p.cmin(k) > p.cmax(k))
      throw InputError(file("cmin.mtx") + ": line " + std::to_string(k + 3) + ": cmin[" +
                       std::to_string(k) + "] > cmax[" + std::to_string(k) + "]");
    if (!std::isfinite(p.b(k)))
      throw InputError(file("b.mtx") + ": b[" + std::to_string(k) + "] is not finite");
  }
  return p;
}

Problem read_dat(const std::string& path) {
  const StoredLcp s = read_siconos(path, siconos_is_relay(path));
  Problem p;
  p.A = s.M.sparseView(0.0, 0.0);
  p.b = -s.q;
  p.cmin = s.lb;
  p.cmax = s.ub;
  return p;
}

/// The system's own matrices, when the folder has all of them (6.1).
void read_bodies(const std::string& dir, Problem& p) {
  const auto file = [&](const char* name) { return (fs::path(dir) / name).string(); };
  for (const char* name : {"J.mtx", "Minv.mtx", "v1.mtx", "fext.mtx", "dt.txt"}) {
    std::error_code ec;
    if (!fs::is_regular_file(file(name), ec)) return;
  }
  std::ifstream in(file("dt.txt"));
  std::string text;
  in >> text;
  double dt = 0.0;
  if (!parse_number(text, dt) || !(dt > 0.0))
    throw InputError(file("dt.txt") + ": line 1: '" + text + "' is not a positive time step");
  p.J = read_matrix_market_sparse(file("J.mtx"));
  p.Minv = read_matrix_market_sparse(file("Minv.mtx"));
  p.v1 = read_matrix_market_vector(file("v1.mtx"));
  p.fext = read_matrix_market_vector(file("fext.mtx"));
  p.dt = dt;
  const long n6 = p.J.cols();
  if (p.J.rows() != p.rows() || p.Minv.rows() != n6 || p.Minv.cols() != n6 || p.v1.size() != n6 ||
      p.fext.size() != n6)
    throw InputError(dir + ": J, Minv, v1 and fext do not fit each other or A (J is " +
                     std::to_string(p.J.rows()) + " x " + std::to_string(n6) + ")");
}

}  // namespace

Problem read_problem(const std::string& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return read_dat(path);
  Problem p = read_folder(path);
  read_bodies(path, p);
  return p;
}

double scale_of(const Problem& p) {
  double s = 1.0;
  if (p.b.size() > 0) s = std::max(s, p.b.lpNorm<Eigen::Infinity>());
  for (Eigen::Index j = 0; j < p.A.outerSize(); ++j)
    for (SpMat::InnerIterator it(p.A, j); it; ++it) s = std::max(s, std::abs(it.value()));
  return s;
}

}  // namespace cbps::cli
