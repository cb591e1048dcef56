// Solvers of the boxed problem A lambda = b, cmin ≤ lambda ≤ cmax (paper 6.2, 7).
// They see only (A, b, cmin, cmax), never bodies, so stored problems feed them as well.
#pragma once

#include <string>

#include "cbps/types.hpp"

namespace cbps {

struct SolverOptions {
  int max_iterations = 100;       ///< sweeps
  double residual_tolerance = 0;  ///< stop when natural_map_residual ≤ this (N); 0 = never
  double delta_tolerance = 0;     ///< stop when max |Δlambda| in a sweep ≤ this (N); 0 = never
  double relaxation = 1.0;        ///< Jacobi damping / SOR factor omega (1 = the paper's 7.1.1)
};

enum class Termination { ResidualTolerance, DeltaTolerance, MaxIterations, Direct, NonFinite };

struct SolverSummary {
  int iterations = 0;     ///< sweeps done (1 for a direct solve)
  double residual = 0.0;  ///< natural-map residual at the end, N
  double delta = 0.0;     ///< max |Δlambda| of the last sweep, N
  Termination termination = Termination::MaxIterations;
  std::string message;  ///< one line with the numbers
  bool ok() const { return termination != Termination::NonFinite; }
};

/// Clamp of 7.1.1: min(max(x, lo), hi).
double clamp(double x, double lo, double hi);

/// Natural-map residual ‖lambda − clamp(lambda − (A lambda − b), cmin, cmax)‖∞, N.
/// Zero exactly at a solution of the boxed LCP of 6.2.
double natural_map_residual(
    const SpMat& A, const VecX& b, const VecX& cmin, const VecX& cmax, const VecX& lambda);

/// One projected Gauss-Seidel sweep (7.1.1), in place, rows j = 0 … c−1:
///   lambda_j ← clamp((b_j − Σ_{i≠j} A_ji lambda_i) / A_jj, cmin_j, cmax_j),
/// each new lambda_j used at once. Returns max |Δlambda_j| (N).
double pgs_sweep(const SpMat& A,
                 const VecX& b,
                 const VecX& cmin,
                 const VecX& cmax,
                 VecX& lambda,
                 double relaxation = 1.0);

/// One projected Jacobi sweep: as pgs_sweep but every row reads the previous sweep's lambda;
/// with relaxation omega, lambda ← clamp(lambda + omega (lambda_J − lambda)).
double jacobi_sweep(const SpMat& A,
                    const VecX& b,
                    const VecX& cmin,
                    const VecX& cmax,
                    VecX& lambda,
                    double relaxation,
                    VecX& scratch);

/// PGS (7.1.1) from the guess in lambda until a tolerance or max_iterations.
SolverSummary solve_pgs(const SpMat& A,
                        const VecX& b,
                        const VecX& cmin,
                        const VecX& cmax,
                        VecX& lambda,
                        const SolverOptions& options);

/// Projected Jacobi from the guess in lambda.
SolverSummary solve_jacobi(const SpMat& A,
                           const VecX& b,
                           const VecX& cmin,
                           const VecX& cmax,
                           VecX& lambda,
                           const SolverOptions& options);

/// Direct solve of A lambda = b with all rows unbounded, by CHOLMOD's sparse Cholesky
/// (supernodal or simplicial, with the fill-reducing ordering CHOLMOD chooses).
/// Throws std::runtime_error if A is not positive definite or a row is bounded.
SolverSummary solve_cholesky(const SpMat& A, const VecX& b, VecX& lambda);

/// By name: "pgs", "jacobi", "direct".
SolverSummary solve(const std::string& method,
                    const SpMat& A,
                    const VecX& b,
                    const VecX& cmin,
                    const VecX& cmax,
                    VecX& lambda,
                    const SolverOptions& options);

/// Names accepted by solve().
bool is_solver_name(const std::string& method);

std::string to_string(Termination t);

}  // namespace cbps
