// Coulomb friction (5.4 with bounds ±mu lambda_n, as ODE, Bullet and Box2D bound it): a friction
// row's bounds move with its contact row's lambda, so the step's problem is a fixed point of
// boxed problems rather than one. This wraps any method around that fixed point.
#pragma once

#include <vector>

#include "cbps/solvers/solver.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps {

/// The bounds at lambda: problem.cmin, problem.cmax with each Coulomb row's set to
/// ∓mu max(0, lambda_normal) (5.4), N.
void coulomb_bounds(const BoxedProblem& problem,
                    const CoulombRows& coulomb,
                    const VecX& lambda,
                    VecX& cmin,
                    VecX& cmax);

/// The natural-map residual at lambda with the Coulomb bounds taken at lambda
/// (coulomb_bounds) and constraint-force mixing cfm (kg⁻¹) on A's diagonal, N.
double coulomb_residual(const BoxedProblem& problem,
                        const CoulombRows& coulomb,
                        const VecX& lambda,
                        double cfm);

/// The unit-free residual (system/unit_free.hpp, the verdict's) at lambda with the Coulomb bounds
/// taken at lambda (coulomb_bounds) and constraint-force mixing cfm (kg⁻¹) on A's diagonal; the
/// problem's cones, if any, kept.
UnitFreeResidual coulomb_unit_free(const BoxedProblem& problem,
                                   const CoulombRows& coulomb,
                                   const VecX& lambda,
                                   double cfm);

/// Solves the problem with Coulomb bounds by options.method, from the guess in lambda. The
/// direct path iterates to a fixed point: solve the boxed problem, move the bounds to
/// ±mu lambda_n, again, until lambda solves the box of its own bounds as closely as the solve
/// solved its box (or no bound moves by more than 1e-12 max(1, ‖b‖∞)); where the rounds stall
/// (five without halving that residual) or a round's solve stops short, semismooth Newton steps
/// on the Coulomb box's own natural map from the rounds' best lambda; at most 100 rounds,
/// NotConverged otherwise. The iterative methods move the bounds before every sweep: the
/// Gauss-Seidel and Jacobi sweeps within one solve (options.after_sweep still called, with the
/// sweeps counted from the start), the others in one solve per sweep. A's symmetry is tested
/// once. Without Coulomb rows this is solve(). CFM as in solve().
SolverSummary solve_coulomb(const BoxedProblem& problem,
                            const CoulombRows& coulomb,
                            VecX& lambda,
                            const SolverOptions& options);

}  // namespace cbps
