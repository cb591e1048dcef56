// The improved push factor (paper 8.1), in one place. The original form (5.2.3, 5.3) puts each
// row's push term in the one system A lambda = b, so the velocities it gives both move the
// bodies and are kept: the push that corrects a position error stays in the velocity as energy.
// 8.1 solves two systems with the same J, Minv, A, cmin and cmax:
//   the velocity system  b   = upsilon/dt − J (v1/dt + Minv fext),  upsilon without the push;
//                        its v2 is kept as the bodies' velocity (momenta p = m v2, l = I omega2);
//   the position system  b_p = (upsilon + upsilon_push)/dt − J (v1/dt + Minv fext);
//                        its velocities v_p only move the bodies this step (3.2) and are dropped.
// assemble_system leaves the push out of upsilon under PushMode::Improved (system.hpp);
// Simulation::position_velocities (step/push.cpp) forms and solves the position system.
#pragma once

#include "cbps/system/system.hpp"

namespace cbps {

/// The position system's bias upsilon + upsilon_push (8.1), m/s, row by row (with_push).
VecX position_bias(const System& sys);

}  // namespace cbps
