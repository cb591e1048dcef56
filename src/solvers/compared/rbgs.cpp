// Red-black (multicolour) projected Gauss-Seidel: a greedy colouring of A's rows and 7.1.1 over
// the rows colour by colour. The method and its sources are described in rbgs.hpp.
#include "cbps/solvers/compared/rbgs.hpp"

#include <sstream>

#include "../sweep.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/paper/pgs.hpp"

namespace cbps {

RowColouring colour_rows(const SpMat& A) {
  const Eigen::Index c = A.outerSize();
  RowColouring g;
  g.colour.assign(static_cast<std::size_t>(c), -1);
  // used[colour] == k marks a colour taken by a neighbour of row k (no clearing between rows).
  std::vector<Eigen::Index> used;
  for (Eigen::Index k = 0; k < c; ++k) {
    // A is symmetric: column k holds the rows i coupled to row k.
    for (SpMat::InnerIterator it(A, k); it; ++it) {
      if (it.row() == k || it.value() == 0.0) continue;
      const int neighbour = g.colour[std::size_t(it.row())];
      if (neighbour >= 0) used[std::size_t(neighbour)] = k;
    }
    int first_free = 0;
    while (first_free < g.colours && used[std::size_t(first_free)] == k) ++first_free;
    if (first_free == g.colours) {
      ++g.colours;
      used.push_back(-1);
    }
    g.colour[std::size_t(k)] = first_free;
  }
  // Rows grouped by colour, natural order within a colour (a counting sort).
  g.start.assign(static_cast<std::size_t>(g.colours) + 1, 0);
  for (const int colour : g.colour) ++g.start[std::size_t(colour) + 1];
  for (std::size_t n = 1; n < g.start.size(); ++n) g.start[n] += g.start[n - 1];
  g.order.resize(static_cast<std::size_t>(c));
  std::vector<int> next(g.start.begin(), g.start.end() - 1);
  for (Eigen::Index k = 0; k < c; ++k)
    g.order[std::size_t(next[std::size_t(g.colour[std::size_t(k)])]++)] = int(k);
  return g;
}

SolverSummary solve_rbgs(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  const RowColouring g = colour_rows(problem.A);
  SolverSummary s = detail::iterate_sweeps(problem, lambda, options, [&](VecX& l) {
    return pgs_sweep(problem, l, options.relaxation, g.order);  // 7.1.1, colour by colour
  });
  if (options.describe) {
    std::ostringstream msg;
    msg << ", " << g.colours << " colours";
    s.message += msg.str();
  }
  return s;
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

extern const MethodEntry kRbgsEntry;
constexpr MethodEntry kRbgsEntry{
    .method = Method::Rbgs,
    .name = "rbgs",
    .omega = true,
    .sweeps_alone = true,
    .solve = solve_rbgs,
    .what = "red-black (graph-coloured) PGS, the parallel engines' order",
};

}  // namespace cbps
