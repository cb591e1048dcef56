// Stored problems (stored_problem.hpp): `cbps matrices` folders, Siconos and FCLIB files.
#include "cbps/io/stored_problem.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/io/fclib_file.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/output_dir.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/io/siconos_fc3d.hpp"

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

/// A one-line text file holding x so that it reads back as the same double (dt.txt, cfm.txt).
void write_number_file(const std::string& path, double x) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g\n", x);
  std::ofstream out(path);
  out << text;
  out.flush();
  if (!out) throw std::runtime_error(path + ": write failed");
}

/// A folder's optional JSON file `name` (labels.json, cones.json): false when it is not there,
/// InputError naming it when it is not JSON.
bool read_json_file(const std::string& dir,
                    const char* name,
                    std::string& file,
                    nlohmann::json& out) {
  file = (fs::path(dir) / name).string();
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return false;
  std::ifstream in(file);
  try {
    out = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file + ": not JSON: " + e.what());
  }
  return true;
}

/// Row kinds and contact manifolds from a folder's labels.json (StoredProblem::kinds, blocks).
void read_row_labels(const std::string& dir, StoredProblem& p) {
  const auto rows = static_cast<std::size_t>(p.rows());
  p.blocks.assign(rows, -1);
  std::string file;
  nlohmann::json labels;
  if (!read_json_file(dir, "labels.json", file, labels)) return;
  if (!labels.is_object() || !labels.contains("rows") || !labels["rows"].is_array() ||
      labels["rows"].size() != rows)
    throw InputError(file + ": /rows: not one label per row of A.mtx");
  p.kinds.assign(rows, RowKind::Distance);
  int manifold = -1;
  std::string previous_pair;
  for (std::size_t k = 0; k < rows; ++k) {
    const nlohmann::json& label = labels["rows"][k];
    if (!label.is_string())
      throw InputError(file + ": /rows/" + std::to_string(k) + ": not a text label");
    p.labels.push_back(label.get<std::string>());
    std::istringstream words(p.labels.back());
    std::string kind, pair;
    words >> kind >> pair;
    if (kind != to_string(RowKind::Contact) && kind != to_string(RowKind::Friction)) {
      previous_pair.clear();
      continue;
    }
    p.kinds[k] = kind == to_string(RowKind::Contact) ? RowKind::Contact : RowKind::Friction;
    if (pair != previous_pair) ++manifold;
    previous_pair = pair;
    p.blocks[k] = manifold;
  }
}

/// The contacts in Coulomb's cone from a folder's cones.json (StoredProblem::cones; none without
/// one): {"law": "coulomb"|"ccp", "contacts": [{"normal_row": k, "mu": mu}, ...]}, each contact
/// owning rows k, k + 1, k + 2 (normal, t1, t2), in increasing row order.
void read_cones(const std::string& dir, StoredProblem& p) {
  std::string file;
  nlohmann::json cones;
  if (!read_json_file(dir, "cones.json", file, cones)) return;
  if (!cones.is_object() || !cones.contains("law") || !cones["law"].is_string() ||
      !cone_law_from_string(cones["law"].get<std::string>(), p.cones.law))
    throw InputError(file + ": /law: not \"coulomb\" or \"ccp\"");
  if (!cones.contains("contacts") || !cones["contacts"].is_array())
    throw InputError(file + ": /contacts: not an array");
  const nlohmann::json& contacts = cones["contacts"];
  std::vector<double> mu;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const nlohmann::json& contact = contacts[i];
    if (!contact.is_object() || !contact.contains("normal_row") ||
        !contact["normal_row"].is_number_integer() || !contact.contains("mu") ||
        !contact["mu"].is_number())
      throw InputError(file + ": /contacts/" + std::to_string(i) +
                       ": not {\"normal_row\": integer, \"mu\": number}");
    const auto n = contact["normal_row"].get<long long>();
    if (n < 0 || n >= p.rows())
      throw InputError(file + ": /contacts/" + std::to_string(i) +
                       "/normal_row: " + std::to_string(n) + " is not a row of A (" +
                       std::to_string(p.rows()) + " rows)");
    p.cones.normal.push_back(static_cast<int>(n));
    mu.push_back(contact["mu"].get<double>());
  }
  p.cones.mu = Eigen::Map<const VecX>(mu.data(), Eigen::Index(mu.size()));
  const std::string error = cone_contacts_error(p.cones, p.rows());
  if (!error.empty()) throw InputError(file + ": /contacts: " + error);
}

/// cones.json of read_cones.
void write_cones(const std::string& path, const FrictionContacts& cones) {
  nlohmann::json contacts = nlohmann::json::array();
  for (long i = 0; i < cones.contacts(); ++i)
    contacts.push_back(
        {{"normal_row", cones.normal[static_cast<std::size_t>(i)]}, {"mu", cones.mu(i)}});
  const nlohmann::json out = {
      {"note",
       "Coulomb's cone |lambda_t| <= mu lambda_n per contact (docs/cones.md): rows normal_row, "
       "normal_row + 1, normal_row + 2 (normal, t1, t2); cmin and cmax of these rows are not "
       "used"},
      {"law", std::string(cone_law_name(cones.law))},
      {"contacts", contacts}};
  write_text(path, out.dump(2) + "\n");
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
  read_row_labels(dir, p);
  read_cones(dir, p);
  return p;
}

StoredProblem read_dat(const std::string& path, SiconosKind kind) {
  if (kind == SiconosKind::FrictionContact ||
      (kind == SiconosKind::Auto && looks_like_siconos_fc3d(path)))
    return read_siconos_fc3d(path);
  const StoredLcp s = read_siconos(path, kind);
  StoredProblem p;
  p.without_jacobian = "a Siconos file carries no J and Minv";
  p.A = s.M.sparseView(0.0, 0.0);
  p.b = -s.q;
  p.cmin = s.lb;
  p.cmax = s.ub;
  check_bounds(p.b, p.cmin, p.cmax, path + " (lb)", path + " (ub)", path + " (q)");
  p.blocks.assign(static_cast<std::size_t>(p.rows()), -1);
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
  // A.mtx must be J Minv Jᵀ (6.2.9): the exact path factors J and Minv, the sweeps read A.
  const VecX x = factors_test_vector(0, p.rows());
  check_factors_agree(dir, factors_gap(p.A, x, times_factors(p.J, p.Minv, 0.0, x)));
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

StoredProblem stored_problem(const System& sys, double cfm) {
  StoredProblem p;
  p.A = sys.A;
  p.b = sys.b;
  p.cmin = sys.cmin;
  p.cmax = sys.cmax;
  p.J = sys.J;
  p.Minv = sys.Minv;
  p.v1 = sys.v1;
  p.fext = sys.fext;
  p.dt = sys.dt;
  p.cfm = cfm;
  p.kinds = sys.kind;
  p.blocks = sys.manifold;
  if (sys.cones() != nullptr) p.cones = *sys.cones();
  return p;
}

void write_problem(const StoredProblem& p, const FileSink& sink, const ProblemNotes& notes) {
  const auto matrix = [&](const char* name, const SpMat& M, const std::string& comment) {
    sink(name, [&](const std::string& path) { write_matrix_market(path, M, comment); });
  };
  const auto vector = [&](const char* name, const VecX& v, const std::string& comment) {
    sink(name, [&](const std::string& path) { write_matrix_market(path, v, comment); });
  };
  const auto number = [&](const char* name, double x) {
    sink(name, [&](const std::string& path) { write_number_file(path, x); });
  };
  matrix("A.mtx", p.A, "A = J Minv J^T, c x c, 1/kg (6.2.9)" + notes.A);
  vector("b.mtx", p.b, "b = upsilon/dt - J (v1/dt + Minv fext) (6.2.9)");
  vector("cmin.mtx", p.cmin, "cmin: lower bounds on lambda, N (5.1)" + notes.bounds);
  vector("cmax.mtx", p.cmax, "cmax: upper bounds on lambda, N (5.1)" + notes.bounds);
  const bool bodies = p.dt > 0.0;  // a step's system: all of J, Minv, v1, fext, dt known
  if (bodies || p.has_jacobian()) {
    matrix("J.mtx", SpMat(p.J), "J: c x 6n constraint Jacobian (6.1)");
    matrix("Minv.mtx", p.Minv, "Minv: 6n x 6n inverse mass (6.1.2)");
  }
  if (bodies) {
    vector("v1.mtx", p.v1, "v1: velocities, m/s and rad/s (6.1.1)");
    vector("fext.mtx", p.fext, "fext: forces and torques, N, N m (6.1.3)");
    number("dt.txt", p.dt);
  }
  if (p.cfm > 0.0) number("cfm.txt", p.cfm);
  if (!p.cones.empty())
    sink("cones.json", [&](const std::string& path) { write_cones(path, p.cones); });
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

StoredProblem read_problem(const std::string& path,
                           const std::string& siconos,
                           const std::string& cone) {
  const SiconosKind kind = parse_siconos_kind(siconos, "--siconos");
  std::error_code ec;
  if (kind != SiconosKind::Auto && (fs::is_directory(path, ec) || is_hdf5_file(path)))
    throw InputError(
        "--siconos " + siconos + ": says what a Siconos .dat file holds; " + path + " is " +
        (fs::is_directory(path, ec) ? "a cbps matrices folder" : "an HDF5 (FCLIB) file") +
        ", whose kind its files say");
  StoredProblem p = read_problem(path, kind);
  set_cone_law(p, cone, path);
  return p;
}

void set_cone_law(StoredProblem& p, const std::string& cone, const std::string& path) {
  if (cone.empty()) return;
  if (p.cones.empty())
    throw InputError("--cone " + cone + ": " + path +
                     " has no contacts in friction cones (a boxed problem); --cone is for an "
                     "FCLIB file");
  if (!cone_law_from_string(cone, p.cones.law))
    throw InputError("--cone " + cone + ": unknown; use coulomb or ccp");
}

StoredProblem read_problem(const std::string& path, SiconosKind kind) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) {
    if (is_hdf5_file(path)) return read_fclib(path);
    const std::string extension = fs::path(path).extension().string();
    if (fs::is_regular_file(path, ec) && (extension == ".hdf5" || extension == ".h5"))
      throw InputError(path + ": named as an HDF5 (FCLIB) file but not one: " +
                       (fs::file_size(path, ec) == 0 ? std::string("it is empty")
                                                     : std::string("no HDF5 signature")));
    return read_dat(path, kind);
  }
  StoredProblem p = read_folder(path);
  read_bodies(path, p);
  return p;
}

long folder_cone_contacts(const std::string& dir) {
  std::string file;
  nlohmann::json cones;
  if (!read_json_file(dir, "cones.json", file, cones)) return 0;
  if (!cones.is_object() || !cones.contains("contacts") || !cones["contacts"].is_array())
    throw InputError(file + ": /contacts: not an array");
  return static_cast<long>(cones["contacts"].size());
}

void check_factors_agree(const std::string& dir, const FactorsGap& gap) {
  if (gap.ratio() <= kFactorsTolerance) return;
  const auto file = [&](const char* name) { return (fs::path(dir) / name).string(); };
  throw InputError(file("A.mtx") + " and " + file("J.mtx") + ", " + file("Minv.mtx") +
                   ": A is not J Minv J^T (6.2.9): on the test vector x_k = sin(1 + k) the "
                   "largest |(A x - J Minv J^T x)_i| is " +
                   number_text(gap.difference) + " kg^-1 N, " + number_text(gap.ratio()) +
                   " of the largest sum_k |A_ik x_k| (round-off stays below " +
                   number_text(kFactorsTolerance) +
                   "); the files are not one step's. Write the folder again (cbps matrices), "
                   "or remove J.mtx and Minv.mtx to solve A.mtx alone");
}

void require_symmetric(const StoredProblem& p, const std::string& what) {
  if (!p.cones.empty()) return;  // on cones direct takes any A (needs_symmetric)
  const double asymmetry = max_asymmetry(p.A);
  if (asymmetry > symmetry_tolerance(p.A))
    throw InputError(
        what + ": needs a symmetric A (the direct path solves the QP of 6.2); max |A - A^T| = " +
        number_text(asymmetry) + "; " + "`cbps lcp --solver lemke` solves any square A");
}

}  // namespace cbps
