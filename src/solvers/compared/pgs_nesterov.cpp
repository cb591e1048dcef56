// Projected Gauss-Seidel (7.1.1) with Nesterov momentum and the gradient restart of O'Donoghue &
// Candès (2015); pgs_nesterov.hpp states the iteration.
#include "cbps/solvers/compared/pgs_nesterov.hpp"

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "../sweep.hpp"
#include "cbps/solvers/paper/pgs.hpp"

namespace cbps {

SolverSummary solve_pgs_nesterov(const BoxedProblem& problem,
                                 VecX& lambda,
                                 const SolverOptions& options,
                                 const PgsNesterovSettings& settings) {
  const Eigen::Index c = problem.rows();
  if (lambda.size() != c) lambda = VecX::Zero(c);
  VecX previous = lambda;  // λ_{k−1}, N; equal to λ_k when the next step has no momentum
  VecX y(c);               // the extrapolated point the sweep starts from, N
  double t = 1.0;          // t_k of the momentum sequence
  int restarts = 0;

  std::mt19937_64 rng(options.seed);
  std::vector<int> rows;
  if (options.order == RowOrder::Reverse) sweep_order(options.order, int(c), rng, rows);

  const auto step = [&](VecX& l) {
    // Extrapolate: y = clamp(λ_k + β_k (λ_k − λ_{k−1})), β_k = (t_k − 1) / t_{k+1}.
    const double t_next = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * t * t));
    const double beta = (t - 1.0) / t_next;
    for (Eigen::Index k = 0; k < c; ++k)
      y(k) = clamp(l(k) + beta * (l(k) - previous(k)), problem.cmin(k), problem.cmax(k));
    previous = l;  // λ_k
    l = y;
    // λ_{k+1}: one sweep of 7.1.1 from y.
    if (options.order == RowOrder::Natural) {
      pgs_sweep(problem, l, options.relaxation);
    } else {
      if (options.order == RowOrder::Random) sweep_order(options.order, int(c), rng, rows);
      pgs_sweep(problem, l, options.relaxation, rows);
    }
    // The iteration's change max |λ_{k+1} − λ_k| and the gradient test's (y − λ_{k+1})ᵀ(λ_{k+1} −
    // λ_k), in one pass.
    double delta = 0.0;
    double uphill = 0.0;
    for (Eigen::Index k = 0; k < c; ++k) {
      const double change = l(k) - previous(k);
      if (std::isnan(change) || std::abs(change) > delta) delta = std::abs(change);  // a NaN stays
      uphill += (y(k) - l(k)) * change;
    }
    if (settings.restart && uphill > 0.0) {
      // The step went uphill along the momentum: t = 1 and no momentum into the next step.
      t = 1.0;
      previous = l;
      ++restarts;
    } else {
      t = t_next;
    }
    return delta;
  };

  SolverSummary s = detail::iterate_sweeps(problem, lambda, options, step);
  s.restarts = restarts;
  if (options.describe) {
    s.message = "pgs-nesterov: " + s.message + ", " + std::to_string(restarts) + " restarts";
  }
  return s;
}

}  // namespace cbps
