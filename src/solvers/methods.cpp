// The one table of methods (methods.hpp): the list of every method's entry (each written beside
// its code, its own keys with it) and the names the grammar accepts.
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
    {"psor", kPaperMethod, true, true, "PGS with relaxation, psor:OMEGA, OMEGA in (0, 2) required"},
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

}  // namespace

std::string key_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  for (int digits = 1; digits <= 17; ++digits) {
    char shorter[32];
    std::snprintf(shorter, sizeof shorter, "%.*g", digits, x);
    if (std::strtod(shorter, nullptr) == x) return shorter;
  }
  return text;
}

bool key_count(const std::string& value, int& out) {
  double x = 0.0;
  if (!parse_number(value, x) || !(x >= 1.0) || x > 1e9 || x != std::floor(x)) return false;
  out = static_cast<int>(x);
  return true;
}

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

const MethodKey* find_method_key(Method method, std::string_view key) {
  for (const MethodKey& m : method_entry(method).keys)
    if (m.key == key) return &m;
  return nullptr;
}

std::vector<std::pair<std::string, std::string>> method_parameters(Method method,
                                                                   const MethodSettings& settings) {
  std::vector<std::pair<std::string, std::string>> parameters;
  for (const MethodKey& m : method_entry(method).keys)
    parameters.emplace_back(std::string(m.key), m.get(settings));
  return parameters;
}

}  // namespace cbps
