// Numbers in cbps's JSON outputs. JSON has no inf or NaN: cbps writes them as the strings
// "inf", "-inf" and "nan" (docs/outputs.md), in every file and every command's --json.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "cbps/base/types.hpp"

namespace cbps {

/// x as a JSON number, or "inf", "-inf", "nan".
inline nlohmann::json number_json(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return x;
}

/// The number number_json wrote: a JSON number, or "inf", "-inf", "nan" as those; NaN for null
/// (no value) and anything else.
inline double number_of_json(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const std::string& s = j.get_ref<const std::string&>();
    if (s == "inf") return INFINITY;
    if (s == "-inf") return -INFINITY;
  }
  return NAN;
}

/// A vector as a JSON array of number_json.
inline nlohmann::json vector_json(const VecX& v) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index k = 0; k < v.size(); ++k) a.push_back(number_json(v(k)));
  return a;
}

/// A dense matrix as nested JSON arrays, one per row, of number_json.
inline nlohmann::json dense_json(const MatX& M) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index r = 0; r < M.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < M.cols(); ++c) row.push_back(number_json(M(r, c)));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace cbps
