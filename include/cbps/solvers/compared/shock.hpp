// Shock propagation order for stacks: projected Gauss-Seidel (7.1.1) that visits the rows level
// by level from the ground up, the levels taken from the contact graph of the bodies.
//
// Sources. Guendelman, Bridson & Fedkiw, "Nonconvex rigid bodies with stacking", ACM Trans.
// Graph. 22(3) (SIGGRAPH 2003), §7: a contact graph whose nodes are the bodies, levels by
// breadth-first search from the static bodies, contacts processed level by level from the
// ground up, and a final "shock propagation" pass in which each level, once processed, is given
// infinite mass so that the bodies above it cannot push it. Erleben, "Stable, robust and
// versatile multibody dynamics animation", PhD thesis, University of Copenhagen (2005), the
// chapter on shock propagation: the same layers, and the observation that the frozen pass is a
// one-way (upward) propagation. DART's ShockPropagationSolver (dartsim/dart, math/lcp/other)
// runs the same idea on a boxed LCP as a block Gauss-Seidel over blocks in a given layer order,
// each block solved exactly, without freezing.
//
// What is implemented here, on the boxed problem (A, b, cmin, cmax) with A = J Minv Jᵀ:
//   bodies  the 6-column blocks of J (body i: columns 6i … 6i+5); a row touches the bodies whose
//           block in its j_c is nonzero. Static bodies have no columns (5.3): a row touching
//           one body rests that body on the world.
//   layers  a body touched by a row with one body is in layer 0; breadth-first search over the
//           rows touching two bodies gives every body reached from there its distance to the
//           world (layer 0, 1, 2, …: the bottom box of a stack is 0, the next 1, …). Bodies
//           not reached (a group touching the world nowhere, e.g. falling) are layered after:
//           each such connected group, in order of its lowest body, by breadth-first search
//           from its lowest body, starting one past the last layer used.
//   levels  a row's level is the HIGHER layer of its bodies (its one body's for a world row):
//           a row belongs to the level of the body it holds up. That is Guendelman et al.'s
//           assignment (a contact is processed with the higher of its two objects' levels, the
//           ground's contacts first), and the one under which freezing the layers below a
//           level leaves every row of that level one free body. Rows acting on no body are
//           level 0.
//   order   every sweep visits the levels 0, 1, 2, … (bottom-up, the shock order), each
//           level's rows in their natural order, each row by 7.1.1 with relaxation
//           options.relaxation (PSOR), each new lambda used at once. With
//           ShockSettings::level_sweeps = s > 1 each level is swept s times before the next
//           (a block Gauss-Seidel with the levels as blocks, each block solved approximately by
//           s PGS sweeps, where DART solves its blocks exactly). ShockSettings::top_down visits
//           the levels from the highest down instead (not in the sources, for comparison).
// Every update is an exact minimisation of ½ λᵀAλ − bᵀλ along one row over [cmin_k, cmax_k]
// (7.1.1), every row is visited in each iteration: a cyclic coordinate descent, so it converges
// to a solution of the boxed LCP as PGS does (Luo & Tseng, "On the convergence of the coordinate
// descent method for convex differentiable minimization", J. Optim. Theory Appl. 72(1), 1992).
// Only the order differs from plain PGS. The sources' frozen pass is not done: it solves each
// level against a lower level made immovable and so does not give the boxed LCP's lambda.
#pragma once

#include <vector>

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// The layers of the bodies and the levels of the rows, from J's pattern.
struct ContactLayers {
  /// n bodies (J.cols() / 6): each body's layer, 0 for a body resting on the world; −1 for a
  /// body no row touches.
  std::vector<int> layer;
  /// Layers 0 … grounded − 1 are reached from the world; layers from `grounded` on belong to
  /// groups of bodies that touch the world nowhere.
  int grounded = 0;
  std::vector<int> level;  ///< c rows: the higher layer of the row's bodies (0: no body)
  int levels = 0;          ///< how many levels (1 + the highest level; 0 for no rows)
  /// The rows level by level (level 0 first), natural order within a level: one sweep's order.
  std::vector<int> order;
  /// order[start[l] … start[l + 1] − 1] are the rows of level l (levels + 1 entries).
  std::vector<int> start;
};

/// The layers and levels of J (c×6n, row-major, 6-column body blocks) as described above.
/// std::invalid_argument when J's columns are not a multiple of 6.
ContactLayers contact_layers(const SpMatRow& J);

/// Shock-ordered PGS from the guess in lambda (warm start). One iteration is level_sweeps
/// sweeps of 7.1.1 over the rows (each level's rows level_sweeps times), i.e. level_sweeps
/// products with A's rows; 1 by default, the cost of a PGS sweep. options.order is not used
/// (the levels fix the order). Needs problem.J (for the layers; Minv is not read):
/// std::invalid_argument without it, as the matrix-free sweep. The message reports the number
/// of levels and of layers reached from the world.
SolverSummary solve_shock(const BoxedProblem& problem,
                          VecX& lambda,
                          const SolverOptions& options,
                          const ShockSettings& settings = {});

}  // namespace cbps
