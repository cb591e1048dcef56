// Errors the command line reports with the contract's exit codes.
#pragma once

#include <stdexcept>
#include <string>

namespace cbps {

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

}  // namespace cbps
