// tao:TYPE in converge and profile (distributed/tao_studies.hpp).
#include "cbps/distributed/tao_studies.hpp"

#include <cmath>

#include "cbps/system/system.hpp"

namespace cbps::distributed {

namespace {

/// TAO on the problem studied: it is handed the matrix itself, A + eps E.
TaoResult solve_studied(const MpiSession& session,
                        const StoredProblem& stored,
                        const std::string& type,
                        int max_iterations,
                        double tolerance,
                        const TaoMonitor& monitor) {
  const SpMat A_solved = with_cfm(stored.A, stored.cfm);
  TaoOptions options;
  options.type = type;
  options.max_iterations = max_iterations;
  options.tolerance = tolerance;
  options.monitor = monitor;
  return solve_tao(session, BoxedProblem{A_solved, stored.b, stored.cmin, stored.cmax}, options);
}

}  // namespace

ConvergenceRun converge_tao(const MpiSession& session,
                            const ConvergenceSystem& s,
                            const SolverSpec& spec,
                            const ConvergenceLimits& limits) {
  ConvergenceRun run;
  run.spec = spec;
  run.samples.push_back(measure(s, VecX::Zero(s.stored.rows()), 0, 0.0));
  run.reach(0, 0.0, run.samples.back().residual);
  VecX last_lambda;  // the last iteration's, when it was not recorded
  int last_k = 0;
  double last_time = 0.0, last_residual = run.samples.back().residual;
  const TaoMonitor monitor = [&](const TaoIterate& at, const VecX& l) {
    if (at.iteration <= last_k) return true;  // TAO's start (the guess row) or a repeat
    run.reach(at.iteration, at.time_s, at.residual);
    if (!std::isfinite(at.residual)) run.stopped = "non-finite values";
    if (run.stopped.empty() && at.time_s >= limits.time_limit) run.stopped = "time limit";
    const bool record = recorded_sweep(at.iteration, limits.record_every) || !run.stopped.empty() ||
                        at.iteration >= limits.iterations || at.residual <= limits.tolerance;
    if (record) {
      ConvergenceSample m = measure(s, l, at.iteration, at.time_s);
      m.residual = at.residual;  // the one TAO's stopping test saw
      run.samples.push_back(m);
    } else {
      last_lambda = l;
    }
    last_k = at.iteration;
    last_time = at.time_s;
    last_residual = at.residual;
    if (limits.progress && at.iteration % 1000 == 0)
      limits.progress(spec, at.iteration, at.time_s, at.residual);
    return run.stopped.empty();
  };
  const TaoResult r =
      solve_studied(session, s.stored, spec.tao, limits.iterations, limits.tolerance, monitor);
  if (run.stopped.empty())
    run.stopped = r.residual <= limits.tolerance  ? "residual tolerance"
                  : r.reason == "DIVERGED_MAXITS" ? "iteration limit"
                                                  : "TAO " + r.reason;
  if (run.samples.back().iteration != last_k) {  // TAO stopped on its own
    ConvergenceSample m = measure(s, last_lambda, last_k, last_time);
    m.residual = last_residual;
    run.samples.push_back(m);
  }
  return run;
}

ProfileMeasurement profile_tao(const MpiSession& session,
                               const ProfileProblem& p,
                               const SolverSpec& spec,
                               const ProfileLimits& limits) {
  ProfileMeasurement m;
  m.reach(0, 0.0, p.relative(VecX::Zero(p.stored.rows())));
  // One process: the monitor's lambda is the whole answer.
  const TaoMonitor monitor = [&](const TaoIterate& at, const VecX& lambda) {
    if (at.iteration == 0) return true;  // TAO's start
    const double relative = p.relative(lambda);
    m.reach(at.iteration, at.time_s, relative);
    m.iterations = at.iteration;
    m.time_s = at.time_s;
    if (!std::isfinite(relative)) m.status = "non-finite";
    if (m.reached[kProfileTolerancesCount - 1].iterations >= 0) m.status = "solved";
    if (m.status.empty() && at.time_s >= limits.time_limit) m.status = "time limit";
    return m.status.empty();
  };
  // The monitor stops it: the unit-free residual is not TAO's measure (tolerance 0).
  const TaoResult r =
      solve_studied(session, p.stored, spec.tao, limits.budget_iterations, 0.0, monitor);
  if (m.status.empty())
    m.status = r.reason == "DIVERGED_MAXITS" ? "iteration budget" : "TAO " + r.reason;
  finish_measurement(m, p, r.lambda);
  return m;
}

}  // namespace cbps::distributed
