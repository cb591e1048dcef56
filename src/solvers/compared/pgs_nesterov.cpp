// Projected Gauss-Seidel (7.1.1) with Nesterov momentum and the gradient restart of O'Donoghue &
// Candès (2015); pgs_nesterov.hpp states the iteration.
#include "cbps/solvers/compared/pgs_nesterov.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "../sweep.hpp"
#include "cbps/solvers/cone/nsgs.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/system/cone_problem.hpp"

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

  // On the relaxation's cones the sweep is nsgs's (7.1.1 with each contact projected onto its
  // cone), in row order.
  const std::unique_ptr<NsgsSweep> cone_sweep =
      problem.cones != nullptr ? std::make_unique<NsgsSweep>(problem) : nullptr;
  const int local = std::max(1, options.methods.nsgs.local);

  const auto step = [&](VecX& l) {
    // Extrapolate: y = P(λ_k + β_k (λ_k − λ_{k−1})), β_k = (t_k − 1) / t_{k+1}, P the
    // projection onto the problem's set (the box; each contact's cone where it has cones).
    const double t_next = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * t * t));
    const double beta = (t - 1.0) / t_next;
    y = l + beta * (l - previous);
    project_onto_set(problem.cmin, problem.cmax, problem.cones, y);
    previous = l;  // λ_k
    l = y;
    // λ_{k+1}: one sweep of 7.1.1 from y.
    if (cone_sweep) {
      (*cone_sweep)(l, local);
    } else if (options.order == RowOrder::Natural) {
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

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

namespace {

SolverSummary pgs_nesterov_method(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_pgs_nesterov(p, lambda, o, o.methods.pgs_nesterov);
}

}  // namespace

/// pgs-nesterov's own keys (`--solver NAME:key=value`, /solver/parameters), over its settings
/// (method_settings.hpp).
constexpr MethodKey kPgsNesterovKeys[] = {
    {"restart",
     "on or off",
     [](const std::string& v, MethodSettings& s) { return on_off(v, s.pgs_nesterov.restart); },
     [](const MethodSettings& s) -> std::string { return s.pgs_nesterov.restart ? "on" : "off"; }},
};

extern const MethodEntry kPgsNesterovEntry;
constexpr MethodEntry kPgsNesterovEntry{
    .method = Method::PgsNesterov,
    .name = "pgs-nesterov",
    .omega = true,
    .order = true,
    .laws = kRelaxationLaw,
    .solve = pgs_nesterov_method,
    .what =
        "PGS with Nesterov momentum and adaptive restart (O'Donoghue & Candes 2015); "
        "restart=on|off",
    .keys = kPgsNesterovKeys,
};

}  // namespace cbps
