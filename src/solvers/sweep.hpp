// Private to solvers/: the pieces of 7.1.1 every sweeping method shares, and their sweep loop.
#pragma once

#include <chrono>
#include <cmath>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps::detail {

/// The matrix whose column k is row k of the problem's A, for the sweeps: A itself when it is
/// symmetric, else the Aᵀ that solve() formed (BoxedProblem::A_rows). SpMat is column-major, so
/// reading A's column k for row k (as the sweeps did) swept Aᵀ: 7.1.1 on a non-symmetric A
/// converged to the solution of the problem of Aᵀ (issue 28).
inline const SpMat& rows_of(const BoxedProblem& problem) {
  return problem.A_rows != nullptr ? *problem.A_rows : problem.A;
}

/// Row k of 7.1.1 before clamping: (b_k − Σ_{i≠k} A_ki x_i) / A_kk, with x the values the
/// sweep reads (the current lambda for Gauss-Seidel, the previous sweep's for Jacobi).
/// A_rows is rows_of(problem): its column k holds row k of A. Returns false for a row with
/// A_kk = 0 (j_c = 0 acts on nothing; its lambda stays).
inline bool row_target(
    const SpMat& A_rows, const VecX& b, const VecX& x, Eigen::Index k, double& target) {
  double sum = b(k);
  double A_kk = 0.0;
  for (SpMat::InnerIterator it(A_rows, k); it; ++it) {  // A_ki = (A_rows)_ik
    if (it.row() == k) {
      A_kk = it.value();
    } else {
      sum -= it.value() * x(it.row());
    }
  }
  if (!(A_kk > 0.0)) return false;
  target = sum / A_kk;
  return true;
}

/// lambda_old + omega (target − lambda_old), exactly the target when omega = 1 (7.1.1).
inline double relax(double old, double target, double relaxation) {
  return relaxation == 1.0 ? target : old + relaxation * (target - old);
}

/// Sweeps until a tolerance, options.max_iterations, a non-finite change or after_sweep's stop;
/// residual(lambda) is the natural-map residual (computed only when a tolerance or the last
/// sweep needs it) and unit_free(lambda) the unit-free residual's relative value (unit_free.hpp;
/// computed only where the residual is within the tolerance). The sweeps stop where the residual
/// is at most τ N, and with options.tolerance_unit_free (a problem read from a Siconos or FCLIB
/// file, in its simulator's units) where the unit-free residual is at most τ too: there τ N can be
/// reached far from the answer (LMGC_GFC3D-i00501-4 of Siconos' history, forces near 3e-10 N: at
/// λ = 0), and "tolerance reached" must not name an answer the verdict fails. Writes the
/// summary's message when options.describe.
template <class Sweep, class Residual, class UnitFree>
SolverSummary iterate_sweeps(Eigen::Index rows,
                             VecX& lambda,
                             const SolverOptions& options,
                             Sweep sweep,
                             Residual residual,
                             UnitFree unit_free) {
  const auto start = std::chrono::steady_clock::now();
  SolverSummary s;
  if (lambda.size() != rows) lambda = VecX::Zero(rows);
  if (rows == 0) {
    s.termination = Termination::ResidualTolerance;
    s.message = "no rows";
    return s;
  }
  const auto reached = [&](const VecX& l) {
    return options.tolerance > 0.0 && s.residual <= options.tolerance &&
           (!options.tolerance_unit_free || unit_free(l) <= options.tolerance);
  };
  s.residual = residual(lambda);
  if (reached(lambda)) s.termination = Termination::ResidualTolerance;
  double sweep_time = 0.0;  // s, in the sweeps alone (for after_sweep)
  while (s.termination == Termination::MaxIterations && s.iterations < options.max_iterations) {
    if (options.after_sweep) {  // the clock only for an observer: sweeps can be 1 µs
      const auto sweep_start = std::chrono::steady_clock::now();
      s.delta = sweep(lambda);
      sweep_time +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - sweep_start).count();
    } else {
      s.delta = sweep(lambda);
    }
    ++s.iterations;
    if (options.after_sweep && !options.after_sweep(s.iterations, lambda, sweep_time)) {
      s.termination = Termination::Stopped;
      s.residual = residual(lambda);
      break;
    }
    if (!std::isfinite(s.delta)) {
      s.termination = Termination::NonFinite;
      break;
    }
    if (past_deadline(options) ||
        (options.time_limit > 0.0 &&
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >=
             options.time_limit)) {
      s.termination = Termination::TimeLimit;
      s.residual = residual(lambda);
      if (reached(lambda)) s.termination = Termination::ResidualTolerance;
      break;
    }
    if (options.delta_tolerance > 0.0 && s.delta <= options.delta_tolerance) {
      s.termination = Termination::DeltaTolerance;
    }
    if (options.tolerance > 0.0 || s.iterations == options.max_iterations ||
        s.termination != Termination::MaxIterations) {
      s.residual = residual(lambda);
      if (reached(lambda)) s.termination = Termination::ResidualTolerance;
    }
  }
  if (!std::isfinite(s.residual)) s.termination = Termination::NonFinite;
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!options.describe) return s;
  std::ostringstream msg;
  msg << to_string(s.termination) << " after " << count_text(s.iterations, "sweep") << ", residual "
      << s.residual << " N, last change " << s.delta << " N";
  s.message = msg.str();
  return s;
}

/// iterate_sweeps with the natural-map residual of the explicit A.
template <class Sweep>
SolverSummary iterate_sweeps(const BoxedProblem& problem,
                             VecX& lambda,
                             const SolverOptions& options,
                             Sweep sweep) {
  return iterate_sweeps(
      problem.rows(),
      lambda,
      options,
      sweep,
      [&](const VecX& l) { return natural_map_residual(problem, l); },
      [&](const VecX& l) { return unit_free_residual(problem, l).relative; });
}

}  // namespace cbps::detail
