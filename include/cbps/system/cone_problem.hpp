// Coulomb's friction cone beside the paper's box (5.4): the same A, b and w = A lambda − b of
// 6.2, but each contact's three rows (normal, t1, t2) live in a cone instead of three boxes:
//
//   K_mu = { r = (r_n, r_t1, r_t2) : ‖r_t‖ ≤ mu r_n }            (Coulomb's cone, N)
//   K*_mu = { u : mu ‖u_t‖ ≤ u_n }                                 (its dual, m/s²)
//
// and the contact's law is one of two (ConeLaw):
//   Coulomb  û = u + mu ‖u_t‖ e_n,  K*_mu ∋ û ⊥ r ∈ K_mu            (De Saxcé & Feng 1991)
//   Ccp      K*_mu ∋ u ⊥ r ∈ K_mu                                     (Anitescu 2006)
// with u = (w_n, w_t1, w_t2) the contact's rows of w. Coulomb's is the law of FCLIB and Siconos
// (FCLIB's u = W r + q is w = A lambda − b with W = A, q = −b, r = lambda). The convex relaxation
// (CCP, the cone complementarity problem MuJoCo and Chrono solve) is the optimality condition of
// the QP ½ λᵀAλ − bᵀλ over the cones; it lets a sliding contact separate (u_n = mu ‖u_t‖ > 0).
//
// Every form of the residual is the natural map of the law, as for the box (6.2):
//   r − P_K(r − û)   (zero exactly at a solution; Acary, Brémond & Huber 2018, eq. 2.21),
// with P_K the Euclidean projection onto K_mu.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "cbps/base/types.hpp"

namespace cbps {

/// Which cone law a problem's contacts follow.
enum class ConeLaw {
  Coulomb,  ///< Coulomb's law with De Saxcé's modified velocity (FCLIB's, the default)
  Ccp       ///< the convex relaxation (cone complementarity, Anitescu 2006)
};
std::string_view to_string(ConeLaw law);
/// "coulomb" or "ccp"; false (law untouched) for anything else.
bool cone_law_from_string(std::string_view name, ConeLaw& law);

/// The contacts of a problem whose rows live in Coulomb's cone: contact i owns the rows
/// normal[i] (its normal), normal[i] + 1 and normal[i] + 2 (its tangents t1, t2; FCLIB's order),
/// with coefficient mu[i] ≥ 0. Those rows' cmin and cmax are not used (a problem keeps there the
/// bounds each row has alone: [0, ∞) for a normal, (−∞, ∞) for a tangent).
struct ConeContacts {
  std::vector<int> normal;
  VecX mu;
  ConeLaw law = ConeLaw::Coulomb;
  long contacts() const { return static_cast<long>(normal.size()); }
  bool empty() const { return normal.empty(); }
  /// c flags, true for every row some contact owns.
  std::vector<char> rows_in_cones(Eigen::Index rows) const;
};

/// What is wrong with `cones` as the contacts of a problem of `rows` rows ("contact 2: normal
/// row 7 is not after the rows of contact 1 (6 to 8)"), empty when nothing is: each normal row k
/// with k + 2 < rows and after the rows of the contact before it, each mu finite and ≥ 0.
std::string cone_contacts_error(const ConeContacts& cones, long rows);

/// r ← P_K(r), the Euclidean projection onto K_mu: r itself inside, 0 inside the polar cone
/// (mu ‖r_t‖ ≤ −r_n), else the nearest point of the cone's surface. r = (r_n, r_t1, r_t2).
void project_onto_cone(double mu, Vec3& r);

/// x ← its Euclidean projection onto the problem's set: each contact's three rows onto its cone
/// (project_onto_cone), every other row clamped to [cmin, cmax]; with no cones (null), the box
/// of 6.2. The projection of the methods that step and project (apgd, admm).
void project_onto_set(const VecX& cmin, const VecX& cmax, const ConeContacts* cones, VecX& x);

/// The Jacobian of P_K at x (3×3, dimensionless), with the case split of project_onto_cone: I
/// inside K, 0 inside the polar cone, else the derivative of the surface's nearest point (with
/// d = x_t/‖x_t‖, a = (x_n + mu ‖x_t‖)/(1 + mu²)):
///   ∂P/∂x = [1, mu dᵀ; mu d, mu² d dᵀ]/(1 + mu²) + [0, 0; 0, mu a (I − d dᵀ)/‖x_t‖].
/// Where P_K is not differentiable (the boundaries between the cases; mu = 0's ray, where P_K(x)
/// = (max(x_n, 0), 0, 0)) it is one element of Clarke's generalized Jacobian, the one a
/// semismooth Newton method may use (Hayashi, Yamashita & Fukushima, SIAM J. Optim. 15(2) 2005).
Mat3 cone_projection_jacobian(double mu, const Vec3& x);

/// The velocity the law pairs with r: û = u + mu ‖u_t‖ e_n (Coulomb), u (Ccp).
Vec3 law_velocity(const Vec3& u, double mu, ConeLaw law);
/// ∂û/∂u: I (Ccp); I + mu e_n (0, u_tᵀ/‖u_t‖) (Coulomb; I where u_t = 0).
Mat3 law_velocity_jacobian(const Vec3& u, double mu, ConeLaw law);

/// The natural map of one contact, r − P_K(r − û), N (u in the units of w).
Vec3 cone_natural_map(const Vec3& r, const Vec3& u, double mu, ConeLaw law);

/// How far lambda is from the law, measured the ways the literature measures it; w = A lambda
/// − b (with a problem's constraint-force mixing in A). Every entry is a maximum over contacts.
struct ConeMeasures {
  double natural_map = 0.0;  ///< max ‖r − P_K(r − û)‖₂, N (the residual's cone part)
  double signorini = 0.0;    ///< max |r_n u_n|, N·m/s² (Coulomb: 0 at a solution; CCP: not)
  double violation = 0.0;    ///< max(‖r_t‖ − mu r_n, −r_n, 0), N (outside the cone)
  /// Maximum dissipation: max (r_t · u_t + mu r_n ‖u_t‖), N·m/s², 0 when every contact's friction
  /// opposes its sliding with all the cone allows (both laws give it at a solution)
  double dissipation = 0.0;
  /// FCLIB's MERIT_1 of lambda for Coulomb's law (whatever `law`): sqrt(Σ ‖natural map‖₂²) /
  /// (1 + sqrt(‖q‖₂)), q = −b restricted to the contacts' rows (fcmer.c's definition)
  double fclib_merit = 0.0;
  /// Siconos 4.4's relative error of lambda for Coulomb's law (fc3d_compute_error, with the
  /// ‖q‖₂ its solvers pass): sqrt(Σ ‖natural map‖₂²) / max(‖q‖₂, ‖r‖₂, ‖u‖₂), the contacts' rows
  /// (not divided where that maximum is below the machine epsilon). Like FCLIB's merit it mixes
  /// units (N with m/s²): shown so that users can compare with published numbers, never the
  /// verdict (system/unit_free.hpp).
  double siconos_error = 0.0;
};
ConeMeasures cone_measures(const ConeContacts& cones,
                           const VecX& lambda,
                           const VecX& w,
                           const VecX& b);

/// The natural-map residual of every row, N: for the rows no contact owns the box's
/// |lambda_k − clamp(lambda_k − w_k, cmin_k, cmax_k)| (6.2), for each contact ‖r − P_K(r − û)‖₂;
/// the largest, NaN when any term is NaN.
double natural_map_residual(const VecX& w,
                            const VecX& lambda,
                            const VecX& cmin,
                            const VecX& cmax,
                            const ConeContacts& cones);

}  // namespace cbps
