// Independent blocks ("islands") of A: rows that share no body never meet in A, so the boxed
// problem splits into smaller ones solved apart (each to its own tolerance).
#pragma once

#include <functional>
#include <vector>

#include "cbps/system/boxed_problem.hpp"

namespace cbps {

/// The islands of A: connected components of its graph (rows i, k joined when A_ik ≠ 0 or
/// A_ki ≠ 0), each a sorted list of rows, in order of their first row.
std::vector<std::vector<int>> find_islands(const SpMat& A);
/// The islands of the problem's A, also when A was left out (BoxedProblem::A_formed): then rows
/// join when they act on one body whose block of Minv is not zero.
std::vector<std::vector<int>> find_islands(const BoxedProblem& problem);

/// The rows J(idx, :) of J, in the order of idx.
SpMatRow select_rows(const SpMatRow& J, const std::vector<int>& idx);

/// The principal submatrix A(idx, idx) of A, idx sorted ascending. `local` is
/// scratch of size A.rows() that holds −1 everywhere on entry and on exit.
SpMat principal_submatrix(const SpMat& A, const std::vector<int>& idx, std::vector<int>& local);

/// The entries v(idx), in the order of idx.
VecX gather_rows(const VecX& v, const std::vector<int>& idx);

/// A solver for one island's sub-problem, lambda_I in and out.
using IslandSolve = std::function<void(const BoxedProblem& island, VecX& lambda_I)>;

/// Calls solve_island on each island in turn with its sub-problem (the whole problem as it is
/// when one island covers every row, so nothing is copied) and writes lambda_I back. The
/// sub-problem carries its rows' block ids and A_rows (the sweeps' rows of a non-symmetric A)
/// when the problem has them. It carries J and Minv only when the problem's A was left out
/// (J_I, the island's rows of J, with the problem's Minv and cfm, its A empty); an island of a
/// problem with A formed gets A(I, I) alone.
void for_each_island(const std::vector<std::vector<int>>& islands,
                     const BoxedProblem& problem,
                     VecX& lambda,
                     const IslandSolve& solve_island);

}  // namespace cbps
