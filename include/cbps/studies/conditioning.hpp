// The condition number of A = J M⁻¹ Jᵀ (6.2.9): how much the solvers of 7 and 6.2 have to fight.
#pragma once

#include <string>

#include "cbps/base/types.hpp"

namespace cbps {

/// kappa(A) = lambda_max / lambda_min of the symmetric positive semidefinite A.
struct ConditionEstimate {
  double condition = 0.0;      ///< lambda_max / lambda_min; +inf when A is singular
  double lambda_max = 0.0;     ///< largest eigenvalue, kg⁻¹
  double lambda_min = 0.0;     ///< smallest eigenvalue (0 when singular), kg⁻¹
  double range_condition = 0;  ///< lambda_max / smallest nonzero eigenvalue (exact method only)
  int nullity = -1;            ///< eigenvalues ≤ n u lambda_max (exact method), else −1
  bool exact = false;          ///< dense eigenvalues (true) or an estimate (false)
  std::string method;          ///< how it was found, one phrase
};

/// Systems up to this many rows get the exact condition number from dense eigenvalues.
inline constexpr int kExactConditionRows = 1500;

/// The condition number of A. Up to kExactConditionRows rows: all eigenvalues (Eigen's
/// SelfAdjointEigenSolver), an eigenvalue ≤ n u lambda_max (u the unit round-off) counted as
/// zero. Larger: lambda_max by Lanczos (60 steps, a lower bound accurate to a few digits) and
/// lambda_min by inverse iteration on a CHOLMOD factor of A (20 steps); A is taken as singular
/// (condition +inf) when the factorization fails or its reciprocal condition estimate is below
/// kDefiniteRcond, as the direct path judges definiteness.
ConditionEstimate estimate_condition(const SpMat& A);

}  // namespace cbps
