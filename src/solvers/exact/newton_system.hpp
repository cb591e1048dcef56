// The Newton matrices of the exact path (NewtonSystem, interior_point.hpp), factored by CHOLMOD
// in body space (M + Jᵀ D⁻¹ J) when J and Minv are known, in row space otherwise. Private to the
// library: direct.cpp and active_set.cpp use it.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "cbps/solvers/exact/interior_point.hpp"
#include "cbps/solvers/solver.hpp"

namespace cbps {

/// The exact paths' way around the null rows of A (no nonzero entry in column k, so none in row
/// k of a symmetric A: a row whose j_c acts on nothing), which CHOLMOD cannot factor: their
/// lambda_k follow from w_k = −b_k and the bounds alone (b_k > 0: cmax_k, b_k < 0: cmin_k, 0: the
/// box's point nearest 0), the other rows are solved by solve_rest (with J's rows of their
/// own), and the summary has the residual of the whole problem, NotConverged when a null row's
/// needed bound is infinite (no solution). Without null rows: solve_rest(problem, lambda).
SolverSummary solve_around_null_rows(
    const BoxedProblem& problem,
    VecX& lambda,
    const std::function<SolverSummary(const BoxedProblem&, VecX&)>& solve_rest);

/// M = Minv⁻¹ block by block, when the problem has J and Minv, Minv is block diagonal with
/// symmetric positive definite 6×6 blocks and A x = J Minv Jᵀ x + cfm x holds on factors_mismatch's
/// test vector (to kFactorsTolerance): what body space factors (M + Jᵀ D⁻¹ J); nullopt otherwise.
std::optional<std::vector<Mat6>> body_masses(const BoxedProblem& problem);

/// Body space when the problem has J and Minv, Minv is block diagonal with positive definite
/// 6×6 blocks and A x = J Minv Jᵀ x + cfm x holds on a test vector (to 1e-12 of |A| |x|); null
/// otherwise. With `memory`, a body space kept there for a J of the same pattern is taken (its
/// H pattern and CHOLMOD analysis reused, nothing factored yet) and a new one is kept there.
/// The returned system reads the problem's J and Minv: it serves while the problem lives.
std::shared_ptr<NewtonSystem> make_body_space(const BoxedProblem& problem,
                                              ExactMemory* memory = nullptr);
/// Body space where it can, row space otherwise.
std::shared_ptr<NewtonSystem> make_newton_system(const BoxedProblem& problem,
                                                 ExactMemory* memory = nullptr);

/// What both exact paths check first. Throws std::invalid_argument when A, b, cmin and cmax
/// differ in size. False, with s filled, when A or b has a non-finite entry or a bound is NaN
/// (NonFinite), or some row's box is empty, cmin > cmax (NotConverged, residual the largest
/// cmin − cmax, N, the message naming the row: clamp() would take cmax and call it solved);
/// the message starts with `who`. True otherwise.
bool check_input(const BoxedProblem& problem, const char* who, SolverSummary& s);

/// The active-set path of active_set.hpp on the whole problem at once from lambda as it is (no
/// PGS sweeps: rows at a bound start there): the exact path's crossover. With `newton`, its free
/// blocks (A + εI)(F, F) are solved by it with the other rows dropped, ε starting at eps_start ·
/// max A_kk (> 0); without, by CHOLMOD on A(F, F) from ε = 0 (exact in finitely many steps
/// where the free block is definite). Termination::Direct or NotConverged; counts in the
/// summary, and the residual of the λ returned (N).
struct FinishHints {
  /// Pivoting rounds allowed in all (each one solve with a free block); −1: no limit.
  long max_rounds = -1;
  /// max_abs_row_sum(A) when the caller has it (one pass over A saved), else −1.
  double row_sum = -1.0;
};
SolverSummary finish_active_set(const BoxedProblem& problem,
                                VecX& lambda,
                                const SolverOptions& options,
                                NewtonSystem* newton,
                                double eps_start,
                                const FinishHints& hints = {});

}  // namespace cbps
