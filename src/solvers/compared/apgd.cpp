// Accelerated projected gradient descent (Mazhar, Heyn, Negrut, Tasora, ACM TOG 2015) on the
// boxed problem of 6.2, or on its cones' relaxation; apgd.hpp states the iteration and its
// choices.
#include "cbps/solvers/compared/apgd.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "../sweep.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/system/cone_problem.hpp"

namespace cbps {

SolverSummary solve_apgd(const BoxedProblem& problem,
                         VecX& lambda,
                         const SolverOptions& options,
                         const ApgdSettings& settings) {
  const Eigen::Index c = problem.rows();
  if (lambda.size() != c) lambda = VecX::Zero(c);
  long products = 0;  // products with A
  const auto times_A = [&](const VecX& x) {
    ++products;
    return VecX(problem.A * x);
  };

  // λ_k with A λ_k, y_k with A y_k (λ in N, A λ in m/s²), θ_k, and L_k (kg⁻¹).
  VecX Ax = c > 0 ? times_A(lambda) : VecX();
  VecX y = lambda;
  VecX Ay = Ax;
  double theta = 1.0;
  double L = max_abs_row_sum(problem.A);  // ‖A‖∞ ≥ A's largest eigenvalue (Gershgorin)
  if (!(L > 0.0) && std::isfinite(L)) L = 1.0;  // A = 0: any step length is exact
  int restarts = 0;
  // The natural-map residual from w = A λ − b (the box's, or with cones the relaxation's).
  const auto residual_of = [&](const VecX& w, const VecX& l) {
    return problem.cones != nullptr
               ? natural_map_residual(w, l, problem.cmin, problem.cmax, *problem.cones)
               : natural_map_residual(w, l, problem.cmin, problem.cmax);
  };
  // The best iterate so far and its natural-map residual (the starting guess counts).
  VecX best = lambda;
  double best_residual = c > 0 ? residual_of(VecX(Ax - problem.b), lambda) : 0.0;
  double residual = best_residual;  // of the current iterate λ_k

  VecX next(c), Anext(c), d(c);
  const auto step = [&](VecX& l) {
    const VecX g = Ay - problem.b;  // ∇f(y_k) = A y_k − b
    // λ_{k+1} = P(y_k − g / L), P the projection onto the box (or the cones, Mazhar et al.'s
    // own set); backtrack while ½ dᵀA d > ½ L dᵀd (f overshoots its model).
    for (int trial = 0;; ++trial) {
      next = y - g / L;
      project_onto_set(problem.cmin, problem.cmax, problem.cones, next);
      Anext = times_A(next);
      d = next - y;
      const double curvature = d.dot(Anext - Ay);  // dᵀA d
      if (!(curvature > L * d.squaredNorm()) || trial >= settings.max_backtracks) break;
      L *= settings.grow;
    }
    // θ_{k+1}, β_{k+1} and the restart test gᵀ(λ_{k+1} − λ_k) > 0.
    const double theta_next = 0.5 * (-theta * theta + theta * std::sqrt(theta * theta + 4.0));
    double beta = theta * (1.0 - theta) / (theta * theta + theta_next);
    theta = theta_next;
    if (settings.restart && g.dot(next - l) > 0.0) {
      beta = 0.0;
      theta = 1.0;
      ++restarts;
    }
    // y_{k+1} = λ_{k+1} + β (λ_{k+1} − λ_k), and A y_{k+1} by linearity (no product).
    y = next + beta * (next - l);
    Ay = (1.0 + beta) * Anext - beta * Ax;
    double delta = 0.0;
    for (Eigen::Index k = 0; k < c; ++k) {
      const double change = std::abs(next(k) - l(k));
      if (std::isnan(change) || change > delta) delta = change;  // a NaN stays
    }
    l = next;
    Ax = Anext;
    residual = residual_of(VecX(Ax - problem.b), l);
    if (residual < best_residual) {
      best = l;
      best_residual = residual;
    }
    L *= settings.shrink;
    return delta;
  };

  // iterate_sweeps asks for the residual only of the iterate the last step made (or the start).
  SolverSummary s = detail::iterate_sweeps(
      c,
      lambda,
      options,
      step,
      [&](const VecX&) { return residual; },
      [&](const VecX& l) { return unit_free_residual(problem, l).relative; });
  s.restarts = restarts;
  const bool returned_best = std::isfinite(best_residual) && !(s.residual <= best_residual);
  if (returned_best) {
    lambda = best;
    s.residual = best_residual;
  }
  if (options.describe) {
    std::ostringstream msg;
    msg << "apgd: " << s.message << ", " << products << " products with A, " << restarts
        << " restarts, final L " << L << " kg^-1";
    if (returned_best) msg << "; returned an earlier iterate, residual " << best_residual << " N";
    s.message = msg.str();
  }
  return s;
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

namespace {

SolverSummary apgd_method(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_apgd(p, lambda, o, o.methods.apgd);
}

}  // namespace

/// apgd's own keys (`--solver NAME:key=value`, /solver/parameters), over its settings
/// (method_settings.hpp).
constexpr MethodKey kApgdKeys[] = {
    {"restart",
     "on or off",
     [](const std::string& v, MethodSettings& s) { return on_off(v, s.apgd.restart); },
     [](const MethodSettings& s) -> std::string { return s.apgd.restart ? "on" : "off"; }},
    {"grow",
     "a number > 1",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.apgd.grow) && s.apgd.grow > 1.0;
     },
     [](const MethodSettings& s) -> std::string { return key_number(s.apgd.grow); }},
    {"shrink",
     "a number in (0, 1]",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.apgd.shrink) && s.apgd.shrink > 0.0 && s.apgd.shrink <= 1.0;
     },
     [](const MethodSettings& s) -> std::string { return key_number(s.apgd.shrink); }},
};

extern const MethodEntry kApgdEntry;
constexpr MethodEntry kApgdEntry{
    .method = Method::Apgd,
    .name = "apgd",
    .symmetric = true,
    .symmetric_on_cones = true,
    .laws = kRelaxationLaw,
    .solve = apgd_method,
    .what =
        "accelerated projected gradient descent (Mazhar et al. 2015); grow=, shrink=, "
        "restart=on|off",
    .keys = kApgdKeys,
};

}  // namespace cbps
