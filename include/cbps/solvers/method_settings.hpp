// The parameters of the methods that have their own, one struct a method, gathered in
// MethodSettings so that SolverOptions (solver.hpp), a scene's SolverSettings and the
// `--solver NAME:key=value` grammar (studies/solver_spec.hpp) carry them alike. Each default is
// its source's, cited beside it; each method's header states its iteration.
#pragma once

namespace cbps {

/// pgs-nesterov (pgs_nesterov.hpp).
struct PgsNesterovSettings {
  /// Adaptive restart by the gradient test (O'Donoghue & Candès 2015, Section 3.2); false: plain
  /// Nesterov momentum on the sweeps, never reset (for comparison).
  bool restart = true;
};

/// apgd (apgd.hpp), defaults from Mazhar et al. (2015), Algorithm 1.
struct ApgdSettings {
  double grow = 2.0;    ///< backtracking: L ← grow · L while the step overshoots (paper: 2)
  double shrink = 0.9;  ///< after each accepted step L ← shrink · L (paper: 0.9)
  bool restart = true;  ///< the paper's restart when gᵀ(λ_{k+1} − λ_k) > 0; false: never
  /// Backtracking trials per iteration at most (not in the paper: a guard against round-off);
  /// 2^60 times L is far past any A's largest eigenvalue from the ‖A‖∞ start.
  int max_backtracks = 60;
};

/// nncg (nncg.hpp).
struct NncgSettings {
  /// Restart (beta = 0) when the Fletcher–Reeves ratio beta_k exceeds this: the sweep's change
  /// grew, so the old direction no longer helps. 1 in Silcowitz-Hansen, Niebe and Erleben (2010).
  double restart_beta = 1.0;
};

/// pgs-sm (pgs_sm.hpp). Silcowitz, Niebe and Erleben run a few PGS sweeps before each
/// subspace phase and a bounded number of CG iterations in it; the paper's own numbers could not
/// be read here, so these defaults were measured on the chain (20 links), the 10-box stack and
/// the base-6 pyramid (iterations to 1e-10 relative, pgs_sweeps / cg_iterations: 5/100: 25,
/// 9,244, not reached; 5/200: 25, 5,694, not reached in 200,000; 10/200: 30, 5,836; 5/400: 25,
/// 4,634, 152,186; at 1e-6 5/200 was best on the stack, 910).
struct PgsSmSettings {
  int pgs_sweeps = 5;       ///< PGS sweeps (7.1.1) per PGS phase, ≥ 1
  int cg_iterations = 200;  ///< CG iterations per subspace phase, ≥ 1
  double cg_tolerance = 1e-10;  ///< stop CG at ‖r_F‖₂ ≤ this · ‖r_F‖₂ at its start (relative)
};

/// admm (admm.hpp).
struct AdmmSettings {
  /// rho at the start, as a multiple of the mean diagonal of A (rho is in A's unit, kg⁻¹, since
  /// it is added to A's diagonal). Boyd et al. give no default (it is problem-dependent, §3.4.1);
  /// the mean A_kk is the row's own stiffness, and residual balancing corrects a poor start.
  double rho = 1.0;
  /// Over-relaxation alpha (Boyd et al. §3.4.3): the z- and u-updates use
  /// alpha lambda_x + (1 − alpha) z_old in place of lambda_x; 1 = plain ADMM, 1.5–1.8 reported
  /// to speed it up, 1.6 the value quoted there. 0 < alpha < 2.
  double alpha = 1.6;
  /// Residual balancing (Boyd et al. §3.4.1): rho ← tau rho when ‖r‖₂ > mu ‖s‖₂,
  /// rho ← rho / tau when ‖s‖₂ > mu ‖r‖₂, s = rho (z − z_old); mu = 10, tau = 2 are the values
  /// given there. The primal residual is taken at the relaxed point, r = lambda_r − z (the step
  /// of u), as OSQP does with its relaxed iterate (Stellato et al., "OSQP: an operator splitting
  /// solver for quadratic programs", Math. Program. Comput. 12, 2020), not at lambda_x: with
  /// alpha ≠ 1 a free row has lambda_x − z = (1 − alpha)(lambda_x − z_old), which pins
  /// ‖r‖ / ‖s‖ at (alpha − 1) / (alpha rho) and so pins rho (measured on the 20-link chain: rho
  /// stuck at 2.4 kg⁻¹, 792 iterations to 1e-10 relative, against 17 with alpha = 1). Each
  /// change of rho costs one numeric refactorization.
  bool adapt_rho = true;
  double mu = 10.0;
  double tau = 2.0;
  /// The smallest rho balancing may reach, a multiple of the mean diagonal of A. Where no bound
  /// is active ADMM is the proximal point method on A and balancing lowers rho every iteration
  /// (measured on the 20-link chain: to 3e-11 of the mean diagonal); on a singular A (a stack's
  /// four contacts per face) A + rho E then becomes as ill-conditioned as 1 / rho. 1e-8 is a
  /// choice (not from Boyd et al.): it keeps about eight digits in each solve.
  double rho_min = 1e-8;
};

/// shock (shock.hpp).
struct ShockSettings {
  /// PGS sweeps (7.1.1) over each level's rows before the next level, ≥ 1. 1: every row once
  /// an iteration, as Guendelman, Bridson & Fedkiw (SIGGRAPH 2003, §7) visit each level once a
  /// pass; s > 1 solves each level more closely before moving up (a block Gauss-Seidel with the
  /// levels as blocks, as DART's ShockPropagationSolver, which solves each block exactly).
  int level_sweeps = 1;
  /// false: the levels from the ground up, the sources' shock order. true: from the top down
  /// (not in the sources; for comparison: a Gauss-Seidel sweep carries a load down a column of
  /// boxes in one top-down sweep, one level a sweep bottom-up).
  bool top_down = false;
};

/// Every method's own parameters.
/// NSGS on friction cones (cone/nsgs.hpp): local projected steps per contact and sweep. One (the
/// step of 7.1.1 with the clamp replaced by the cone's projection) by default: more solve each
/// contact's local problem more closely per sweep at more cost a sweep (docs/cones.md).
struct NsgsSettings {
  int local = 1;  ///< at most this many projected steps per contact, ≥ 1
};

struct MethodSettings {
  PgsNesterovSettings pgs_nesterov;
  ApgdSettings apgd;
  NncgSettings nncg;
  PgsSmSettings pgs_sm;
  AdmmSettings admm;
  ShockSettings shock;
  NsgsSettings nsgs;
};

}  // namespace cbps
