// Red-black (multicolour) projected Gauss-Seidel: 7.1.1 with the rows visited colour by colour,
// the order a parallel engine computes. The rows are coloured greedily so that no two rows of
// one colour are coupled in A (A_ij ≠ 0); the rows of a colour then read only rows of other
// colours, so they can be updated at once (a Jacobi step inside a colour, Gauss-Seidel between
// colours). The colouring is the greedy multicolouring of Saad, "Iterative Methods for Sparse
// Linear Systems", 2nd ed., SIAM 2003, §3.3.3, with the multicolour SOR sweep of its §12.4;
// red-black is its two-colour case (a chain's tridiagonal A). Parallel rigid-body engines need
// such an order because the sequential PGS order cannot be kept in parallel (Tonge,
// Benevolenski, Voroshilov, "Mass splitting for jitter-free parallel rigid body simulation",
// ACM Trans. Graph. 31(4), 2012, who go to Jacobi with mass splitting instead).
#pragma once

#include <vector>

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// A colouring of A's rows: no two rows of one colour are coupled (A_ij ≠ 0, i ≠ j).
struct RowColouring {
  std::vector<int> colour;  ///< c colours, 0 … colours − 1, one per row
  int colours = 0;          ///< how many colours were used
  /// The rows colour by colour (colour 0 first), each colour's rows in natural order: the
  /// order of one red-black sweep.
  std::vector<int> order;
  /// order[start[g] … start[g + 1] − 1] are the rows of colour g (colours + 1 entries).
  std::vector<int> start;
};

/// Greedy colouring (Saad §3.3.3): rows k = 0 … c−1 in turn take the smallest
/// colour none of their already coloured neighbours (A_ik ≠ 0, i ≠ k) has. Uses at most
/// 1 + the largest number of neighbours of a row; 2 for a tridiagonal A (a chain's).
RowColouring colour_rows(const SpMat& A);

/// Red-black PGS from the guess in lambda: each iteration is one sweep of pgs_sweep (7.1.1, with
/// relaxation options.relaxation, PSOR) over the rows in colour order, i.e. one product with A's
/// rows, the cost of a PGS sweep. Run sequentially here; the rows of one colour could be
/// updated in parallel with the same result, bit for bit. options.order is not used (the
/// colouring fixes the order). The message reports the number of colours.
SolverSummary solve_rbgs(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options);

}  // namespace cbps
