// The improved push factor (paper 8.1), in one place. The original form (5.2.3, 5.3) puts each
// row's push term in the one system A lambda = b, so the velocities it gives both move the
// bodies and are kept: the push that corrects a position error stays in the velocity as energy.
// 8.1 solves two systems with the same J, Minv, A, cmin and cmax:
//   the velocity system  b   = upsilon/dt − J (v1/dt + Minv fext),  upsilon without the push;
//                        its v2 is kept as the bodies' velocity (momenta p = m v2, l = I omega2);
//   the position system  b_p = (upsilon + upsilon_push)/dt − J (v1/dt + Minv fext);
//                        its velocities v_p only move the bodies this step (3.2) and are dropped.
// assemble_system leaves the push out of upsilon under PushMode::Improved (system.hpp);
// solve_position_system forms and solves the position system; the step (step/simulation.cpp)
// starts it from its guess, guards it and keeps its lambda for the next step's guess.
#pragma once

#include "cbps/solvers/solver.hpp"
#include "cbps/system/system.hpp"

namespace cbps {

/// The position system's bias upsilon + upsilon_push (8.1), m/s, row by row (with_push).
VecX position_bias(const System& sys);

/// Solves the position system b_position = (upsilon + upsilon_push)/dt − J (v1/dt + Minv fext)
/// (6.2.9 with 8.1's bias) with the velocity system's A, cmin, cmax and `options`, from the
/// guess in lambda_position, N; Coulomb friction rows (5.4) take their bounds ±mu lambda_normal
/// from it (solve_coulomb), as in the velocity system.
SolverSummary solve_position_system(const System& sys,
                                    VecX& lambda_position,
                                    const SolverOptions& options);

}  // namespace cbps
