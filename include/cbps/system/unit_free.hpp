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
#pragma once

#include "cbps/system/boxed_problem.hpp"

namespace cbps {

struct UnitFreeResidual {
  double residual = 0.0;  ///< max(max_k |F_k|, max_α ‖F_α‖₂), N
  double scale = 0.0;     ///< S, N
  /// residual / S; 0 when both are 0, ∞ when only S is; NaN when a term is NaN
  double relative = 0.0;
};

/// The unit-free residual of lambda for the problem of A + eps E (eps = cfm, kg⁻¹).
UnitFreeResidual unit_free_residual(const BoxedProblem& problem,
                                    const VecX& lambda,
                                    double cfm = 0.0);

}  // namespace cbps
