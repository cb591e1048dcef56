// The one table of methods (methods.hpp): the list of every method's entry (each written beside
// its code), the names the grammar accepts, each method's own keys.
#include "cbps/solvers/methods.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "cbps/base/numbers.hpp"

namespace cbps {

// Every method's entry (MethodEntry), written beside its code: one `k<Method>Entry` in the file
// that solves with it.
extern const MethodEntry kPgsEntry;
extern const MethodEntry kSgsEntry;
extern const MethodEntry kJacobiEntry;
extern const MethodEntry kBlockPgsEntry;
extern const MethodEntry kMatrixFreeEntry;
extern const MethodEntry kPgsNesterovEntry;
extern const MethodEntry kApgdEntry;
extern const MethodEntry kNncgEntry;
extern const MethodEntry kPgsSmEntry;
extern const MethodEntry kAdmmEntry;
extern const MethodEntry kRbgsEntry;
extern const MethodEntry kShockEntry;
extern const MethodEntry kDirectEntry;
extern const MethodEntry kActiveSetEntry;
extern const MethodEntry kLemkeEntry;
extern const MethodEntry kNsgsEntry;
extern const MethodEntry kSiconosLemkeEntry;
extern const MethodEntry kSiconosPgsEntry;
extern const MethodEntry kSiconosEnumEntry;
extern const MethodEntry kSiconosAviEntry;
extern const MethodEntry kSiconosFc3dNsgsEntry;
extern const MethodEntry kSiconosFc3dNsnAcEntry;
extern const MethodEntry kSiconosFc3dProxEntry;
extern const MethodEntry kSiconosFc3dAdmmEntry;
extern const MethodEntry kBulletDantzigEntry;
extern const MethodEntry kBulletLemkeEntry;
extern const MethodEntry kBulletPgsEntry;

/// The list of them, in the order --help lists them.
constexpr const MethodEntry* kEntries[] = {
    &kPgsEntry,
    &kSgsEntry,
    &kJacobiEntry,
    &kBlockPgsEntry,
    &kMatrixFreeEntry,
    &kPgsNesterovEntry,
    &kApgdEntry,
    &kNncgEntry,
    &kPgsSmEntry,
    &kAdmmEntry,
    &kRbgsEntry,
    &kShockEntry,
    &kDirectEntry,
    &kActiveSetEntry,
    &kLemkeEntry,
    &kNsgsEntry,
    &kSiconosLemkeEntry,
    &kSiconosPgsEntry,
    &kSiconosEnumEntry,
    &kSiconosAviEntry,
    &kSiconosFc3dNsgsEntry,
    &kSiconosFc3dNsnAcEntry,
    &kSiconosFc3dProxEntry,
    &kSiconosFc3dAdmmEntry,
    &kBulletDantzigEntry,
    &kBulletLemkeEntry,
    &kBulletPgsEntry,
};

namespace {

/// Names besides a method's own, each listed after its method.
constexpr MethodName kAliases[] = {
    {"psor", Method::Pgs, true, true, "PGS with relaxation, psor:OMEGA, OMEGA in (0, 2) required"},
};

/// Every name: each entry's own, its aliases after it.
std::vector<MethodName> all_names() {
  std::vector<MethodName> names;
  for (const MethodEntry* e : kEntries) {
    names.push_back({e->name, e->method, e->omega, e->order, e->what});
    for (const MethodName& alias : kAliases)
      if (alias.method == e->method) names.push_back(alias);
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

std::span<const MethodEntry* const> method_entries() { return kEntries; }

std::vector<Method> all_methods() {
  std::vector<Method> methods;
  for (const MethodEntry* e : kEntries) methods.push_back(e->method);
  return methods;
}

const MethodEntry& method_entry(Method method) {
  for (const MethodEntry* e : kEntries)
    if (e->method == method) return *e;
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
