// Numerical checks of the paper's derivations, one per equation. `cbps verify` prints them and
// the Catch2 suite asserts each (tests/studies/test_verify.cpp).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace cbps {

struct Check {
  std::string equation;  ///< the paper's equation number, e.g. "5.2.1"
  std::string what;      ///< what is checked, one line
  double error = 0.0;    ///< the measured error (relative unless `what` says otherwise)
  double tolerance = 0.0;
  bool pass() const { return error <= tolerance; }
};

/// 5.2.1: the distance row's j_c against the central finite difference of c = |p_b − p_a| − l
/// along a random motion (relative error).
Check check_distance_jacobian();
/// 12.2.2: Jᵀλ equals Σ_i J_iᵀ λ_i, row by row (relative, round-off).
Check check_transpose_sum();
/// 12.2: (Jᵀλ)·v = λ·(J v) (relative, round-off).
Check check_power_identity();
/// 12.3: after an unbounded solve to convergence J v2 = upsilon (absolute, m/s).
Check check_velocity_constraint();
/// 12.4.1 vs 12.5.1: the finite-difference derivative of q(t) = axis_angle(omega t) ⊗ q0 at
/// t = 0 equals ½ [0, omega] ⊗ q0 (relative).
Check check_quaternion_derivative();
/// 6.2.9: A = J Minv Jᵀ is symmetric (exactly).
Check check_A_symmetric();
/// 6.2.9: A is positive semidefinite: smallest eigenvalue ≥ −tol · largest, on a system with a
/// redundant row (so A is singular).
Check check_A_semidefinite();
/// 5.2.3: the Baumgarte bias removes beta of a violated distance in one step: the measured
/// ratio c_after / c_before against 1 − beta (absolute difference).
Check check_bias_reduces_violation();
/// 9: scaling metres, kilograms and seconds scales lambda (N), b (m/s²) and positions (m)
/// exactly as their units say (largest relative deviation over 50 steps).
Check check_dimensional_analysis();

/// All of the above, in the paper's order.
std::vector<Check> run_derivation_checks();

/// `cbps verify`'s table: a header, then one line per check (equation, error, tolerance, pass or
/// FAIL, what), as text; or as JSON, one object per check (docs/outputs.md).
std::string checks_text(const std::vector<Check>& checks);
nlohmann::json checks_json(const std::vector<Check>& checks);
/// Every check passes.
bool all_pass(const std::vector<Check>& checks);

}  // namespace cbps
