// Reading a built-in scene's NAME=VALUE parameters (internal to src/scene/builtin).
#pragma once

#include <map>
#include <string>

#include "cbps/scene/builtin.hpp"

namespace cbps {

/// The values of one built-in scene's parameters: the user's, else the defaults. Every getter
/// throws InputError naming the scene and the parameter when a value is not valid.
class ParameterValues {
 public:
  ParameterValues(const BuiltinScene& scene, const std::map<std::string, std::string>& values);

  /// True if the user gave this parameter.
  bool given(const std::string& name) const;
  /// The value as text, e.g. for a word such as attach=top.
  std::string text(const std::string& name) const;
  /// A finite number; fractions "p/q" are accepted. Throws unless lo ≤ value ≤ hi.
  double number(const std::string& name, double lo, double hi) const;
  /// A number strictly greater than zero.
  double positive(const std::string& name) const;
  /// An integer in [lo, hi].
  long integer(const std::string& name, long lo, long hi) const;
  /// One of the words in `choices` (separated by '|').
  std::string word(const std::string& name, const std::string& choices) const;

  /// All parameters with the values in force, for the summary.
  std::vector<std::pair<std::string, std::string>> in_force() const;

 private:
  [[noreturn]] void fail(const std::string& name, const std::string& why) const;
  const BuiltinScene& scene_;
  std::map<std::string, std::string> values_;
  std::map<std::string, std::string> given_;
};

}  // namespace cbps
