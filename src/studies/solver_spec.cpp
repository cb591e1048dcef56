// Solver names with parameters, as the command line writes them (solver_spec.hpp).
#include "cbps/studies/solver_spec.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/solvers/methods.hpp"

namespace cbps {

namespace {

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
  for (const MethodName& n : method_table()) {
    if (!names.empty()) names += ", ";
    names += std::string(n.name) + (n.name == "psor" ? ":OMEGA" : n.omega ? "[:OMEGA]" : "");
  }
  return names;
}

namespace {

/// The method name that starts a spec: its first part, or its first two for a peer's
/// (siconos:lemke, bullet:pgs); how many parts it took.
std::pair<std::string, std::size_t> spec_name(const std::vector<std::string>& parts) {
  if (parts.size() >= 2 && find_method_name(parts[0] + ":" + parts[1]) != nullptr)
    return {parts[0] + ":" + parts[1], 2};
  return {parts.front(), 1};
}

}  // namespace

bool is_solver_name(const std::string& text) {
  return find_method_name(spec_name(split(text, ':')).first) != nullptr;
}

SolverSpec parse_solver_spec(const std::string& text, const std::string& what) {
  const auto fail = [&](const std::string& why) {
    throw InputError(what + " '" + text + "': " + why);
  };
  const std::vector<std::string> parts = split(text, ':');
  SolverSpec spec;
  spec.text = text;
  const auto [name, first] = spec_name(parts);
  const MethodName* entry = find_method_name(name);
  if (entry == nullptr) fail("unknown solver (valid: " + solver_names() + ")");
  spec.method = entry->method;
  bool have_omega = false;
  for (std::size_t k = first; k < parts.size(); ++k) {
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
    for (std::size_t j = first; j < k; ++j)
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
    const bool sorts = method_entry(spec.method).contacts_first;
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
    for (const MethodKey& m : method_entry(spec.method).keys) {
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
  settings.max_iterations = max_iterations;
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

std::string solver_spec_help() {
  std::string help =
      "Solvers: NAME[:OMEGA][:key=value]..., every one with warm=on|off|F (start each row from "
      "F times the previous step's lambda: on 1, off 0, F in [0, 1]) and warm_friction=on|off|G "
      "(G for the friction rows, default F):\n";
  for (const MethodName& n : method_table()) {
    std::string line = "  " + std::string(n.name);
    line.resize(std::max<std::size_t>(16, line.size() + 1), ' ');  // a space after a long name
    help += line + std::string(n.what) + (n.order ? "; order=natural|reverse|random" : "") +
            (method_entry(n.method).contacts_first ? "; contacts_first=on|off" : "") + "\n";
  }
  return help;
}

}  // namespace cbps
