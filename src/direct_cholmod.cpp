// Direct solve of the equality system A λ = b (6.2.9) by CHOLMOD's sparse Cholesky.
// The only file that includes CHOLMOD.
#include <Eigen/CholmodSupport>
#include <cmath>
#include <sstream>

#include "cbps/error.hpp"
#include "cbps/solver.hpp"

namespace cbps {

SolverSummary solve_cholesky(const SpMat& A, const VecX& b, VecX& lambda) {
  SolverSummary s;
  s.termination = Termination::Direct;
  if (A.rows() == 0) {
    lambda.resize(0);
    s.message = "no rows";
    return s;
  }
  // CHOLMOD picks the fill-reducing ordering (AMD or METIS) and simplicial or supernodal.
  Eigen::CholmodDecomposition<SpMat, Eigen::Lower> llt;
  llt.compute(A);
  if (llt.info() != Eigen::Success) {
    throw ComputationError(
        "direct solver: CHOLMOD found A = J Minv Jᵀ not positive definite (redundant rows?)");
  }
  lambda = llt.solve(b);
  s.iterations = 1;
  s.residual = (A * lambda - b).lpNorm<Eigen::Infinity>();  // all rows unbounded: |w|∞
  if (!std::isfinite(s.residual)) s.termination = Termination::NonFinite;
  std::ostringstream msg;
  msg << "CHOLMOD Cholesky, residual " << s.residual << " N";
  s.message = msg.str();
  return s;
}

}  // namespace cbps
