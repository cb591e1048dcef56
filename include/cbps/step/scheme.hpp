// Step schemes beside the paper's (docs/schemes.md): what each changes in a substep's rows and
// system. Every scheme poses each substep h = dt/N as the paper's system (6.2.9) with dt = h;
// the step (simulation.cpp) runs the substeps, these say how the scheme's system differs:
//   tgs        Tonge's temporal Gauss-Seidel (Tonge, Benevolenski, Voroshilov, "Mass splitting
//              for jitter-free parallel rigid body simulation", SIGGRAPH 2012; PhysX's TGS):
//              the rows as the paper builds them (beta, push mode of the world), N substeps.
//   soft-step  Catto's soft step (Box2D v3; "Solver2D", box2d.org, 2024; "Soft Constraints",
//              GDC 2011): a soft push system, (A + diag(gamma)) lambda = b_push with the soft
//              push factor, moves the bodies; a rigid relax, A lambda = b without the push, gives
//              the velocity kept: 8.1's two systems with a soft position system.
//   xpbd       Macklin, Müller, Chentanez, "XPBD: position-based simulation of compliant
//              constrained dynamics" (MIG 2016) and Macklin et al., "Small steps in physics
//              simulation" (SCA 2019), in the linear form the matrix view poses: each substep
//              removes the whole violation (beta = 1), rows of compliance alpha add alpha/h² to
//              A's diagonal, lambda starts from 0, and the one system's v2 is kept (it is
//              (x_new − x)/h of the position update).
#pragma once

#include <vector>

#include "cbps/rows/row.hpp"
#include "cbps/scene/scene.hpp"
#include "cbps/system/system.hpp"

namespace cbps {

/// The substep h = dt/N of a world's scheme, s.
double substep_dt(const World& world);

/// The push form of a scheme's substep systems: the world's under paper and tgs, 8.1's two
/// systems under soft-step (push system, then relax), the one system under xpbd.
PushMode scheme_push(const World& world);

/// The row settings of a substep: dt = h; beta the world's under paper and tgs, 1 under
/// soft-step (scheme_rows then scales each push) and xpbd.
RowSettings substep_row_settings(const World& world);

/// Catto's soft constraint over a substep h for stiffness `hertz` and damping ratio `zeta`, with
/// omega = 2 pi hertz; for a row of effective mass m = 1/A_kk, spring k = m omega² and damper
/// c = 2 m zeta omega:
///   beta  = h k / (c + h k) = h omega / (2 zeta + h omega)      its push factor (5.2.3, 5.3)
///   gamma = 1 / (h (c + h k)) = A_kk / (h omega (2 zeta + h omega)),  kg⁻¹, its softness;
/// gamma_per_A_kk is gamma / A_kk. GS on (A + gamma) lambda = b is Box2D v3's soft update
/// (massScale = 1/(1 + gamma/A_kk), impulseScale = massScale gamma/A_kk).
struct SoftRow {
  double beta = 0.0;
  double gamma_per_A_kk = 0.0;
};
SoftRow soft_row(double hertz, double zeta, double h);

/// A scheme's changes to the rows of a substep (built with substep_row_settings): soft-step
/// scales each push term d/h of a contact at depth d ≥ 0 to min(beta_c d/h, max_push_speed)
/// and each distance row's −C/h to −beta_j C/h (soft_row of the contact and joint hertz);
/// other schemes leave the rows as built.
void scheme_rows(const World& world, std::vector<Row>& rows);

/// The softness a scheme adds to A's diagonal (System::softness), kg⁻¹ per row, from the
/// substep's rows and its A: soft-step gamma on contact rows at depth ≥ 0 and on distance rows
/// (friction rows and gaps stay rigid); xpbd compliance/h² on every row but friction; zero
/// otherwise (and then empty).
VecX scheme_softness(const World& world, const std::vector<Row>& rows, const System& sys);

/// Whether a world's scheme softens rows (so its step must form A).
bool scheme_softens(const World& world);

/// The contact stiffness a substep of h seconds uses, Hz: the scene's contact_hertz, at most a
/// quarter of the substep rate 1/h (Box2D v3's limit); summary.json reports it beside the asked.
double contact_hertz(const SchemeSettings& s, double h);

}  // namespace cbps
