// The divergence guard, run after every solve of every step: a run that blows up stops at the
// step it happens, naming the body and the row, before the positions move.
#pragma once

#include <vector>

#include "cbps/body/body.hpp"
#include "cbps/scene/scene.hpp"
#include "cbps/system/system.hpp"

namespace cbps {

/// Throws DivergenceError when any lambda or v2 entry is not finite, or a body's speed |v| or
/// spin |omega| exceeds the world's limits (World::divergence_speed, divergence_spin). The
/// message names the step and its time, `system` (which system was solved), the body and the
/// row with the largest impulse on it.
void check_divergence(const System& sys,
                      const std::vector<Body>& bodies,
                      const World& world,
                      const VecX& lambda,
                      const VecX& v2,
                      long step,
                      const char* system);

}  // namespace cbps
