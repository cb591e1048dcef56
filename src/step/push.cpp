// The improved push factor (paper 8.1): the position system. push.hpp explains the two systems.
#include "cbps/step/push.hpp"

#include "cbps/step/guard.hpp"
#include "cbps/step/simulation.hpp"
#include "stage_timer.hpp"

namespace cbps {

VecX position_bias(const System& sys) {
  VecX upsilon(sys.rows());
  for (int k = 0; k < sys.rows(); ++k) upsilon(k) = with_push(sys.upsilon(k), sys.upsilon_push(k));
  return upsilon;
}

VecX Simulation::position_velocities(const System& sys, const VecX& lambda, StepReport& report) {
  VecX lambda_position, v_position;
  {
    const detail::StageTimer solve(report.times.solve);
    const VecX b_position =
        compute_b(position_bias(sys), sys.J, sys.v1, sys.Minv, sys.fext, sys.dt);  // (6.2.9)
    // Start from this step's velocity λ plus last step's push increment λ_position − λ: the
    // two systems differ only by the push (8.1). (4.1 cm top drift against 6.1 cm from the last
    // λ_position, 10-box stack, 20 sweeps.) The increment takes the rows' warm-start factors.
    lambda_position = position_guess(sys, lambda);
    report.position_solver = solve_system(sys, b_position, lambda_position);
  }
  v_position = compute_v2(sys, lambda_position);  // (12.3.1), with the position system's λ
  check_divergence(sys,
                   scene_.bodies,
                   scene_.world,
                   lambda_position,
                   v_position,
                   steps_,
                   "position system (8.1)");
  warm_position_.clear();
  for (int k = 0; k < sys.rows(); ++k)
    warm_position_[sys.ids[static_cast<std::size_t>(k)]] = lambda_position(k) - lambda(k);
  return v_position;
}

}  // namespace cbps
