// The one table of methods: every name the command line, scene files and the Python module
// accept (`--solver NAME[:OMEGA][:key=value]...`, a scene's "method" and "parameters"), the
// method each selects, and each method's own parameters with their checks (MethodSettings,
// method_settings.hpp). solver.hpp's to_string and method_from_string read it too.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// A name the grammar accepts: the method it selects, what it takes, and one line for --help.
/// A method's first name is its own (to_string); a later one is an alias (psor).
struct MethodName {
  std::string_view name;
  Method method;
  bool omega;  ///< takes :OMEGA (relaxation_in_range of the method)
  bool order;  ///< takes order=
  std::string_view what;
};

/// Every name, in the order --help lists them.
std::span<const MethodName> method_table();
/// The entry of a name, or null.
const MethodName* find_method_name(std::string_view name);

/// A method's own key=value: the method, the key, what it accepts (for messages) and its setter
/// (false for a value out of range).
struct MethodKey {
  Method method;
  std::string_view key;
  std::string_view accepts;
  bool (*set)(const std::string& value, MethodSettings& settings);
  std::string (*get)(const MethodSettings& settings);  ///< as the grammar writes it
};

/// Every method's own keys.
std::span<const MethodKey> method_keys();
/// The key of a method, or null.
const MethodKey* find_method_key(Method method, std::string_view key);

/// A method's own parameters as key and value text, the way the grammar writes them
/// (`apgd`: grow 2, shrink 0.9, restart on); none for the methods without.
std::vector<std::pair<std::string, std::string>> method_parameters(Method method,
                                                                   const MethodSettings& settings);

/// "on" or "off" as a bool; false for anything else.
bool on_off(const std::string& value, bool& out);
/// A warm-start factor: on (1), off (0) or a number in [0, 1]; false for anything else.
bool warm_factor(const std::string& value, double& out);

}  // namespace cbps
