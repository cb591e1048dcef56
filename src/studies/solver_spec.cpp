// Solver names with parameters, as the command line writes them (solver_spec.hpp).
#include "cbps/studies/solver_spec.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"

namespace cbps {

namespace {

/// A name the grammar accepts: the method it selects, what it takes, and one line for --help.
struct SpecName {
  std::string_view name;
  Method method;
  bool omega;  ///< takes :OMEGA (relaxation_in_range of the method)
  bool order;  ///< takes order=
  std::string_view what;
};

constexpr SpecName kSpecNames[] = {
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
};

/// A method's own key=value: the method, the key, what it accepts (for messages) and its setter
/// (false for a value out of range).
struct MethodKey {
  Method method;
  std::string_view key;
  std::string_view accepts;
  bool (*set)(const std::string& value, MethodSettings& settings);
  std::string (*get)(const MethodSettings& settings);  ///< as the grammar writes it
};

bool on_off(const std::string& value, bool& out) {
  if (value != "on" && value != "off") return false;
  out = value == "on";
  return true;
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

/// A warm-start factor: on (1), off (0) or a number in [0, 1].
bool warm_factor(const std::string& value, double& out) {
  if (value == "on" || value == "off") {
    out = value == "on" ? 1.0 : 0.0;
    return true;
  }
  return parse_number(value, out) && out >= 0.0 && out <= 1.0;
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
};

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  for (const char c : text) {
    if (c == separator) {
      parts.push_back(part);
      part.clear();
    } else {
      part.push_back(c);
    }
  }
  parts.push_back(part);
  return parts;
}

}  // namespace

std::string solver_names() {
  std::string names;
  for (const SpecName& n : kSpecNames) {
    if (!names.empty()) names += ", ";
    names += std::string(n.name) + (n.name == "psor" ? ":OMEGA" : n.omega ? "[:OMEGA]" : "");
  }
  return names;
}

bool is_solver_name(const std::string& text) {
  const std::string name = text.substr(0, text.find(':'));
  for (const SpecName& n : kSpecNames)
    if (n.name == name) return true;
  return false;
}

SolverSpec parse_solver_spec(const std::string& text, const std::string& what) {
  const auto fail = [&](const std::string& why) {
    throw InputError(what + " '" + text + "': " + why);
  };
  const std::vector<std::string> parts = split(text, ':');
  SolverSpec spec;
  spec.text = text;
  const std::string& name = parts.front();
  const SpecName* entry = nullptr;
  for (const SpecName& n : kSpecNames)
    if (n.name == name) entry = &n;
  if (entry == nullptr) fail("unknown solver (valid: " + solver_names() + ")");
  spec.method = entry->method;
  bool have_omega = false;
  for (std::size_t k = 1; k < parts.size(); ++k) {
    const std::string& p = parts[k];
    const auto eq = p.find('=');
    if (eq == std::string::npos) {
      double omega = 0.0;
      if (!entry->omega) fail("'" + name + "' takes no relaxation factor");
      if (have_omega) fail("more than one relaxation factor");
      if (!parse_number(p, omega) || !relaxation_in_range(spec.method, omega)) {
        fail("relaxation factor '" + p + "' must be a number in " + relaxation_range(spec.method));
      }
      spec.relaxation = omega;
      have_omega = true;
      continue;
    }
    const std::string key = p.substr(0, eq), value = p.substr(eq + 1);
    for (std::size_t j = 1; j < k; ++j)
      if (parts[j].substr(0, parts[j].find('=')) == key) fail("'" + key + "=' given twice");
    if (key == "order") {
      if (!entry->order) fail("order= applies to pgs, psor, pgs-nesterov and matrix-free");
      if (value == "natural") {
        spec.order = RowOrder::Natural;
      } else if (value == "reverse") {
        spec.order = RowOrder::Reverse;
      } else if (value == "random") {
        spec.order = RowOrder::Random;
      } else {
        fail("order '" + value + "' (valid: natural, reverse, random)");
      }
      continue;
    }
    if (key == "warm" || key == "warm_friction") {
      double factor = 0.0;
      if (!warm_factor(value, factor))
        fail(key + " '" + value + "' (valid: on, off or a number in [0, 1])");
      if (key == "warm") {
        spec.warm = factor;
      } else {
        spec.warm_friction = factor;
      }
      continue;
    }
    const bool sorts = spec.method == Method::Pgs || spec.method == Method::MatrixFree;
    if (key == "contacts_first") {
      if (!sorts) fail("contacts_first= applies to pgs, psor and matrix-free");
      if (!on_off(value, spec.contacts_first))
        fail("contacts_first '" + value + "' (valid: on, off)");
      continue;
    }
    std::string valid = entry->order ? "order, " : "";
    if (sorts) valid += "contacts_first, ";
    valid += "warm, warm_friction";
    bool known = false;
    for (const MethodKey& m : kMethodKeys) {
      if (m.method != spec.method) continue;
      valid += ", " + std::string(m.key);
      if (m.key != key) continue;
      known = true;
      if (!m.set(value, spec.methods))
        fail(key + " '" + value + "' must be " + std::string(m.accepts));
    }
    if (!known) fail("unknown option '" + key + "' for " + name + " (valid: " + valid + ")");
  }
  if (name == "psor" && !have_omega) fail("psor needs its factor, e.g. psor:1.3");
  return spec;
}

std::vector<SolverSpec> parse_solver_list(const std::string& text, const std::string& what) {
  std::vector<SolverSpec> specs;
  for (const std::string& item : split(text, ',')) {
    if (item.empty()) throw InputError(what + " '" + text + "': an empty entry");
    specs.push_back(parse_solver_spec(item, what));
  }
  return specs;
}

void apply_solver_spec(const SolverSpec& spec, SolverSettings& settings) {
  settings.method = spec.method;
  settings.relaxation = spec.relaxation;
  settings.order = spec.order;
  settings.contacts_first = spec.contacts_first;
  settings.warm = spec.warm;
  settings.warm_friction = spec.warm_friction;
  settings.methods = spec.methods;
}

SolverOptions solver_options(const SolverSpec& spec, int max_iterations, double tolerance) {
  SolverSettings settings;
  apply_solver_spec(spec, settings);
  settings.iterations = max_iterations;
  settings.tolerance = tolerance;
  return settings.options();
}

SolverOptions study_options(const SolverSpec& spec, int max_iterations, double cfm) {
  SolverOptions options = solver_options(spec, max_iterations, 0.0);
  options.delta_tolerance = 0.0;
  options.split_islands = false;
  options.describe = false;
  options.cfm = cfm;
  return options;
}

std::vector<std::pair<std::string, std::string>> method_parameters(Method method,
                                                                   const MethodSettings& settings) {
  std::vector<std::pair<std::string, std::string>> parameters;
  for (const MethodKey& m : kMethodKeys)
    if (m.method == method) parameters.emplace_back(std::string(m.key), m.get(settings));
  return parameters;
}

std::string solver_spec_help() {
  std::string help =
      "Solvers: NAME[:OMEGA][:key=value]..., every one with warm=on|off|F (start each row from "
      "F times the previous step's lambda: on 1, off 0, F in [0, 1]) and warm_friction=on|off|G "
      "(G for the friction rows, default F):\n";
  for (const SpecName& n : kSpecNames) {
    std::string line = "  " + std::string(n.name);
    line.resize(16, ' ');
    help += line + std::string(n.what) + (n.order ? "; order=natural|reverse|random" : "") +
            (n.method == Method::Pgs || n.method == Method::MatrixFree ? "; contacts_first=on|off"
                                                                       : "") +
            "\n";
  }
  return help;
}

}  // namespace cbps
