// Projected Gauss-Seidel (paper 7.1.1), PSOR, symmetric Gauss-Seidel and projected Jacobi over
// the explicit A.
#include "cbps/solvers/paper/pgs.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "../sweep.hpp"
#include "cbps/solvers/methods.hpp"

namespace cbps {

using detail::relax;
using detail::row_target;

namespace {

/// 7.1.1 over the rows row_at(0), row_at(1), …, row_at(count − 1).
template <class RowAt>
double sweep_rows(
    const BoxedProblem& p, VecX& lambda, double relaxation, Eigen::Index count, RowAt row_at) {
  const SpMat& A_rows = detail::rows_of(p);
  double delta = 0.0;
  double target = 0.0;
  for (Eigen::Index n = 0; n < count; ++n) {
    const Eigen::Index k = row_at(n);
    if (!row_target(A_rows, p.b, lambda, k, target)) continue;
    const double next =
        clamp(relax(lambda(k), target, relaxation), p.cmin(k), p.cmax(k));  // (7.1.1)
    const double change = std::abs(next - lambda(k));
    max_keep_nan(delta, change);
    lambda(k) = next;
  }
  return delta;
}

}  // namespace

double pgs_sweep(const BoxedProblem& problem, VecX& lambda, double relaxation) {
  return sweep_rows(
      problem, lambda, relaxation, problem.A.outerSize(), [](Eigen::Index n) { return n; });
}

double pgs_sweep(const BoxedProblem& problem,
                 VecX& lambda,
                 double relaxation,
                 const std::vector<int>& rows) {
  return sweep_rows(
      problem, lambda, relaxation, static_cast<Eigen::Index>(rows.size()), [&](Eigen::Index n) {
        return Eigen::Index(rows[std::size_t(n)]);
      });
}

void sweep_order(RowOrder order, int rows, std::mt19937_64& rng, std::vector<int>& out) {
  out.resize(static_cast<std::size_t>(rows));
  std::iota(out.begin(), out.end(), 0);
  if (order == RowOrder::Reverse) std::reverse(out.begin(), out.end());
  if (order == RowOrder::Random) std::shuffle(out.begin(), out.end(), rng);
}

void sweep_order(RowOrder order,
                 const std::vector<RowKind>& kinds,
                 std::mt19937_64& rng,
                 std::vector<int>& out) {
  out.clear();
  for (const RowKind kind : {RowKind::Distance, RowKind::Contact, RowKind::Friction}) {
    const auto first = static_cast<std::ptrdiff_t>(out.size());
    for (std::size_t k = 0; k < kinds.size(); ++k)
      if (kinds[k] == kind) out.push_back(static_cast<int>(k));
    if (order == RowOrder::Reverse) std::reverse(out.begin() + first, out.end());
    if (order == RowOrder::Random) std::shuffle(out.begin() + first, out.end(), rng);
  }
}

SweepOrder::SweepOrder(const BoxedProblem& problem, const SolverOptions& options)
    : order_(options.order), rows_(static_cast<int>(problem.rows())), rng_(options.seed) {
  if (options.contacts_first) {
    if (problem.kinds == nullptr)
      throw std::invalid_argument("contacts_first: the problem has no row kinds");
    kinds_ = problem.kinds;
  }
  // The orders that stay the same every sweep are made once.
  if (kinds_ != nullptr && order_ != RowOrder::Random) sweep_order(order_, *kinds_, rng_, out_);
  if (kinds_ == nullptr && order_ == RowOrder::Reverse) sweep_order(order_, rows_, rng_, out_);
}

const std::vector<int>& SweepOrder::next() {
  if (order_ == RowOrder::Random) {
    if (kinds_ != nullptr) {
      sweep_order(order_, *kinds_, rng_, out_);
    } else {
      sweep_order(order_, rows_, rng_, out_);
    }
  }
  return out_;
}

double jacobi_sweep(const BoxedProblem& problem, VecX& lambda, double relaxation, VecX& scratch) {
  scratch = lambda;  // the previous sweep's values
  const SpMat& A_rows = detail::rows_of(problem);
  double delta = 0.0;
  double target = 0.0;
  for (Eigen::Index k = 0; k < problem.A.outerSize(); ++k) {
    if (!row_target(A_rows, problem.b, scratch, k, target)) continue;
    lambda(k) = clamp(relax(scratch(k), target, relaxation), problem.cmin(k), problem.cmax(k));
    const double change = std::abs(lambda(k) - scratch(k));
    max_keep_nan(delta, change);
  }
  return delta;
}

SolverSummary solve_pgs(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  SweepOrder order(problem, options);
  return detail::iterate_sweeps(problem, lambda, options, [&](VecX& l) {
    const std::vector<int>& rows = order.next();
    if (rows.empty()) return pgs_sweep(problem, l, options.relaxation);  // 0 … c−1
    return pgs_sweep(problem, l, options.relaxation, rows);
  });
}

SolverSummary solve_sgs(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  const Eigen::Index c = problem.A.outerSize();
  return detail::iterate_sweeps(problem, lambda, options, [&](VecX& l) {
    const double forward = pgs_sweep(problem, l, options.relaxation);
    const double backward =
        sweep_rows(problem, l, options.relaxation, c, [c](Eigen::Index n) { return c - 1 - n; });
    return std::max(forward, backward);
  });
}

SolverSummary solve_jacobi(const BoxedProblem& problem,
                           VecX& lambda,
                           const SolverOptions& options) {
  VecX scratch;
  return detail::iterate_sweeps(problem, lambda, options, [&](VecX& l) {
    return jacobi_sweep(problem, l, options.relaxation, scratch);
  });
}

// This file's entries in the one table of methods (methods.hpp, gathered by methods.cpp).

extern const MethodEntry kPgsEntry;
constexpr MethodEntry kPgsEntry{
    .method = Method::Pgs,
    .name = "pgs",
    .order = true,
    .contacts_first = true,
    .sweeps_alone = true,
    .solve = solve_pgs,
    .what = "projected Gauss-Seidel, the paper's 7.1.1",
};

extern const MethodEntry kSgsEntry;
constexpr MethodEntry kSgsEntry{
    .method = Method::Sgs,
    .name = "sgs",
    .omega = true,
    .sweeps_alone = true,
    .solve = solve_sgs,
    .what = "symmetric Gauss-Seidel, a forward and a backward sweep",
};

extern const MethodEntry kJacobiEntry;
constexpr MethodEntry kJacobiEntry{
    .method = Method::Jacobi,
    .name = "jacobi",
    .omega = true,
    .damping = true,
    .sweeps_alone = true,
    .solve = solve_jacobi,
    .what = "projected Jacobi; jacobi:OMEGA damps it, (0, 1]",
};

}  // namespace cbps
