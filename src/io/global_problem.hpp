// A global frictional-contact problem with its velocities eliminated: the one path of the two
// files that hold one, FCLIB's /fclib_global (fclib_file.cpp) and Siconos' GlobalFrictionContact
// dump (siconos_fc3d.cpp):
//   M v = H r + G l + f,   Gᵀ v + b_G = 0,   u = Hᵀ v + w,   each contact's (u, r) in its cone.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cbps/io/stored_problem.hpp"

namespace cbps {

/// The largest block of a block-diagonal M whose inverse block_inverse forms entry by entry: a
/// rigid body's 6 rows (Siconos' and cbps's bodies), with room for coupled pairs.
inline constexpr long kInverseBlock = 12;

/// The inverse of a symmetric M made of independent blocks of at most kInverseBlock rows (the
/// components of its pattern), each inverted by a dense LLᵀ: M⁻¹ from M (reading a global
/// problem) and M from Minv (writing one). False, `inverse` untouched, for larger blocks, and
/// with `failure` saying which block where one is not positive definite.
bool block_inverse(const SpMat& M, SpMat& inverse, std::string& failure);

/// M itself where it stores both triangles (or only its diagonal); where it stores one strict
/// triangle and nothing in the other (LMGC90's dumps, e.g. Siconos' LMGC_GFC3D_CubeH8: its upper
/// triangle) the symmetric matrix that triangle is half of (FCLIB's M is symmetric, fclib.h),
/// with `note` saying so (empty otherwise).
SpMat symmetric_from_triangle(const SpMat& M, std::string& note);

/// A global problem as read, before v is eliminated. H is n × m (3 columns per contact), G
/// n × e (may have no columns).
struct GlobalProblem {
  SpMat M, H, G;
  VecX f, w, b_G;
  std::vector<double> mu;  ///< per contact, ≥ 0
};

/// The problem with v eliminated: J = [Hᵀ; Gᵀ] (r's rows, then l's), A = J M⁻¹ Jᵀ (6.2.9),
/// b = −[Hᵀ M⁻¹ f + w; Gᵀ M⁻¹ f + b_G] (M as symmetric_from_triangle reads it, its note in the
/// problem's `notes`), the contacts' rows in cones (law Coulomb), l's rows
/// free. With a block-diagonal M (rigid bodies) J and M⁻¹ are kept, as a `cbps matrices`
/// folder's; else A comes from a sparse LDLᵀ of M. `fail_M` is called (and must throw) with
/// what is wrong with M: not symmetric, not positive definite, or so near singular that A or b
/// overflows.
StoredProblem eliminate_velocities(const GlobalProblem& g,
                                   const std::function<void(const std::string& why)>& fail_M);

/// The rows of a problem with m contact rows (normal, t1, t2 per contact) in the cones of `mu`,
/// then e free rows: p's cmin, cmax and cones.
void in_cones(StoredProblem& p, long m, long e, const std::vector<double>& mu);

}  // namespace cbps
