// Performance profiles of Dolan & Moré, "Benchmarking optimization software with performance
// profiles", Math. Program. 91 (2002) 201-213: how often a solver is within a factor tau of the
// best solver, over a set of problems. `cbps profile` draws them for time and sweeps.
//
//   Symbol     Meaning
//   t_{p,s}    cost of solver s on problem p (s, or sweeps); +inf where s failed on p
//   r_{p,s}    performance ratio t_{p,s} / min_s' t_{p,s'} (Dolan & Moré, section 2)
//   rho_s(tau) fraction of the problems with r_{p,s} <= tau (their eq. 1)
#pragma once

#include <cstddef>
#include <vector>

namespace cbps {

/// Costs t_{p,s}: cost[p][s], one row per problem, one column per solver; +inf (or NaN) where
/// the solver failed on the problem (did not reach the tolerance within its budget).
using CostTable = std::vector<std::vector<double>>;

/// The performance ratios r_{p,s} = t_{p,s} / min_s' t_{p,s'}, same layout as the costs. A
/// failure has r = +inf, Dolan & Moré's r_M, larger than every ratio of a solved problem; on a
/// problem no solver solved every r is +inf. A best cost of 0 (the guess already meets the
/// tolerance) gives r = 1 to each solver of cost 0 and +inf to the others. Throws
/// std::invalid_argument for rows of different lengths or a negative cost.
CostTable performance_ratios(const CostTable& cost);

/// rho_s(tau) = |{p : r_{p,s} <= tau}| / n_p (Dolan & Moré eq. 1), from the ratios; 0 for an
/// empty table. rho_s(1) is the fraction of problems where s is the best (ties count for each
/// solver tied); rho_s(+inf) the fraction it solved.
double performance_fraction(const CostTable& ratios, std::size_t solver, double tau);

}  // namespace cbps
