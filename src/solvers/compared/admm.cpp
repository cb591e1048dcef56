// ADMM on the box QP of 6.2 with one CHOLMOD factor of A + rho E kept while rho stays. The
// method, its parameters and its sources are described at solve_admm() in admm.hpp.
#include "cbps/solvers/compared/admm.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "../sweep.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/solvers/exact/cholmod_factor.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/system/cone_problem.hpp"

namespace cbps {

namespace {

/// The mean of A's diagonal, kg⁻¹ (1 when it is empty or zero: rho must be positive).
double mean_diagonal(const SpMat& A) {
  const double mean = A.rows() > 0 ? A.diagonal().sum() / double(A.rows()) : 0.0;
  return mean > 0.0 ? mean : 1.0;
}

}  // namespace

SolverSummary solve_admm(const BoxedProblem& problem,
                         VecX& lambda,
                         const SolverOptions& options,
                         const AdmmSettings& settings) {
  const Eigen::Index c = problem.rows();
  const SpMat& A = problem.A;
  const VecX& b = problem.b;
  if (lambda.size() != c) lambda = VecX::Zero(c);
  project_onto_set(problem.cmin, problem.cmax, problem.cones, lambda);

  const double diagonal = mean_diagonal(A);
  double rho = settings.rho * diagonal;  // kg⁻¹
  const double rho_min = settings.rho_min * diagonal;
  CholmodFactor factor;
  int factorizations = 0;
  bool factored = true;
  if (c > 0) {
    factored = factor.factor(A, rho);  // A + rho E (Boyd et al. §5.2)
    ++factorizations;
  }
  if (!factored) {
    SolverSummary s;
    s.termination = Termination::NonFinite;
    s.residual = natural_map_residual(problem, lambda);
    s.factorizations = factorizations;
    if (options.describe) s.message = "A + rho E is not positive definite (NaN in A?)";
    return s;
  }

  // z is lambda itself; u the scaled dual, u = y / rho (Boyd et al. §3.1.1). The warm start's
  // u = (b − A z) / rho = −w / rho makes a solution a fixed point of the iteration.
  VecX u = c > 0 ? VecX((b - A * lambda) / rho) : VecX();
  VecX x, rhs, z_old, relaxed;
  SolverSummary s = detail::iterate_sweeps(problem, lambda, options, [&](VecX& z) {
    rhs = b + rho * (z - u);
    factor.solve(rhs, x);  // (A + rho E) lambda_x = b + rho (z − u), N
    if (!x.allFinite()) return std::numeric_limits<double>::quiet_NaN();  // z stays in the box
    z_old = z;
    const double alpha = settings.alpha;
    relaxed = alpha * x + (1.0 - alpha) * z_old;  // §3.4.3
    // z = P(relaxed + u): the box's clamp, or each contact's cone (the relaxation's set).
    z = relaxed + u;
    project_onto_set(problem.cmin, problem.cmax, problem.cones, z);
    double delta = 0.0;
    double r2 = 0.0, s2 = 0.0;  // ‖lambda_r − z‖₂², ‖z − z_old‖₂² (before the factor rho)
    for (Eigen::Index k = 0; k < c; ++k) {
      const double primal = relaxed(k) - z(k);  // r_k, also the step of u
      u(k) += primal;
      const double change = std::abs(z(k) - z_old(k));
      max_keep_nan(delta, change);
      r2 += primal * primal;
      s2 += change * change;
    }
    if (settings.adapt_rho) {  // residual balancing (§3.4.1): ‖r‖ against ‖s‖ = rho ‖Δz‖
      const double r = std::sqrt(r2), dual = rho * std::sqrt(s2);
      double next = rho;
      if (r > settings.mu * dual) next = rho * settings.tau;
      if (dual > settings.mu * r) next = std::max(rho / settings.tau, std::min(rho, rho_min));
      if (next != rho) {
        u *= rho / next;  // y = rho u stays
        rho = next;
        ++factorizations;
        if (!factor.refactor(A, rho)) return std::numeric_limits<double>::quiet_NaN();
      }
    }
    return delta;
  });
  s.factorizations = factorizations;
  if (options.describe) {
    std::ostringstream msg;
    msg << ", rho " << rho << " kg^-1, " << factorizations << " factorizations";
    s.message += msg.str();
  }
  return s;
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

namespace {

SolverSummary admm_method(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_admm(p, lambda, o, o.methods.admm);
}

}  // namespace

/// admm's own keys (`--solver NAME:key=value`, /solver/parameters), over its settings
/// (method_settings.hpp).
constexpr MethodKey kAdmmKeys[] = {
    {"rho",
     "a number > 0",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.admm.rho) && s.admm.rho > 0.0;
     },
     [](const MethodSettings& s) -> std::string { return key_number(s.admm.rho); }},
    {"alpha",
     "a number in (0, 2)",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.admm.alpha) && s.admm.alpha > 0.0 && s.admm.alpha < 2.0;
     },
     [](const MethodSettings& s) -> std::string { return key_number(s.admm.alpha); }},
    {"adapt",
     "on or off",
     [](const std::string& v, MethodSettings& s) { return on_off(v, s.admm.adapt_rho); },
     [](const MethodSettings& s) -> std::string { return s.admm.adapt_rho ? "on" : "off"; }},
    {"rho_min",
     "a number > 0",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.admm.rho_min) && s.admm.rho_min > 0.0;
     },
     [](const MethodSettings& s) -> std::string { return key_number(s.admm.rho_min); }},
};

extern const MethodEntry kAdmmEntry;
constexpr MethodEntry kAdmmEntry{
    .method = Method::Admm,
    .name = "admm",
    .symmetric = true,
    .symmetric_on_cones = true,
    .laws = kRelaxationLaw,
    .solve = admm_method,
    .what =
        "ADMM with one factor of A + rho E (Boyd et al. 2011); rho=, alpha=, adapt=on|off, "
        "rho_min=",
    .keys = kAdmmKeys,
};

}  // namespace cbps
