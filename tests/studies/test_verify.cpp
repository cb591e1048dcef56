// The derivation checks of cbps verify, one test per paper equation.
#include <catch2/catch.hpp>

#include "cbps/studies/verify.hpp"

namespace {
void require_pass(const cbps::Check& c) {
  INFO(c.equation << ": " << c.what << ": error " << c.error << ", tolerance " << c.tolerance);
  REQUIRE(c.pass());
}
}  // namespace

TEST_CASE("distance row j_c is the time derivative of |p_b - p_a| - l (5.2.1)", "[eq5.2.1]") {
  require_pass(cbps::check_distance_jacobian());
}

TEST_CASE("J^T lambda is the sum of the rows J_i scaled by lambda_i (12.2.2)", "[eq12.2]") {
  require_pass(cbps::check_transpose_sum());
}

TEST_CASE("(J^T lambda) . v equals lambda . (J v) (12.2)", "[eq12.2]") {
  require_pass(cbps::check_power_identity());
}

TEST_CASE("J v2 = upsilon after an unbounded solve to convergence (12.3)", "[eq12.3]") {
  require_pass(cbps::check_velocity_constraint());
}

TEST_CASE("axis-angle update 12.4.1 has the derivative of 12.5.1", "[eq12.4.1][eq12.5.1]") {
  require_pass(cbps::check_quaternion_derivative());
}

TEST_CASE("A = J Minv J^T is symmetric (6.2.9)", "[eq6.2.9]") {
  require_pass(cbps::check_A_symmetric());
}

TEST_CASE("A = J Minv J^T is positive semidefinite, also when singular (6.2.9)", "[eq6.2.9]") {
  require_pass(cbps::check_A_semidefinite());
}

TEST_CASE("the Baumgarte bias removes beta of a violated distance per step (5.2.3)", "[eq5.2.3]") {
  require_pass(cbps::check_bias_reduces_violation());
}

TEST_CASE("rescaling m, kg, s rescales lambda, b and positions by their units (9)", "[eq9]") {
  require_pass(cbps::check_dimensional_analysis());
}

TEST_CASE("every derivation check is run by cbps verify", "[verify]") {
  const auto checks = cbps::run_derivation_checks();
  REQUIRE(checks.size() == 9);
  for (const auto& c : checks) {
    CAPTURE(c.equation, c.what, c.error);
    CHECK(c.pass());
  }
}
