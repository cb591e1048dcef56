// The contacts of a problem and their friction law (base/friction_law.hpp: the laws, the cone
// K_mu, its dual, De Saxcé's term and each contact's natural map), beside the box of 6.2: the same
// A, b and w = A lambda − b, but each contact's three rows (normal, t1, t2) are one contact. Under
// a cone law they live in K_mu instead of three boxes; FCLIB's u = W r + q is w = A lambda − b
// with W = A, q = −b, r = lambda. The residual of a cone law is its natural map r − P_K(r − û),
// as the box's is (6.2).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "cbps/base/friction_law.hpp"
#include "cbps/base/types.hpp"

namespace cbps {

/// The contacts of a problem and their law: contact i owns the rows normal[i] (its normal),
/// normal[i] + 1 and normal[i] + 2 (its friction rows t1, t2; FCLIB's order), with coefficient
/// mu[i] ≥ 0; every contact follows `law`. Under a cone law (is_cone) those rows' cmin and cmax
/// are not used (a problem keeps there the bounds each row has alone: [0, ∞) for a normal,
/// (−∞, ∞) for a tangent); under Coulomb's box the friction rows' bounds are set at lambda
/// (coulomb_bound); under the paper's box they are the rows' own cmin, cmax.
struct FrictionContacts {
  std::vector<int> normal;
  VecX mu;
  FrictionLaw law = FrictionLaw::CoulombCone;
  long contacts() const { return static_cast<long>(normal.size()); }
  bool empty() const { return normal.empty(); }
  /// c flags, true for every row some contact owns.
  std::vector<char> rows_in_cones(Eigen::Index rows) const;
};

/// The contacts' mu as text: "0.5" when every contact has it, else "0.3 to 0.8"; "none" for no
/// contacts.
std::string mu_text(const FrictionContacts& contacts);

/// What is wrong with `cones` as the contacts of a problem of `rows` rows ("contact 2: normal
/// row 7 is not after the rows of contact 1 (6 to 8)"), empty when nothing is: each normal row k
/// with k + 2 < rows and after the rows of the contact before it, each mu finite and ≥ 0.
std::string cone_contacts_error(const FrictionContacts& cones, long rows);

/// x ← its Euclidean projection onto the problem's set: each contact's three rows onto its cone
/// (project_onto_cone), every other row clamped to [cmin, cmax]; with no cones (null), the box
/// of 6.2. The projection of the methods that step and project (apgd, admm).
void project_onto_set(const VecX& cmin, const VecX& cmax, const FrictionContacts* cones, VecX& x);

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
ConeMeasures cone_measures(const FrictionContacts& cones,
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
                            const FrictionContacts& cones);

}  // namespace cbps
