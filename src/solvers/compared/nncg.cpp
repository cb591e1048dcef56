// NNCG (Silcowitz-Hansen, Niebe and Erleben, The Visual Computer 2010): PGS sweeps (7.1.1) with
// a Fletcher–Reeves momentum and restarts. The formulas are listed in nncg.hpp.
#include "cbps/solvers/compared/nncg.hpp"

#include <cmath>
#include <sstream>

#include "../sweep.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/paper/pgs.hpp"

namespace cbps {

SolverSummary solve_nncg(const BoxedProblem& problem,
                         VecX& lambda,
                         const SolverOptions& options,
                         const NncgSettings& settings) {
  const Eigen::Index c = problem.rows();
  VecX p = VecX::Zero(c);     // p_{k−1}, N
  VecX swept(c);              // PGS(lambda_k), N
  double rr_previous = -1.0;  // ‖r_{k−1}‖², N²; < 0 before the first iteration
  int restarts = 0;
  SolverSummary s = detail::iterate_sweeps(problem, lambda, options, [&](VecX& l) {
    swept = l;
    pgs_sweep(problem, swept, options.relaxation);  // PGS(lambda_k)
    const VecX r = swept - l;                       // r_k
    const double rr = r.squaredNorm();
    double beta = 0.0;  // Fletcher–Reeves beta_k
    if (rr_previous > 0.0) {
      beta = rr / rr_previous;
      if (!(beta <= settings.restart_beta)) {  // restart; NaN ends the solve below anyway
        beta = 0.0;
        ++restarts;
      }
    } else if (rr_previous == 0.0) {
      beta = 0.0;  // the last sweep changed nothing: lambda_k was already a fixed point
    }
    rr_previous = rr;
    p = r + beta * p;  // p_k
    double delta = 0.0;
    for (Eigen::Index k = 0; k < c; ++k) {
      const double next = clamp(l(k) + p(k), problem.cmin(k), problem.cmax(k));  // lambda_{k+1}
      const double change = std::abs(next - l(k));
      max_keep_nan(delta, change);
      l(k) = next;
    }
    return delta;
  });
  s.restarts = restarts;
  if (options.describe) {
    std::ostringstream msg;
    msg << s.message << ", " << restarts << " restarts";
    s.message = msg.str();
  }
  return s;
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

namespace {

SolverSummary nncg_method(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_nncg(p, lambda, o, o.methods.nncg);
}

}  // namespace

/// nncg's own keys (`--solver NAME:key=value`, /solver/parameters), over its settings
/// (method_settings.hpp).
constexpr MethodKey kNncgKeys[] = {
    {"restart_beta",
     "a number >= 0",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.nncg.restart_beta) && s.nncg.restart_beta >= 0.0;
     },
     [](const MethodSettings& s) -> std::string { return key_number(s.nncg.restart_beta); }},
};

extern const MethodEntry kNncgEntry;
constexpr MethodEntry kNncgEntry{
    .method = Method::Nncg,
    .name = "nncg",
    .symmetric = true,
    .symmetric_on_cones = true,
    .solve = nncg_method,
    .what =
        "nonsmooth nonlinear conjugate gradient on PGS sweeps (Silcowitz, Niebe & Erleben "
        "2010); restart_beta=",
    .keys = kNncgKeys,
};

}  // namespace cbps
