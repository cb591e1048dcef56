// Numbers in cbps's JSON outputs. JSON has no inf or NaN: cbps writes them as the strings
// "inf", "-inf" and "nan" (docs/outputs.md), in every file and every command's --json.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>

namespace cbps {

/// x as a JSON number, or "inf", "-inf", "nan".
inline nlohmann::json number_json(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return x;
}

}  // namespace cbps
