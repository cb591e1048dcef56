// The one table of methods (methods.hpp): each method's entry and solve function, the names
// the grammar accepts, each method's own keys.
#include "cbps/solvers/methods.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/solvers/compared/admm.hpp"
#include "cbps/solvers/compared/apgd.hpp"
#include "cbps/solvers/compared/nncg.hpp"
#include "cbps/solvers/compared/pgs_block.hpp"
#include "cbps/solvers/compared/pgs_nesterov.hpp"
#include "cbps/solvers/compared/pgs_sm.hpp"
#include "cbps/solvers/compared/rbgs.hpp"
#include "cbps/solvers/compared/shock.hpp"
#include "cbps/solvers/cone/cone_direct.hpp"
#include "cbps/solvers/cone/nsgs.hpp"
#include "cbps/solvers/exact/active_set.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/exact/lemke.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/paper/pgs_matrix_free.hpp"
#include "cbps/solvers/peers/peers.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps {

namespace {

// Adapters: the methods whose solve function takes their own settings (method_settings.hpp), and
// the two that choose a path by the problem.
SolverSummary pgs_nesterov(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_pgs_nesterov(p, lambda, o, o.methods.pgs_nesterov);
}
SolverSummary apgd(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_apgd(p, lambda, o, o.methods.apgd);
}
SolverSummary nncg(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_nncg(p, lambda, o, o.methods.nncg);
}
SolverSummary pgs_sm(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_pgs_sm(p, lambda, o, o.methods.pgs_sm);
}
SolverSummary admm(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_admm(p, lambda, o, o.methods.admm);
}
SolverSummary shock(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_shock(p, lambda, o, o.methods.shock);
}

/// "direct": on friction cones their second-order-cone form (cone/cone_direct.hpp); on the boxed
/// problem the exact path (exact/direct.hpp) aiming at the tolerance read both as N and as a
/// unit-free residual (UnitFreeTarget::both, at λ = 0: the force scale b alone calls for), the
/// rounding floor still stopping it.
SolverSummary direct(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  if (problem.cones != nullptr) return solve_cone_direct(problem, lambda, options);
  SolverOptions aimed = options;
  aimed.tolerance = unit_free_target(problem).both(options.tolerance, VecX());
  return solve_direct(problem, lambda, aimed);
}

/// "lemke": the dense pivoting method of lemke.hpp on M = A, q = −b (the standard LCP when
/// cmin = 0 and cmax = +inf, else the boxed one), verified on the problem itself: Direct when
/// cbps's verdict holds (is_solved, system/unit_free.hpp). A ray termination whose
/// last point passes that check is a solution, and is reported as one, with the ray named.
SolverSummary lemke(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const long c = problem.rows();
  if (c > kMaxDenseLemkeRows)
    throw InputError("lemke: the problem has " + std::to_string(c) +
                     " rows; the dense Lemke solver takes at most " +
                     std::to_string(kMaxDenseLemkeRows) + " (use pgs or direct)");
  const MatX M = MatX(problem.A);
  const VecX q = -problem.b;
  const bool standard = (problem.cmin.array() == 0.0).all() && (problem.cmax.array() == kInf).all();
  const LcpResult r = standard
                          ? solve_lemke(M, q, options.deadline)
                          : solve_boxed_lemke(M, q, problem.cmin, problem.cmax, options.deadline);
  lambda = r.z.size() == c ? r.z : VecX::Zero(c);
  SolverSummary s;
  s.iterations = r.pivots;
  s.pivots = r.pivots;
  s.residual = natural_map_residual(problem, lambda);
  const UnitFreeResidual unit_free = unit_free_residual(problem, lambda);
  const bool passes = is_solved(unit_free, lambda);
  s.message = r.message;
  if (passes) {
    s.termination = Termination::Direct;
    if (!r.solved()) {
      std::ostringstream msg;
      msg << "Lemke: solved: its last point has unit-free residual " << unit_free.relative
          << " <= " << kSolvedTolerance << " (" << s.residual << " N)"
          << ", although the pivoting ended "
          << (r.status == LcpResult::Status::NoSolution ? "in a ray termination"
                                                        : "without a verified basis")
          << " after " << r.pivots << " pivots";
      s.message = msg.str();
    }
  } else {
    s.termination = !lambda.allFinite()                         ? Termination::NonFinite
                    : r.status == LcpResult::Status::NoSolution ? Termination::NoSolution
                                                                : Termination::NotConverged;
  }
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

constexpr unsigned kBothLaws = kRelaxationLaw | kCoulombLaw;

// The peers' row limits: they work on a dense copy of A.
constexpr long kDenseRows = kMaxDenseLemkeRows;  ///< 72 MB at 3000 rows, as cbps's own lemke
constexpr long kEnumerationRows = 20;  ///< 2^c cases (2^(2c) for a boxed pair): 10^6 at 20 rows
constexpr long kTableauRows = 1000;    ///< a dense inverse of A, a 2c x 4c tableau: 64 MB
constexpr long kDenseConeRows = 6000;  ///< a dense W of 288 MB: the 1,600-contact pyramid's rows

/// The methods, in the order --help lists them. The traits' defaults (methods.hpp): iterative,
/// cbps's own, reads A and no J, any A, no cones.
constexpr MethodEntry kEntries[] = {
    {.method = Method::Pgs,
     .name = "pgs",
     .order = true,
     .contacts_first = true,
     .sweeps_alone = true,
     .solve = solve_pgs,
     .what = "projected Gauss-Seidel, the paper's 7.1.1"},
    {.method = Method::Sgs,
     .name = "sgs",
     .omega = true,
     .sweeps_alone = true,
     .solve = solve_sgs,
     .what = "symmetric Gauss-Seidel, a forward and a backward sweep"},
    {.method = Method::Jacobi,
     .name = "jacobi",
     .omega = true,
     .damping = true,
     .sweeps_alone = true,
     .solve = solve_jacobi,
     .what = "projected Jacobi; jacobi:OMEGA damps it, (0, 1]"},
    {.method = Method::BlockPgs,
     .name = "block-pgs",
     .sweeps_alone = true,
     .solve = solve_block_pgs,
     .what = "PGS with each contact manifold solved whole"},
    {.method = Method::MatrixFree,
     .name = "matrix-free",
     .order = true,
     .contacts_first = true,
     .needs_jacobian = true,
     .sweeps_factors = true,
     .sweeps_alone = true,
     .reads_A = false,
     .reads_A_on_cones = false,
     .solve = solve_matrix_free,
     .what = "7.1.1 on J and Minv, without A"},
    {.method = Method::PgsNesterov,
     .name = "pgs-nesterov",
     .omega = true,
     .order = true,
     .laws = kRelaxationLaw,
     .solve = pgs_nesterov,
     .what = "PGS with Nesterov momentum and adaptive restart (O'Donoghue & Candes 2015); "
             "restart=on|off"},
    {.method = Method::Apgd,
     .name = "apgd",
     .symmetric = true,
     .symmetric_on_cones = true,
     .laws = kRelaxationLaw,
     .solve = apgd,
     .what = "accelerated projected gradient descent (Mazhar et al. 2015); grow=, shrink=, "
             "restart=on|off"},
    {.method = Method::Nncg,
     .name = "nncg",
     .symmetric = true,
     .symmetric_on_cones = true,
     .solve = nncg,
     .what = "nonsmooth nonlinear conjugate gradient on PGS sweeps (Silcowitz, Niebe & Erleben "
             "2010); restart_beta="},
    {.method = Method::PgsSm,
     .name = "pgs-sm",
     .symmetric = true,
     .symmetric_on_cones = true,
     .solve = pgs_sm,
     .what = "PGS with subspace minimization by CG (Silcowitz, Niebe & Erleben 2010); sweeps=, "
             "cg=, cg_tolerance="},
    {.method = Method::Admm,
     .name = "admm",
     .symmetric = true,
     .symmetric_on_cones = true,
     .laws = kRelaxationLaw,
     .solve = admm,
     .what = "ADMM with one factor of A + rho E (Boyd et al. 2011); rho=, alpha=, adapt=on|off, "
             "rho_min="},
    {.method = Method::Rbgs,
     .name = "rbgs",
     .omega = true,
     .solve = solve_rbgs,
     .what = "red-black (graph-coloured) PGS, the parallel engines' order"},
    {.method = Method::Shock,
     .name = "shock",
     .omega = true,
     .needs_jacobian = true,
     .solve = shock,
     .what = "PGS level by level from the ground up (Guendelman, Bridson & Fedkiw 2003); "
             "level_sweeps=, direction=up|down"},
    {.method = Method::Direct,
     .name = "direct",
     .iterative = false,
     .reads_A = false,
     .symmetric = true,
     .laws = kBothLaws,
     .solve = direct,
     .what = "the exact path: interior point, then active set"},
    {.method = Method::ActiveSet,
     .name = "active-set",
     .iterative = false,
     .symmetric = true,
     .symmetric_on_cones = true,
     .solve = solve_active_set,
     .what = "the previous exact path, for comparison"},
    {.method = Method::Lemke,
     .name = "lemke",
     .iterative = false,
     .max_rows = kMaxDenseLemkeRows,
     .solve = lemke,
     .what = "Lemke's complementary pivoting on the dense A: any square A, at most 3000 rows"},
    {.method = Method::Nsgs,
     .name = "nsgs",
     .laws = kBothLaws,
     .solve = solve_nsgs,
     .what = "non-smooth Gauss-Seidel: 7.1.1 with each contact's rows projected onto its friction "
             "cone (Jean & Moreau 1992); local=; PGS where no row is in a cone"},
    // The peers (solvers/peers/peers.hpp, docs/peers.md), in a build with the library.
    {.method = Method::SiconosLemke,
     .name = "siconos:lemke",
     .iterative = false,
     .library = Library::Siconos,
     .max_rows = kDenseRows,
     .solve = solve_peer,
     .what = "Siconos numerics' lexicographic Lemke on the LCP, relay or MLCP (dense, <= 3000 "
             "rows)"},
    {.method = Method::SiconosPgs,
     .name = "siconos:pgs",
     .library = Library::Siconos,
     .max_rows = kDenseRows,
     .solve = solve_peer,
     .what = "Siconos numerics' projected Gauss-Seidel on the LCP, relay or MLCP (dense)"},
    {.method = Method::SiconosEnum,
     .name = "siconos:enum",
     .iterative = false,
     .library = Library::Siconos,
     .max_rows = kEnumerationRows,
     .solve = solve_peer,
     .what = "Siconos numerics' enumeration of the complementarity cases (<= 20 rows)"},
    {.method = Method::SiconosAvi,
     .name = "siconos:avi",
     .iterative = false,
     .library = Library::Siconos,
     .max_rows = kDenseRows,
     .solve = solve_peer,
     .what = "Siconos numerics' AVI solver of Cao & Ferris on the LCP or relay (dense)"},
    {.method = Method::SiconosFc3dNsgs,
     .name = "siconos:fc3d-nsgs",
     .library = Library::Siconos,
     .laws = kCoulombLaw,
     .max_rows = kDenseConeRows,
     .solve = solve_peer,
     .what = "Siconos numerics' non-smooth Gauss-Seidel on Coulomb's cones (fc3d; dense, <= 6000 "
             "rows)"},
    {.method = Method::SiconosFc3dNsnAc,
     .name = "siconos:fc3d-nsn-ac",
     .library = Library::Siconos,
     .laws = kCoulombLaw,
     .max_rows = kDenseConeRows,
     .solve = solve_peer,
     .what = "Siconos numerics' non-smooth Newton on Alart-Curnier's function (fc3d; Coulomb's "
             "cones)"},
    {.method = Method::SiconosFc3dProx,
     .name = "siconos:fc3d-prox",
     .library = Library::Siconos,
     .laws = kCoulombLaw,
     .max_rows = kDenseConeRows,
     .solve = solve_peer,
     .what = "Siconos numerics' proximal points around NSN-AC (fc3d; Coulomb's cones)"},
    {.method = Method::SiconosFc3dAdmm,
     .name = "siconos:fc3d-admm",
     .library = Library::Siconos,
     .laws = kCoulombLaw,
     .max_rows = kDenseConeRows,
     .solve = solve_peer,
     .what = "Siconos numerics' ADMM on Coulomb's cones (fc3d)"},
    {.method = Method::BulletDantzig,
     .name = "bullet:dantzig",
     .iterative = false,
     .library = Library::Bullet,
     .max_rows = kDenseRows,
     .solve = solve_peer,
     .what = "Bullet's Dantzig solver (ODE's) on the boxed problem (dense, cmin <= 0 <= cmax)"},
    {.method = Method::BulletLemke,
     .name = "bullet:lemke",
     .iterative = false,
     .library = Library::Bullet,
     .max_rows = kTableauRows,
     .solve = solve_peer,
     .what = "Bullet's Lemke solver on the boxed problem (dense, <= 1000 rows)"},
    {.method = Method::BulletPgs,
     .name = "bullet:pgs",
     .library = Library::Bullet,
     .max_rows = kDenseRows,
     .solve = solve_peer,
     .what = "Bullet's projected Gauss-Seidel on the dense A"},
};

/// Names besides a method's own, each listed after its method.
constexpr MethodName kAliases[] = {
    {"psor", Method::Pgs, true, true, "PGS with relaxation, psor:OMEGA, OMEGA in (0, 2) required"},
};

/// Every name: each entry's own, its aliases after it.
std::vector<MethodName> all_names() {
  std::vector<MethodName> names;
  for (const MethodEntry& e : kEntries) {
    names.push_back({e.name, e.method, e.omega, e.order, e.what});
    for (const MethodName& alias : kAliases)
      if (alias.method == e.method) names.push_back(alias);
  }
  return names;
}

/// x as the grammar reads it back (shortest round trip).
std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  for (int digits = 1; digits <= 17; ++digits) {
    char shorter[32];
    std::snprintf(shorter, sizeof shorter, "%.*g", digits, x);
    if (std::strtod(shorter, nullptr) == x) return shorter;
  }
  return text;
}

/// A whole number ≥ 1 (a count of sweeps or iterations).
bool count(const std::string& value, int& out) {
  double x = 0.0;
  if (!parse_number(value, x) || !(x >= 1.0) || x > 1e9 || x != std::floor(x)) return false;
  out = static_cast<int>(x);
  return true;
}

constexpr MethodKey kMethodKeys[] = {
    {Method::PgsNesterov,
     "restart",
     "on or off",
     [](const std::string& v, MethodSettings& s) { return on_off(v, s.pgs_nesterov.restart); },
     [](const MethodSettings& s) -> std::string { return s.pgs_nesterov.restart ? "on" : "off"; }},
    {Method::Apgd,
     "restart",
     "on or off",
     [](const std::string& v, MethodSettings& s) { return on_off(v, s.apgd.restart); },
     [](const MethodSettings& s) -> std::string { return s.apgd.restart ? "on" : "off"; }},
    {Method::Apgd,
     "grow",
     "a number > 1",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.apgd.grow) && s.apgd.grow > 1.0;
     },
     [](const MethodSettings& s) -> std::string { return number(s.apgd.grow); }},
    {Method::Apgd,
     "shrink",
     "a number in (0, 1]",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.apgd.shrink) && s.apgd.shrink > 0.0 && s.apgd.shrink <= 1.0;
     },
     [](const MethodSettings& s) -> std::string { return number(s.apgd.shrink); }},
    {Method::Nncg,
     "restart_beta",
     "a number >= 0",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.nncg.restart_beta) && s.nncg.restart_beta >= 0.0;
     },
     [](const MethodSettings& s) -> std::string { return number(s.nncg.restart_beta); }},
    {Method::PgsSm,
     "sweeps",
     "a whole number >= 1",
     [](const std::string& v, MethodSettings& s) { return count(v, s.pgs_sm.pgs_sweeps); },
     [](const MethodSettings& s) -> std::string { return std::to_string(s.pgs_sm.pgs_sweeps); }},
    {Method::PgsSm,
     "cg",
     "a whole number >= 1",
     [](const std::string& v, MethodSettings& s) { return count(v, s.pgs_sm.cg_iterations); },
     [](const MethodSettings& s) -> std::string { return std::to_string(s.pgs_sm.cg_iterations); }},
    {Method::PgsSm,
     "cg_tolerance",
     "a number in (0, 1)",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.pgs_sm.cg_tolerance) && s.pgs_sm.cg_tolerance > 0.0 &&
              s.pgs_sm.cg_tolerance < 1.0;
     },
     [](const MethodSettings& s) -> std::string { return number(s.pgs_sm.cg_tolerance); }},
    {Method::Admm,
     "rho",
     "a number > 0",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.admm.rho) && s.admm.rho > 0.0;
     },
     [](const MethodSettings& s) -> std::string { return number(s.admm.rho); }},
    {Method::Admm,
     "alpha",
     "a number in (0, 2)",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.admm.alpha) && s.admm.alpha > 0.0 && s.admm.alpha < 2.0;
     },
     [](const MethodSettings& s) -> std::string { return number(s.admm.alpha); }},
    {Method::Admm,
     "adapt",
     "on or off",
     [](const std::string& v, MethodSettings& s) { return on_off(v, s.admm.adapt_rho); },
     [](const MethodSettings& s) -> std::string { return s.admm.adapt_rho ? "on" : "off"; }},
    {Method::Admm,
     "rho_min",
     "a number > 0",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.admm.rho_min) && s.admm.rho_min > 0.0;
     },
     [](const MethodSettings& s) -> std::string { return number(s.admm.rho_min); }},
    {Method::Shock,
     "level_sweeps",
     "a whole number >= 1",
     [](const std::string& v, MethodSettings& s) { return count(v, s.shock.level_sweeps); },
     [](const MethodSettings& s) -> std::string { return std::to_string(s.shock.level_sweeps); }},
    {Method::Shock,
     "direction",
     "up or down",
     [](const std::string& v, MethodSettings& s) {
       if (v != "up" && v != "down") return false;
       s.shock.top_down = v == "down";
       return true;
     },
     [](const MethodSettings& s) -> std::string { return s.shock.top_down ? "down" : "up"; }},
    {Method::Nsgs,
     "local",
     "a whole number >= 1",
     [](const std::string& v, MethodSettings& s) { return count(v, s.nsgs.local); },
     [](const MethodSettings& s) -> std::string { return std::to_string(s.nsgs.local); }},
};

}  // namespace

bool on_off(const std::string& value, bool& out) {
  if (value != "on" && value != "off") return false;
  out = value == "on";
  return true;
}

/// A warm-start factor: on (1), off (0) or a number in [0, 1].
bool warm_factor(const std::string& value, double& out) {
  if (value == "on" || value == "off") {
    out = value == "on" ? 1.0 : 0.0;
    return true;
  }
  return parse_number(value, out) && out >= 0.0 && out <= 1.0;
}

std::span<const MethodEntry> method_entries() { return kEntries; }

std::vector<Method> all_methods() {
  std::vector<Method> methods;
  for (const MethodEntry& e : kEntries) methods.push_back(e.method);
  return methods;
}

const MethodEntry& method_entry(Method method) {
  for (const MethodEntry& e : kEntries)
    if (e.method == method) return e;
  throw std::invalid_argument("method_entry: a method without an entry");
}

std::span<const MethodName> method_table() {
  static const std::vector<MethodName> names = all_names();
  return names;
}

const MethodName* find_method_name(std::string_view name) {
  for (const MethodName& n : method_table())
    if (n.name == name) return &n;
  return nullptr;
}

std::span<const MethodKey> method_keys() { return kMethodKeys; }

const MethodKey* find_method_key(Method method, std::string_view key) {
  for (const MethodKey& m : kMethodKeys)
    if (m.method == method && m.key == key) return &m;
  return nullptr;
}

std::vector<std::pair<std::string, std::string>> method_parameters(Method method,
                                                                   const MethodSettings& settings) {
  std::vector<std::pair<std::string, std::string>> parameters;
  for (const MethodKey& m : kMethodKeys)
    if (m.method == method) parameters.emplace_back(std::string(m.key), m.get(settings));
  return parameters;
}

}  // namespace cbps
