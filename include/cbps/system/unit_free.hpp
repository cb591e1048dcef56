// The unit-free residual of a problem (issue 51): what `solved` must not depend on.
//
// The natural map of 6.2, λ − clamp(λ − w, cmin, cmax), subtracts an acceleration (w, m/s²) from
// a force (λ, N), and cbps's scale max(1, ‖b‖∞, max |A_ij|) mixes accelerations with
// compliances (kg⁻¹): change the unit of force or of velocity and both the residual and the
// verdict change (Siconos' spheres-in-a-box, max |W_ij| 6.6e5 and ‖q‖∞ 0.02: an answer 3e-7 from
// the law called solved). Here each row's step turns w into a force first, as PGS's step does
// (7.1.1):
//   a row no contact owns   F_k = λ_k − clamp(λ_k − ρ_k w_k, cmin_k, cmax_k),  ρ_k = 1 / A_kk
//   a contact α (3 rows)    F_α = r_α − P_K(r_α − ρ_α û_α),  ρ_α = 1 / max_{k∈α} A_kk
// (û Coulomb's De Saxcé velocity or u, the law's; A with its constraint-force mixing), both in N
// and zero exactly at a solution (for every ρ > 0: the natural map's zeros do not depend on its
// step), and divides the largest by the problem's force scale
//   S = max(‖λ‖∞, max_k ρ_k |b_k|)   (N: the forces, and the forces b alone would call for),
//   relative = max(max_k |F_k|, max_α ‖F_α‖₂) / S.
// A change of the unit of force (λ → λ/s, A → s A, cmin, cmax → ·/s) divides every ρ, F and S
// by s; one of the unit of velocity (A → s A, b → s b) leaves ρ w, F and S as they were: the
// relative residual is the same number in any units (tests/system/test_unit_free.cpp). A row
// whose A_kk is not positive takes ρ = 1 / max_k A_kk (1 where A has no positive diagonal).
//
// This is the one verdict of cbps (docs/cones.md, "A residual that does not depend on units"):
// an answer is solved when it is finite and its relative unit-free residual is at most
// kSolvedTolerance. `cbps lcp`, `run --check`, `matrices`, the peers and Lemke's method judge by
// it, and `cbps profile` measures its costs in it. The paths no process holds whole (TAO, the
// exact path under MPI) form it from each rank's rows (unit_free_rows) and their maxima over the
// ranks (unit_free_of).
#pragma once

#include <algorithm>

#include "cbps/system/boxed_problem.hpp"

namespace cbps {

struct UnitFreeResidual {
  double residual = 0.0;  ///< max(max_k |F_k|, max_α ‖F_α‖₂), N
  double scale = 0.0;     ///< S, N
  /// residual / S; 0 when both are 0, ∞ when only S is; NaN when a term is NaN
  double relative = 0.0;
};

/// UnitFreeResidual from its two maxima (N): relative = residual / scale, 0 when both are 0, ∞
/// when only the scale is, NaN when the residual is.
UnitFreeResidual unit_free_of(double residual, double scale);

/// A row's step ρ_k (kg) from its diagonal entry A_kk (+ eps) and the largest of all rows':
/// 1 / A_kk, or 1 / largest where A_kk is not positive (1 where no row's is).
double unit_free_step(double diagonal, double largest_diagonal);

/// The unit-free residual of some rows of a boxed problem without cones, as a rank under MPI
/// holds them: w = (A + eps E) λ − b, b, cmin, cmax and `diagonal` (A_kk + eps) on those rows,
/// `largest_diagonal` over all rows. Its `residual` and `scale` are the two maxima over these
/// rows; unit_free_of(their maxima over every part) is unit_free_residual of the whole problem.
UnitFreeResidual unit_free_rows(const Eigen::Ref<const VecX>& w,
                                const Eigen::Ref<const VecX>& lambda,
                                const Eigen::Ref<const VecX>& b,
                                const Eigen::Ref<const VecX>& cmin,
                                const Eigen::Ref<const VecX>& cmax,
                                const Eigen::Ref<const VecX>& diagonal,
                                double largest_diagonal);

/// The relative residual above which an answer is not solved (of UnitFreeResidual::relative).
inline constexpr double kSolvedTolerance = 1e-9;

/// The unit-free residual of lambda for the problem of A + eps E (eps = cfm, kg⁻¹).
UnitFreeResidual unit_free_residual(const BoxedProblem& problem,
                                    const VecX& lambda,
                                    double cfm = 0.0);

/// The terms of the unit-free residual of lambda (of the problem's size), one per row: a row no
/// contact owns |F_k|, a contact's ‖F_α‖₂ on its normal row and 0 on its two friction rows (a
/// contact is one term); unit_free_residual is their largest over `scale`.
struct UnitFreeTerms {
  VecX term;           ///< c, N
  VecX w;              ///< (A + eps E) λ − b (6.2), c, in b's units
  VecX rho;            ///< each row's step ρ_k, kg (unit_free_steps)
  double scale = 0.0;  ///< S = max(‖λ‖∞, max_k ρ_k |b_k|), N
};
UnitFreeTerms unit_free_terms(const BoxedProblem& problem, const VecX& lambda, double cfm = 0.0);

/// Each row's step ρ_k (kg): 1 / A_kk (+ eps), a contact's rows 1 / max A_kk of its rows, 1 /
/// max_k A_kk where A_kk is not positive (1 where none is).
VecX unit_free_steps(const BoxedProblem& problem, double cfm = 0.0);

/// A unit-free target as a natural-map residual with unit step (6.2, or the cone law's), the
/// measure the exact paths stop by: since the map's norm grows with its step and shrinks over it
/// (‖F_ρ‖ ≤ max(1, ρ) ‖F_1‖), a residual of at most
///   relative · max(‖λ‖∞, max_k ρ_k |b_k|) / max(1, max_k ρ_k)   (N)
/// has a unit-free residual of at most `relative`.
/// The direct path reads its tolerance τ both ways on cbps's own problems, in SI units
/// (exact/direct.cpp, cone/cone_direct.cpp): it stops at min(τ, newtons(τ, λ)), where the
/// natural map is at most τ N and the unit-free residual at most τ (down to its rounding floor),
/// so that on problems of small forces its answer passes the verdict as well (Siconos'
/// spheres-in-a-box: forces near 1e-8 N). On a problem in its simulator's units (a Siconos or
/// FCLIB file: SolverOptions::tolerance_unit_free) a newton is no unit of that problem, and τ is
/// read as a unit-free residual alone (`read` on the boxed problem; on cones, cone_direct.cpp's
/// Aim), so that a change of the unit of force changes neither where it stops nor what it says.
struct UnitFreeTarget {
  double rho_b = 0.0;    ///< max_k ρ_k |b_k|, N
  double rho_max = 1.0;  ///< max_k ρ_k, kg
  double newtons(double relative, const VecX& lambda) const;
  /// min(tolerance, newtons(tolerance, lambda)), N: both readings of a tolerance.
  double both(double tolerance, const VecX& lambda) const {
    return std::min(tolerance, newtons(tolerance, lambda));
  }
  /// The residual (N) to stop at: newtons(tolerance, lambda) where `unit_free_only` (a problem
  /// in its simulator's units), both(tolerance, lambda) otherwise.
  double read(double tolerance, const VecX& lambda, bool unit_free_only) const {
    return unit_free_only ? newtons(tolerance, lambda) : both(tolerance, lambda);
  }
};
UnitFreeTarget unit_free_target(const BoxedProblem& problem, double cfm = 0.0);
/// The same from some rows of a boxed problem without cones (b and `diagonal`, A_kk + eps, on
/// those rows; `largest_diagonal` over all): the maxima over every part are the whole problem's.
UnitFreeTarget unit_free_target_rows(const Eigen::Ref<const VecX>& b,
                                     const Eigen::Ref<const VecX>& diagonal,
                                     double largest_diagonal);

/// The verdict: lambda finite and u.relative ≤ kSolvedTolerance (NaN is not solved).
bool is_solved(const UnitFreeResidual& u, const VecX& lambda);

}  // namespace cbps
