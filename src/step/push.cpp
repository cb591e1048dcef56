// The improved push factor (paper 8.1): the position system. push.hpp explains the two systems.
#include "cbps/step/push.hpp"

#include "cbps/solvers/paper/coulomb.hpp"

namespace cbps {

VecX position_bias(const System& sys) {
  VecX upsilon(sys.rows());
  for (int k = 0; k < sys.rows(); ++k) upsilon(k) = with_push(sys.upsilon(k), sys.upsilon_push(k));
  return upsilon;
}

SolverSummary solve_position_system(const System& sys,
                                    VecX& lambda_position,
                                    const SolverOptions& options) {
  const VecX b_position =
      compute_b(position_bias(sys), sys.J, sys.v1, sys.Minv, sys.fext, sys.dt);  // (6.2.9)
  return solve_coulomb(sys.push_problem(b_position), sys.coulomb(), lambda_position, options);
}

}  // namespace cbps
