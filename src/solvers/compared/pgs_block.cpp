// Block projected Gauss-Seidel: contact manifolds solved as blocks by Lemke's method.
#include "cbps/solvers/compared/pgs_block.hpp"

#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "../sweep.hpp"
#include "cbps/solvers/exact/lemke.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/paper/pgs.hpp"

namespace cbps {

using detail::relax;
using detail::row_target;

double block_pgs_sweep(const BoxedProblem& problem,
                       VecX& lambda,
                       double relaxation,
                       double regularization,
                       int* fallbacks) {
  const SpMat& A = detail::rows_of(problem);  // column k holds row k of the problem's A
  const VecX& b = problem.b;
  const VecX& cmin = problem.cmin;
  const VecX& cmax = problem.cmax;
  const std::vector<int>& blocks = *problem.blocks;
  const Eigen::Index c = A.outerSize();
  double delta = 0.0;
  double target = 0.0;
  const auto update = [&](Eigen::Index k, double next) {
    const double change = std::abs(next - lambda(k));
    max_keep_nan(delta, change);
    lambda(k) = next;
  };
  MatX M;
  VecX q;
  for (Eigen::Index first = 0; first < c;) {
    const int id = blocks[static_cast<std::size_t>(first)];
    Eigen::Index end = first + 1;
    while (id >= 0 && end < c && blocks[static_cast<std::size_t>(end)] == id) ++end;
    const Eigen::Index size = end - first;
    if (size == 1) {  // a row of its own: 7.1.1
      if (row_target(A, b, lambda, first, target))
        update(first, clamp(relax(lambda(first), target, relaxation), cmin(first), cmax(first)));
      first = end;
      continue;
    }
    // M = A_BB, q = A_BR lambda_R − b_B; column k of A (rows_of) is row k of the problem's A.
    M.setZero(size, size);
    q = -b.segment(first, size);
    for (Eigen::Index k = first; k < end; ++k) {
      for (SpMat::InnerIterator it(A, k); it; ++it) {
        if (it.row() >= first && it.row() < end) {
          M(k - first, it.row() - first) = it.value();  // M_ki = A_ki
        } else {
          q(k - first) += it.value() * lambda(it.row());
        }
      }
    }
    if (!M.allFinite() || !q.allFinite()) {
      // Non-finite data (NaN or inf in A or b): the block's λ become NaN, so that the sweep
      // reports it (NonFinite) where Lemke would refuse the block.
      for (Eigen::Index k = first; k < end; ++k)
        update(k, std::numeric_limits<double>::quiet_NaN());
      first = end;
      continue;
    }
    // A_BB of a resting face has rank 6 of 12: Lemke's pivots on it break down numerically
    // (answers off by 0.5 of the scale). With delta I added it is positive definite and every
    // block solves; delta is a constraint-force-mixing term and biases lambda by O(delta),
    // which the residual of the whole system (reported) shows.
    M.diagonal().array() += regularization * M.diagonal().maxCoeff();
    const LcpResult z =
        solve_boxed_lemke(M, q, cmin.segment(first, size), cmax.segment(first, size));
    if (z.solved()) {
      for (Eigen::Index k = first; k < end; ++k)
        update(k, clamp(relax(lambda(k), z.z(k - first), relaxation), cmin(k), cmax(k)));
    } else {
      if (fallbacks != nullptr) ++*fallbacks;
      for (Eigen::Index k = first; k < end; ++k) {
        if (row_target(A, b, lambda, k, target))
          update(k, clamp(relax(lambda(k), target, relaxation), cmin(k), cmax(k)));
      }
    }
    first = end;
  }
  return delta;
}

SolverSummary solve_block_pgs(const BoxedProblem& problem,
                              VecX& lambda,
                              const SolverOptions& options) {
  if (problem.blocks == nullptr || problem.blocks->empty())
    return solve_pgs(problem, lambda, options);
  if (problem.blocks->size() != static_cast<std::size_t>(problem.rows()))
    throw std::invalid_argument("solve_block_pgs: one block id per row expected");
  int fallbacks = 0;
  SolverSummary s = detail::iterate_sweeps(problem, lambda, options, [&](VecX& l) {
    return block_pgs_sweep(
        problem, l, options.relaxation, options.block_regularization, &fallbacks);
  });
  if (options.describe) {
    std::ostringstream note;
    note << ", blocks regularised by " << options.block_regularization << " max A_jj";
    s.message.append(note.str());
  }
  if (fallbacks > 0 && options.describe) {
    s.message.append(", ");
    s.message.append(std::to_string(fallbacks));
    s.message.append(" blocks swept row by row (Lemke failed)");
  }
  return s;
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

extern const MethodEntry kBlockPgsEntry;
constexpr MethodEntry kBlockPgsEntry{
    .method = Method::BlockPgs,
    .name = "block-pgs",
    .sweeps_alone = true,
    .solve = solve_block_pgs,
    .what = "PGS with each contact manifold solved whole",
};

}  // namespace cbps
