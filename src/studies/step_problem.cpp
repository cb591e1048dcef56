// The problem a step solved, and the same posed on Coulomb's cone (step_problem.hpp).
#include "cbps/studies/step_problem.hpp"

#include "cbps/base/error.hpp"
#include "cbps/solvers/paper/coulomb.hpp"

namespace cbps {

StepProblem solved_step_problem(Simulation& sim,
                                const Scene& scene,
                                const System& sys,
                                const std::string& what) {
  StepProblem out;
  SolverSettings exact = scene.solver;
  exact.method = Method::Direct;
  exact.tolerance = 0.0;
  out.lambda = VecX::Zero(sys.rows());
  out.direct = sim.solve_system(sys, sys.b, out.lambda, exact);
  out.coulomb = sys.coulomb().any();
  // With Coulomb friction the boxed problem is the one whose bounds ±mu lambda_n come from
  // lambda itself: lambda must solve it, by `cbps lcp`'s verdict (a singular resting contact may
  // leave the direct path a little above its rounding floor, never above that).
  if (out.coulomb &&
      !is_solved(coulomb_unit_free(sys.problem(), sys.coulomb(), out.lambda, scene.solver.cfm),
                 out.lambda))
    throw ComputationError(what + ": the Coulomb bounds did not reach a fixed point (" +
                           out.direct.message + "), so no boxed problem is the step's");
  out.problem = stored_problem(sys, scene.solver.cfm);
  // The bounds lambda satisfies: Coulomb rows at ±mu lambda_n.
  coulomb_bounds(sys.problem(), sys.coulomb(), out.lambda, out.problem.cmin, out.problem.cmax);
  return out;
}

PosedOnCones pose_on_cones(const System& sys, const StoredProblem& boxed, double mu, ConeLaw law) {
  PosedOnCones out;
  out.problem = boxed;
  out.problem.cones = contacts_in_cones(sys, mu, law);
  if (out.problem.cones.empty()) throw InputError("it has no contacts");
  for (const int n : out.problem.cones.normal) {  // the cone replaces the box: the rows' own sets
    out.problem.cmin(n) = 0.0;
    out.problem.cmax(n) = kInf;
    for (const int t : {n + 1, n + 2}) {
      out.problem.cmin(t) = -kInf;
      out.problem.cmax(t) = kInf;
    }
  }
  SolverOptions exact;
  exact.method = Method::Direct;
  exact.tolerance = 0.0;
  out.lambda = VecX::Zero(out.problem.rows());
  out.direct = solve(out.problem.problem(), out.lambda, exact);
  out.unit_free = unit_free_residual(out.problem.problem(), out.lambda);
  out.verified = is_solved(out.unit_free, out.lambda);
  return out;
}

}  // namespace cbps
