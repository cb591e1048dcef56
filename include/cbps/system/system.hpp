// The whole system (paper 6.1) and the system equation A lambda = b (6.2).
//
// Notation (n movable bodies, c rows):
//   Symbol   Shape   Unit                       Equation  Member
//   J        c×6n    1 (linear), m (angular)    6.1       J
//   Minv     6n×6n   kg⁻¹, kg⁻¹ m⁻²            6.1.2     Minv
//   v1       6n      m/s, rad/s                 6.1.1     v1
//   fext     6n      N, N m                     6.1.3     fext
//   upsilon  c       m/s                        6.1.4     upsilon (the push in it or not: push)
//   cmin     c       N                          5.1       cmin
//   cmax     c       N                          5.1       cmax
//   A        c×c     kg⁻¹                       6.2.9     A
//   b        c       m/s²                       6.2.9     b
//   lambda   c       N                          6.2.1     (solver output)
//   v2       6n      m/s, rad/s                 12.3.1    compute_v2()
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cbps/rows/row.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/cone_problem.hpp"

namespace cbps {

struct System {
  double dt = 0.0;                  ///< time step, s
  std::vector<int> block_of_body;   ///< body index → column block (6 columns), -1 if static
  std::vector<int> body_of_block;   ///< column block → body index
  std::vector<std::string> labels;  ///< one per row
  std::vector<std::uint64_t> ids;   ///< one per row, for warm starting
  std::vector<RowKind> kind;        ///< one per row: distance, contact or friction (Row::kind)

  SpMatRow J;  ///< c×6n (6.1), row-major: row k is j_c of row k
  SpMat Minv;  ///< 6n×6n block diagonal (6.1.2)
  VecX v1;     ///< 6n, velocities at the start of the step (6.1.1)
  VecX fext;   ///< 6n, external forces and torques (6.1.3)
  /// c (6.1.4), the bias of A lambda = b: each row's velocity bias with its push term under
  /// PushMode::Original (5.2.3, 5.3), without it under PushMode::Improved (8.1's velocity system).
  VecX upsilon;
  VecX cmin;                           ///< c
  VecX cmax;                           ///< c
  SpMat A;                             ///< c×c, J Minv Jᵀ (6.2.9)
  VecX b;                              ///< c, upsilon/dt − J (v1/dt + Minv fext) (6.2.9)
  VecX upsilon_push;                   ///< c, each row's push term alone (Row::upsilon_push), m/s
  PushMode push = PushMode::Original;  ///< the push factor's form upsilon was made for (8, 8.1)
  std::vector<int> manifold;           ///< c, the row's contact manifold (4), else −1 (block PGS)
  /// Every contact with friction rows (a contact row and its two friction rows after it, 5.4),
  /// its mu and the law the rows carry (Row::mu, Row::law): empty at mu = 0 and without
  /// contacts.
  FrictionContacts contacts;
  /// c, kg⁻¹: what a step scheme adds to A's diagonal (docs/schemes.md), kept apart from A: the
  /// soft step's soft rows (Catto's gamma), XPBD's compliance over h². The system that carries
  /// the push solves (A + diag(softness)) lambda = b (push_problem). Empty: the paper's rigid rows.
  VecX softness;
  SpMat A_soft;  ///< A + diag(softness) (soften), empty without softness

  int rows() const { return static_cast<int>(J.rows()); }
  int blocks() const { return static_cast<int>(body_of_block.size()); }
  /// The boxed problem of 6.2 this system poses (with J, Minv and the manifold blocks), or the
  /// same with another right-hand side (the position system of 8.1). A view: the System and
  /// rhs must outlive it (never pass a temporary rhs).
  /// The velocity system's problem: with a scheme's softness when the push is in it (push
  /// Original), as soft_problem.
  BoxedProblem problem() const { return problem(b); }
  BoxedProblem problem(const VecX& rhs) const {
    return softness.size() > 0 && push == PushMode::Original ? soft_problem(rhs)
                                                             : rigid_problem(rhs);
  }
  /// The problem of the system that carries the push (8.1's position system, or the one system):
  /// (A + diag(softness)) lambda = rhs when a scheme set softness (soften), else A lambda = rhs.
  BoxedProblem push_problem(const VecX& rhs) const {
    return softness.size() > 0 ? soft_problem(rhs) : rigid_problem(rhs);
  }
  /// A lambda = rhs with A = J Minv Jᵀ, whatever the softness.
  BoxedProblem rigid_problem(const VecX& rhs) const {
    BoxedProblem p{A, rhs, cmin, cmax, &J, &Minv, &manifold, &kind};
    p.symmetric = true;  // A = J Minv Jᵀ (6.2.9)
    p.cones = cones();
    return p;
  }
  /// (A + diag(softness)) lambda = rhs: A_soft alone (no J and Minv: the methods that work
  /// through the factors would leave the softness out).
  BoxedProblem soft_problem(const VecX& rhs) const {
    BoxedProblem p{A_soft, rhs, cmin, cmax, nullptr, nullptr, &manifold, &kind};
    p.symmetric = true;  // A + a diagonal
    p.cones = cones();
    return p;
  }
  /// The contacts when their law is a cone (is_cone; docs/cones.md), else null: the problem's
  /// cones (BoxedProblem::cones).
  const FrictionContacts* cones() const {
    return is_cone(contacts.law) && !contacts.empty() ? &contacts : nullptr;
  }
  /// The contacts when their law is Coulomb's box, whose friction bounds ±mu lambda_n the solve
  /// sets (5.4); else none.
  CoulombRows coulomb() const {
    return {contacts.law == FrictionLaw::CoulombBox && !contacts.empty() ? &contacts : nullptr};
  }
};

/// The contacts of a system whose friction is a box (the paper's or Coulomb's, 5.4), posed in
/// Coulomb's cone under `law` (a cone law), each with the mu its rows were built with: the same
/// J, Minv, A and b, only the set lambda lives in changes (docs/cones.md). Throws InputError
/// naming the first contact row without its two friction rows (mu = 0 makes none).
FrictionContacts contacts_in_cones(const System& sys, FrictionLaw law);

/// Gives `sys` (A formed) a scheme's softness, kg⁻¹ per row (System::softness), and forms
/// A_soft = A + diag(softness). An all-zero softness is dropped (the rigid system).
void soften(System& sys, const VecX& softness);

/// Column blocks for the movable bodies only: static bodies get none (5.3).
void map_bodies(const std::vector<Body>& bodies, System& sys);

/// J (6.1): row k holds the two 6-blocks of row k's j_c in the columns of its bodies (nonzero
/// entries only). Fills J in place, reusing its storage.
void assemble_J(const std::vector<Row>& rows,
                const std::vector<int>& block_of_body,
                int blocks,
                SpMatRow& J);
SpMatRow assemble_J(const std::vector<Row>& rows,
                    const std::vector<int>& block_of_body,
                    int blocks);

/// Minv = blockdiag(m_i⁻¹ E₃, I_i⁻¹) (6.1.2), movable bodies only (nonzero entries only).
/// Fills Minv in place, reusing its storage.
void assemble_Minv(const std::vector<Body>& bodies,
                   const std::vector<int>& body_of_block,
                   SpMat& Minv);
SpMat assemble_Minv(const std::vector<Body>& bodies, const std::vector<int>& body_of_block);

/// v = [v_i; omega_i] stacked over movable bodies (6.1.1).
VecX stack_velocities(const std::vector<Body>& bodies, const std::vector<int>& body_of_block);

/// fext = [f_i + m_i g; tau_i] stacked over movable bodies (6.1.3); g in m/s².
VecX stack_forces(const std::vector<Body>& bodies,
                  const std::vector<int>& body_of_block,
                  const Vec3& gravity);

/// A = J Minv Jᵀ (6.2.9): c×c, symmetric positive semidefinite. Always exactly this: constraint-
/// force mixing is a solver setting (SolverOptions::cfm), never folded into A.
SpMat compute_A(const SpMatRow& J, const SpMat& Minv);

/// b = upsilon/dt − J (v1/dt + Minv fext) (6.2.9).
VecX compute_b(const VecX& upsilon,
               const SpMatRow& J,
               const VecX& v1,
               const SpMat& Minv,
               const VecX& fext,
               double dt);

/// v2 = v1 + dt Minv (Jᵀ lambda + fext) (12.3.1).
VecX compute_v2(const VecX& v1,
                const SpMat& Minv,
                const SpMatRow& J,
                const VecX& lambda,
                const VecX& fext,
                double dt);

/// v2 of a system (12.3.1).
VecX compute_v2(const System& sys, const VecX& lambda);

/// Builds the whole system of one step from the bodies and the rows (6.1, 6.2), into `sys`,
/// reusing the storage it already has (a simulation keeps one System across steps, so large
/// scenes do not fetch fresh memory from the kernel every step). `push` says whether the rows'
/// push terms go into upsilon (Original) or wait for the position system (Improved, 8.1).
/// `form_A`: false leaves A = J Minv Jᵀ out (sys.A empty) for a caller that works in body
/// space on J and Minv alone (the distributed generator; issue 32's "leave out what the solver
/// does not read").
void assemble_system(const std::vector<Body>& bodies,
                     const std::vector<Row>& rows,
                     const Vec3& gravity,
                     double dt,
                     PushMode push,
                     System& sys,
                     bool form_A = true);
System assemble_system(const std::vector<Body>& bodies,
                       const std::vector<Row>& rows,
                       const Vec3& gravity,
                       double dt,
                       PushMode push,
                       bool form_A = true);

}  // namespace cbps
