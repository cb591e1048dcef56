// Non-smooth Gauss-Seidel (NSGS) on friction cones: the paper's projected Gauss-Seidel (7.1.1)
// with each contact's three rows (normal, t1, t2) updated together and projected onto its cone
// (system/cone_problem.hpp) instead of clamped row by row (Jean & Moreau 1992; Jean 1999, "The
// non-smooth contact dynamics method"; the NSGS of Acary, Brémond & Huber 2018, Algorithm 1).
//
// A sweep visits the rows in order. A row no contact owns takes the step of 7.1.1,
//   lambda_k ← clamp((b_k − Σ_{i≠k} A_ki lambda_i) / A_kk, cmin_k, cmax_k);
// a contact's rows take the projected step of its local problem u = W_αα r + p (p: the rest of
// w, held fixed during the step), repeated up to `local` times or until r stops moving:
//   r ← P_K(r − rho_α û(u)),   rho_α = 1 / λmax(W_αα),
// with û = u + mu ‖u_t‖ e_n (Coulomb, De Saxcé's term taken at the current u, so updated per
// contact and per local step) or û = u (CCP). For CCP this is block-coordinate projected gradient
// descent on ½ λᵀAλ − bᵀλ over the cones (each step a descent step of its block: rho_α ≤
// 1/λmax), which converges for a symmetric positive semidefinite A; for Coulomb's law NSGS is the
// field's reference method without a convergence proof. On a problem without cones it is PGS.
#pragma once

#include <memory>

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// NSGS from the guess in lambda until a tolerance or options.max_iterations sweeps; the local
/// steps per contact are options.methods.nsgs.local. No islands, no CFM: solve() adds the CFM.
SolverSummary solve_nsgs(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options);

/// NSGS's sweep as a step of another method (pgs-nesterov on the relaxation's cones), set up
/// once for a problem (each contact's W_αα and rho_α, what a sweep visits in row order). Keeps a
/// reference to `problem`: keep it alive.
class NsgsSweep {
 public:
  explicit NsgsSweep(const BoxedProblem& problem);
  ~NsgsSweep();
  NsgsSweep(const NsgsSweep&) = delete;
  NsgsSweep& operator=(const NsgsSweep&) = delete;
  /// One sweep over lambda in place, each contact's local step taken at most `local` times;
  /// returns the largest change of an entry (a NaN stays).
  double operator()(VecX& lambda, int local) const;

 private:
  struct Setup;
  const BoxedProblem& problem_;
  std::unique_ptr<Setup> setup_;
};

}  // namespace cbps
