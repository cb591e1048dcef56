// The boxed problem of 6.2 and its natural-map residual.
#include <Eigen/Cholesky>
#include <catch2/catch.hpp>

#include "cbps/system/boxed_problem.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::random_spd;

TEST_CASE("the natural-map residual is zero at a solution and positive elsewhere", "[solver]") {
  const SpMat A = random_spd(5, 9);
  const VecX b = VecX::LinSpaced(5, -1.0, 1.0);
  const VecX lo = VecX::Constant(5, -kInf);
  const VecX hi = VecX::Constant(5, kInf);
  const VecX x = MatX(A).ldlt().solve(b);
  CHECK(natural_map_residual(BoxedProblem{A, b, lo, hi}, x) < 1e-14);
  CHECK(natural_map_residual(BoxedProblem{A, b, lo, hi}, VecX::Zero(5)) == Approx(1.0));  // |b|∞
}
