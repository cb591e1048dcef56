// Bullet 3.24's MLCP solvers (double precision, libBulletDynamics-float64) on cbps's boxed
// problem: btMLCPSolverInterface::solveMLCP(A, b, x, lo, hi) is 6.2's problem itself
// (w = A x − b, lo ≤ x ≤ hi), with A dense. Infinite bounds pass as they are (BT_INFINITY is
// IEEE infinity in a double build).
#include <cmath>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/peers/peers.hpp"

#ifdef CBPS_HAVE_BULLET

#include <BulletDynamics/MLCPSolvers/btDantzigSolver.h>
#include <BulletDynamics/MLCPSolvers/btLemkeSolver.h>
#include <BulletDynamics/MLCPSolvers/btSolveProjectedGaussSeidel.h>

#include <algorithm>
#include <chrono>
#include <memory>

#include "child_process.hpp"

static_assert(sizeof(btScalar) == sizeof(double),
              "cbps's Bullet peers need Bullet's double-precision build (BT_USE_DOUBLE_PRECISION)");

namespace cbps {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

PeerRun run_here(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int c = static_cast<int>(problem.rows());
  PeerRun run;
  run.problem_class = "boxed MLCP";
  btMatrixXu A(c, c);
  A.setZero();
  for (int k = 0; k < problem.A.outerSize(); ++k)
    for (SpMat::InnerIterator it(problem.A, k); it; ++it)
      A.setElem(static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
  btVectorXu b(c), x(c), lo(c), hi(c);
  for (int k = 0; k < c; ++k) {
    b[k] = problem.b[k];
    x[k] = lambda[k];
    lo[k] = problem.cmin[k];
    hi[k] = problem.cmax[k];
  }
  btAlignedObjectArray<int> limit_dependency;  // no row's bound scales with another's
  limit_dependency.resize(c, -1);

  std::unique_ptr<btMLCPSolverInterface> solver;
  int iterations = options.max_iterations;
  if (options.method == Method::BulletDantzig) {
    solver = std::make_unique<btDantzigSolver>();
  } else if (options.method == Method::BulletLemke) {
    auto lemke = std::make_unique<btLemkeSolver>();
    // Its plain LCP path for an LCP (every row [0, inf)), its bounded path otherwise (which
    // inverts A); a pivot limit of at least 10 per unknown.
    lemke->m_useLoHighBounds = peer_class(problem) != PeerClass::Lcp;
    lemke->m_maxLoops = std::max(lemke->m_maxLoops, 10 * c);
    solver = std::move(lemke);
  } else {
    auto pgs = std::make_unique<btSolveProjectedGaussSeidel>();
    // It stops when the sum of squared changes of a sweep is below its threshold: cbps's change
    // tolerance squared (0: every sweep).
    pgs->m_leastSquaresResidualThreshold = options.delta_tolerance * options.delta_tolerance;
    solver = std::move(pgs);
  }
  run.convert_s = seconds_since(start);
  const auto solve_start = std::chrono::steady_clock::now();
  run.said_ok = solver->solveMLCP(A, b, x, lo, hi, limit_dependency, iterations, true);
  run.solve_s = seconds_since(solve_start);
  run.status = run.said_ok ? "returned true" : "returned false";
  // Its PGS sweeps numIterations times unless the threshold stops it (it does not say when).
  if (options.method == Method::BulletPgs && options.delta_tolerance == 0.0)
    run.iterations = iterations;
  for (int k = 0; k < c; ++k) lambda[k] = x[k];
  return run;
}

}  // namespace

PeerRun run_bullet(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  // Bullet's solvers take no limit of time and cannot be interrupted: under one, they run in a
  // child process killed at it; without one, here (no fork in a timed comparison).
  if (options.time_limit > 0.0 || options.deadline != std::chrono::steady_clock::time_point::max())
    return run_in_child(problem, lambda, options, run_here, "Bullet");
  return run_here(problem, lambda, options);
}

}  // namespace cbps

#else  // a build without Bullet: solve_peer refuses before it gets here

namespace cbps {
PeerRun run_bullet(const BoxedProblem&, VecX&, const SolverOptions&) { return {}; }
}  // namespace cbps

#endif

namespace cbps {

namespace {

/// Dantzig's method (ODE's, as Bullet ships it) needs cmin <= 0 <= cmax on every row.
std::string dantzig_refusal(const BoxedProblem& problem) {
  for (long k = 0; k < problem.rows(); ++k)
    if (!(problem.cmin[k] <= 0.0 && problem.cmax[k] >= 0.0))
      return "bullet:dantzig: Dantzig's method (ODE's, as Bullet ships it) needs cmin <= 0 <= "
             "cmax on every row; row " +
             std::to_string(k) + " has [" + number_text(problem.cmin[k]) + ", " +
             number_text(problem.cmax[k]) + "]";
  return "";
}

}  // namespace

// This file's entries in the one table of methods (methods.hpp, gathered by methods.cpp); the
// entries are there in every build, the peers refuse where the build has no Bullet
// (peer_available).

extern const MethodEntry kBulletDantzigEntry;
constexpr MethodEntry kBulletDantzigEntry{
    .method = Method::BulletDantzig,
    .name = "bullet:dantzig",
    .iterative = false,
    .library = Library::Bullet,
    .max_rows = kPeerDenseRows,
    .rows_why = "it works on a dense copy of A",
    .solve = solve_peer,
    .refuse = dantzig_refusal,
    .what = "Bullet's Dantzig solver (ODE's) on the boxed problem (dense, cmin <= 0 <= cmax)",
};

extern const MethodEntry kBulletLemkeEntry;
constexpr MethodEntry kBulletLemkeEntry{
    .method = Method::BulletLemke,
    .name = "bullet:lemke",
    .iterative = false,
    .library = Library::Bullet,
    .max_rows = kPeerTableauRows,
    .rows_why = "it works on a dense copy of A",
    .solve = solve_peer,
    .what = "Bullet's Lemke solver on the boxed problem (dense, <= 1000 rows)",
};

extern const MethodEntry kBulletPgsEntry;
constexpr MethodEntry kBulletPgsEntry{
    .method = Method::BulletPgs,
    .name = "bullet:pgs",
    .library = Library::Bullet,
    .max_rows = kPeerDenseRows,
    .rows_why = "it works on a dense copy of A",
    .solve = solve_peer,
    .what = "Bullet's projected Gauss-Seidel on the dense A",
};

}  // namespace cbps
