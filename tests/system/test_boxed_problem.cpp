// The boxed problem of 6.2 and its natural-map residual.
#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

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

TEST_CASE("a NaN in any row makes the residual NaN, wherever the row is", "[solver]") {
  const VecX lo = VecX::Constant(4, -kInf);
  const VecX hi = VecX::Constant(4, kInf);
  const VecX lambda = VecX::Zero(4);
  for (Eigen::Index k = 0; k < 4; ++k) {
    VecX w = VecX::Constant(4, 2.0);
    w(k) = std::numeric_limits<double>::quiet_NaN();  // first, middle or last row
    INFO("NaN in row " << k);
    CHECK(std::isnan(natural_map_residual(w, lambda, lo, hi)));
  }
  double m = 1.0;
  max_keep_nan(m, 3.0);
  CHECK(m == 3.0);
  max_keep_nan(m, std::numeric_limits<double>::quiet_NaN());
  max_keep_nan(m, 5.0);  // a later finite value does not replace the NaN
  CHECK(std::isnan(m));
}
