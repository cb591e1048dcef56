// tao:TYPE in `cbps converge` and `cbps profile` (docs/distributed.md, "TAO beside PGS: converge
// and profile"): PETSc/TAO's bound-constrained minimisers in this one process, a job of one MPI
// rank, measured as the studies measure every other method. Built only with PETSc; the studies
// reach these through their run_spec and profile_spec, which the command line hands them.
#pragma once

#include "cbps/distributed/tao.hpp"
#include "cbps/studies/convergence.hpp"
#include "cbps/studies/profile.hpp"

namespace cbps::distributed {

/// tao:TYPE on `s` from lambda = 0 (TAO has no warm start here): every TAO iteration as a sweep,
/// by the monitor of solve_tao, which also gives the natural-map residual on PETSc's vectors;
/// the stops of run_iterative (the tolerance by solve_tao's own test, the time limit and
/// non-finite values by the monitor), the limits' progress every 1000 iterations.
ConvergenceRun converge_tao(const MpiSession& session,
                            const ConvergenceSystem& s,
                            const SolverSpec& spec,
                            const ConvergenceLimits& limits);

/// tao:TYPE on `p` from lambda = 0: each TAO iteration as a sweep, at most the budget's
/// iterations, stopped by the monitor at the time limit or once the unit-free residual reaches
/// the finest of the profile's tolerances.
ProfileMeasurement profile_tao(const MpiSession& session,
                               const ProfileProblem& p,
                               const SolverSpec& spec,
                               const ProfileLimits& limits);

}  // namespace cbps::distributed
