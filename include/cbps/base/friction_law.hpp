// The friction law of a contact (paper 5.4; docs/cones.md), one value from the scene to the
// solver, and each law's per-contact pieces. A contact owns three rows, its normal n and two
// friction rows t1, t2 right after it (FCLIB's order), r = (r_n, r_t1, r_t2) their lambda (N)
// and u = (w_n, w_t1, w_t2) their rows of w = A lambda − b (6.2, m/s²). Four laws:
//
//   PaperBox     |r_tk| ≤ mu m |g·n|        the paper's box (5.4): fixed bounds in cmin, cmax,
//                                           m the pair's mass over its points
//                                           (paper_friction_bound)
//   CoulombBox   |r_tk| ≤ mu max(0, r_n)    Coulomb's box (ODE, Bullet, Box2D): the bounds follow
//                                           the normal's lambda (coulomb_bound)
//   CoulombCone  K*_mu ∋ û ⊥ r ∈ K_mu,       Coulomb's law with De Saxcé's modified velocity
//                û = u + mu ‖u_t‖ e_n        (De Saxcé & Feng 1991; FCLIB's and Siconos' law)
//   Relaxation   K*_mu ∋ u ⊥ r ∈ K_mu        the convex relaxation (the cone complementarity
//                                           problem of Anitescu 2006, MuJoCo's and Chrono's)
//
// with Coulomb's cone K_mu = { r : ‖r_t‖ ≤ mu r_n } (N) and its dual K*_mu = { u : mu ‖u_t‖ ≤ u_n }
// (m/s²). The relaxation is the optimality condition of the QP ½ λᵀAλ − bᵀλ over the cones; it
// lets a sliding contact separate (u_n = mu ‖u_t‖ > 0). Each cone law's residual is its natural
// map r − P_K(r − û) (Acary, Brémond & Huber 2018, eq. 2.21), zero exactly at a solution.
#pragma once

#include <algorithm>
#include <string_view>

#include "cbps/base/types.hpp"

namespace cbps {

/// The friction law of a contact (above). A scene's `friction` key names its box or cone
/// (paper, coulomb, cone), its `cone` key which cone (coulomb, ccp).
enum class FrictionLaw { PaperBox, CoulombBox, CoulombCone, Relaxation };

/// Coulomb's cone, under either law: its three rows live in K_mu, no box on the friction rows.
inline bool is_cone(FrictionLaw law) {
  return law == FrictionLaw::CoulombCone || law == FrictionLaw::Relaxation;
}
/// The scene's friction word: "paper", "coulomb" or "cone" (either cone law).
std::string_view friction_name(FrictionLaw law);
/// A cone's law word: "coulomb" (CoulombCone) or "ccp" (Relaxation); "" for a box.
std::string_view cone_law_name(FrictionLaw law);
/// The law in one name, as outputs report it: "paper", "coulomb" (the boxes), "cone coulomb",
/// "cone ccp".
std::string_view law_name(FrictionLaw law);
/// "coulomb" → CoulombCone, "ccp" → Relaxation; false (law untouched) for anything else.
bool cone_law_from_string(std::string_view name, FrictionLaw& law);

/// Coulomb's box (CoulombBox): each friction row's bound mu max(0, lambda_n), N, for lambda_n
/// its contact's normal lambda (N); the row lives in [−bound, bound].
inline double coulomb_bound(double mu, double lambda_n) { return mu * std::max(0.0, lambda_n); }

/// r ← P_K(r), the Euclidean projection onto K_mu: r itself inside, 0 inside the polar cone
/// (mu ‖r_t‖ ≤ −r_n), else the nearest point of the cone's surface. r = (r_n, r_t1, r_t2).
void project_onto_cone(double mu, Vec3& r);

/// The Jacobian of P_K at x (3×3, dimensionless), with the case split of project_onto_cone: I
/// inside K, 0 inside the polar cone, else the derivative of the surface's nearest point (with
/// d = x_t/‖x_t‖, a = (x_n + mu ‖x_t‖)/(1 + mu²)):
///   ∂P/∂x = [1, mu dᵀ; mu d, mu² d dᵀ]/(1 + mu²) + [0, 0; 0, mu a (I − d dᵀ)/‖x_t‖].
/// Where P_K is not differentiable (the boundaries between the cases; mu = 0's ray, where P_K(x)
/// = (max(x_n, 0), 0, 0)) it is one element of Clarke's generalized Jacobian, the one a
/// semismooth Newton method may use (Hayashi, Yamashita & Fukushima, SIAM J. Optim. 15(2) 2005).
Mat3 cone_projection_jacobian(double mu, const Vec3& x);

/// The velocity a cone law pairs with r: û = u + mu ‖u_t‖ e_n (CoulombCone: De Saxcé's term),
/// u (Relaxation).
Vec3 law_velocity(const Vec3& u, double mu, FrictionLaw law);
/// ∂û/∂u: I (Relaxation); I + mu e_n (0, u_tᵀ/‖u_t‖) (CoulombCone; I where u_t = 0).
Mat3 law_velocity_jacobian(const Vec3& u, double mu, FrictionLaw law);

/// The natural map of one contact under a cone law, r − P_K(r − û), N (u in the units of w).
Vec3 cone_natural_map(const Vec3& r, const Vec3& u, double mu, FrictionLaw law);

}  // namespace cbps
