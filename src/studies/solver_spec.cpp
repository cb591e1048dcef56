// Solver names with parameters, as the command line writes them (solver_spec.hpp).
#include "cbps/studies/solver_spec.hpp"

#include <string>
#include <vector>

#include "cbps/error.hpp"
#include "cbps/scene/builtin.hpp"

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

SolverSpec parse_solver_spec(const std::string& text, const std::string& what) {
  const auto fail = [&](const std::string& why) {
    throw InputError(what + " '" + text + "': " + why);
  };
  const std::vector<std::string> parts = split(text, ':');
  SolverSpec spec;
  spec.text = text;
  const std::string& name = parts.front();
  bool omega_allowed = true;
  bool omega_required = false;
  if (name == "pgs" || name == "matrix-free" || name == "block-pgs" || name == "direct" ||
      name == "active-set") {
    method_from_string(name, spec.method);
    omega_allowed = false;
  } else if (name == "psor") {
    spec.method = Method::Pgs;
    omega_required = true;
  } else if (name == "sgs") {
    spec.method = Method::Sgs;
  } else if (name == "jacobi") {
    spec.method = Method::Jacobi;
  } else {
    fail(
        "unknown solver (valid: pgs, psor:OMEGA, sgs[:OMEGA], jacobi[:OMEGA], block-pgs, "
        "matrix-free, direct, active-set)");
  }
  bool have_omega = false;
  for (std::size_t k = 1; k < parts.size(); ++k) {
    const std::string& p = parts[k];
    const auto eq = p.find('=');
    if (eq == std::string::npos) {
      double omega = 0.0;
      if (!omega_allowed) fail("'" + name + "' takes no relaxation factor");
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
      if (spec.method != Method::Pgs && spec.method != Method::MatrixFree)
        fail("order= applies to pgs, psor and matrix-free");
      if (value == "natural") {
        spec.order = RowOrder::Natural;
      } else if (value == "reverse") {
        spec.order = RowOrder::Reverse;
      } else if (value == "random") {
        spec.order = RowOrder::Random;
      } else {
        fail("order '" + value + "' (valid: natural, reverse, random)");
      }
    } else if (key == "warm") {
      if (value != "on" && value != "off") fail("warm '" + value + "' (valid: on, off)");
      spec.warm_start = value == "on";
    } else {
      fail("unknown option '" + key + "' (valid: order, warm)");
    }
  }
  if (omega_required && !have_omega) fail("psor needs its factor, e.g. psor:1.3");
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
  settings.warm_start = spec.warm_start;
}

}  // namespace cbps
