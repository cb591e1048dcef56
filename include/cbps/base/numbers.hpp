// Numbers read from text, in the two forms cbps meets them. Every reader calls these, so a
// number means the same thing in a scene parameter, an option and a stored problem.
#pragma once

#include <string>

namespace cbps {

/// A number a person wrote (a scene parameter, --param, a solver spec's value): a finite
/// decimal such as "0.25" or "1e-3", or a fraction "1/240". False if the text is not one.
bool parse_number(const std::string& text, double& value);

/// A whole token of a data file as strtod reads it (decimal or hexadecimal; "inf", "-inf",
/// "Infinity" and "nan" included: each reader decides what it accepts). False if the token is
/// empty or holds anything after the number.
bool parse_token(const std::string& token, double& value);

}  // namespace cbps
