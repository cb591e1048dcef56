// Errors the command line reports with the contract's exit codes.
#pragma once

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace cbps {

/// A number for a message: 6 significant digits (or `digits`), "inf", "-inf" or "nan" (never
/// the 300 digits std::to_string gives DBL_MAX, never "-nan").
inline std::string number_text(double x, int digits = 6) {
  if (std::isnan(x)) return "nan";  // never printf's "-nan"
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", digits, x);
  return text;
}

/// A count with its noun for messages: "1 sweep", "2 sweeps", "1 movable body", "0 rows".
/// `plural` defaults to the singular with an "s".
inline std::string count_text(long n, const std::string& singular, std::string plural = {}) {
  if (plural.empty()) plural = singular + "s";
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

/// Bad input or usage (exit code 2). what() reads "<where>: <why>", where names the file and
/// the JSON path or line, or the option.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A computation that failed: diverged, non-finite values, no solution (exit code 1).
class ComputationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A step whose values turned non-finite or exploded (speed beyond the scene's divergence
/// limits). what() names the step, the body and the row; the fields say the same for programs.
class DivergenceError : public ComputationError {
 public:
  DivergenceError(const std::string& what, long step, int body, int row)
      : ComputationError(what), step_(step), body_(body), row_(row) {}
  long step() const { return step_; }  ///< 0-based index of the step that failed
  int body() const { return body_; }   ///< index into the scene's bodies, −1 if none
  int row() const { return row_; }     ///< row of that step's system, −1 if none

 private:
  long step_;
  int body_;
  int row_;
};

}  // namespace cbps
