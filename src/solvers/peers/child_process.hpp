// A peer's solve in a child process: what it returns comes back through a pipe, how it ended
// (an abort, exit(), a signal) is reported instead when it sends nothing, and it is killed at
// SolverOptions::time_limit. Siconos runs there always (it can end the process it runs in);
// Bullet, which cannot be interrupted, there when a time limit is set.
#pragma once

#include "cbps/solvers/peers/peers.hpp"

namespace cbps {

/// The peer's solve of the problem in this process.
using PeerSolve = PeerRun (*)(const BoxedProblem& problem,
                              VecX& lambda,
                              const SolverOptions& options);

/// run_here(problem, lambda, options) in a forked child, which ends with this process however it
/// ends (Ctrl-C, SIGTERM, SIGKILL). lambda: the child's answer, or the guess as it was when the
/// child sent no whole reply (PeerRun::status says how it ended, naming `library`) or was killed
/// at options.time_limit (PeerRun::timed_out).
PeerRun run_in_child(const BoxedProblem& problem,
                     VecX& lambda,
                     const SolverOptions& options,
                     PeerSolve run_here,
                     const char* library);

}  // namespace cbps
