#include "cbps/solvers/methods.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "cbps/base/numbers.hpp"

namespace cbps {

namespace {

constexpr MethodName kSpecNames[] = {
    {"pgs", Method::Pgs, false, true, "projected Gauss-Seidel, the paper's 7.1.1"},
    {"psor", Method::Pgs, true, true, "PGS with relaxation, psor:OMEGA, OMEGA in (0, 2) required"},
    {"sgs", Method::Sgs, true, false, "symmetric Gauss-Seidel, a forward and a backward sweep"},
    {"jacobi", Method::Jacobi, true, false, "projected Jacobi; jacobi:OMEGA damps it, (0, 1]"},
    {"block-pgs", Method::BlockPgs, false, false, "PGS with each contact manifold solved whole"},
    {"matrix-free", Method::MatrixFree, false, true, "7.1.1 on J and Minv, without A"},
    {"pgs-nesterov",
     Method::PgsNesterov,
     true,
     true,
     "PGS with Nesterov momentum and adaptive restart (O'Donoghue & Candes 2015); restart=on|off"},
    {"apgd",
     Method::Apgd,
     false,
     false,
     "accelerated projected gradient descent (Mazhar et al. 2015); grow=, shrink=, "
     "restart=on|off"},
    {"nncg",
     Method::Nncg,
     false,
     false,
     "nonsmooth nonlinear conjugate gradient on PGS sweeps (Silcowitz, Niebe & Erleben 2010); "
     "restart_beta="},
    {"pgs-sm",
     Method::PgsSm,
     false,
     false,
     "PGS with subspace minimization by CG (Silcowitz, Niebe & Erleben 2010); sweeps=, cg=, "
     "cg_tolerance="},
    {"admm",
     Method::Admm,
     false,
     false,
     "ADMM with one factor of A + rho E (Boyd et al. 2011); rho=, alpha=, adapt=on|off, "
     "rho_min="},
    {"rbgs",
     Method::Rbgs,
     true,
     false,
     "red-black (graph-coloured) PGS, the parallel engines' order"},
    {"shock",
     Method::Shock,
     true,
     false,
     "PGS level by level from the ground up (Guendelman, Bridson & Fedkiw 2003); level_sweeps=, "
     "direction=up|down"},
    {"direct", Method::Direct, false, false, "the exact path: interior point, then active set"},
    {"active-set", Method::ActiveSet, false, false, "the previous exact path, for comparison"},
    {"lemke",
     Method::Lemke,
     false,
     false,
     "Lemke's complementary pivoting on the dense A: any square A, at most 3000 rows"},
    {"nsgs",
     Method::Nsgs,
     false,
     false,
     "non-smooth Gauss-Seidel: 7.1.1 with each contact's rows projected onto its friction cone "
     "(Jean & Moreau 1992); local=; PGS where no row is in a cone"},
    // The peers (solvers/peers/peers.hpp, docs/peers.md), in a build with the library.
    {"siconos:lemke",
     Method::SiconosLemke,
     false,
     false,
     "Siconos numerics' lexicographic Lemke on the LCP, relay or MLCP (dense, <= 3000 rows)"},
    {"siconos:pgs",
     Method::SiconosPgs,
     false,
     false,
     "Siconos numerics' projected Gauss-Seidel on the LCP, relay or MLCP (dense)"},
    {"siconos:enum",
     Method::SiconosEnum,
     false,
     false,
     "Siconos numerics' enumeration of the complementarity cases (<= 20 rows)"},
    {"siconos:avi",
     Method::SiconosAvi,
     false,
     false,
     "Siconos numerics' AVI solver of Cao & Ferris on the LCP or relay (dense)"},
    {"siconos:fc3d-nsgs",
     Method::SiconosFc3dNsgs,
     false,
     false,
     "Siconos numerics' non-smooth Gauss-Seidel on Coulomb's cones (fc3d; dense, <= 6000 rows)"},
    {"siconos:fc3d-nsn-ac",
     Method::SiconosFc3dNsnAc,
     false,
     false,
     "Siconos numerics' non-smooth Newton on Alart-Curnier's function (fc3d; Coulomb's cones)"},
    {"siconos:fc3d-prox",
     Method::SiconosFc3dProx,
     false,
     false,
     "Siconos numerics' proximal points around NSN-AC (fc3d; Coulomb's cones)"},
    {"siconos:fc3d-admm",
     Method::SiconosFc3dAdmm,
     false,
     false,
     "Siconos numerics' ADMM on Coulomb's cones (fc3d)"},
    {"bullet:dantzig",
     Method::BulletDantzig,
     false,
     false,
     "Bullet's Dantzig solver (ODE's) on the boxed problem (dense, cmin <= 0 <= cmax)"},
    {"bullet:lemke",
     Method::BulletLemke,
     false,
     false,
     "Bullet's Lemke solver on the boxed problem (dense, <= 1000 rows)"},
    {"bullet:pgs",
     Method::BulletPgs,
     false,
     false,
     "Bullet's projected Gauss-Seidel on the dense A"},
};

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

std::span<const MethodName> method_table() { return kSpecNames; }

const MethodName* find_method_name(std::string_view name) {
  for (const MethodName& n : kSpecNames)
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
