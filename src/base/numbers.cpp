#include "cbps/base/numbers.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace cbps {

bool parse_number(const std::string& text, double& value) {
  const auto slash = text.find('/');
  if (slash != std::string::npos) {
    double p = 0.0;
    double q = 0.0;
    if (!parse_number(text.substr(0, slash), p) || !parse_number(text.substr(slash + 1), q) ||
        q == 0.0) {
      return false;
    }
    value = p / q;
    return std::isfinite(value);
  }
  std::istringstream in(text);
  in >> value;
  return !text.empty() && !in.fail() && in.eof() && std::isfinite(value);
}

bool parse_token(const std::string& token, double& value) {
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  return end != token.c_str() && *end == '\0';
}

}  // namespace cbps
