// Condition estimates of A: exact, singular, and Lanczos/Cholesky against analysis.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "cbps/studies/conditioning.hpp"

using namespace cbps;

namespace {

/// The tridiagonal matrix tridiag(−1, 2, −1) of size n: eigenvalues 2 − 2 cos(k π / (n + 1)).
SpMat laplacian(int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < n; ++k) {
    t.emplace_back(k, k, 2.0);
    if (k + 1 < n) {
      t.emplace_back(k, k + 1, -1.0);
      t.emplace_back(k + 1, k, -1.0);
    }
  }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

double laplacian_condition(int n) {
  const double pi = std::acos(-1.0);
  const double h = pi / (n + 1);
  return (2.0 - 2.0 * std::cos(n * h)) / (2.0 - 2.0 * std::cos(h));
}

}  // namespace

TEST_CASE("condition estimate: exact, singular and Lanczos/Cholesky against analysis",
          "[stress][condition]") {
  const ConditionEstimate small = estimate_condition(laplacian(50));
  CHECK(small.exact);
  CHECK(small.nullity == 0);
  CHECK(small.condition == Approx(laplacian_condition(50)).epsilon(1e-10));

  SpMat twice(2, 2);
  twice.insert(0, 0) = 1.0;
  twice.insert(0, 1) = 1.0;
  twice.insert(1, 0) = 1.0;
  twice.insert(1, 1) = 1.0;
  const ConditionEstimate singular = estimate_condition(twice);
  CHECK(singular.nullity == 1);
  CHECK(std::isinf(singular.condition));
  CHECK(singular.range_condition == Approx(1.0));

  const int n = 3000;  // beyond kExactConditionRows: the estimate
  REQUIRE(n > kExactConditionRows);
  const ConditionEstimate large = estimate_condition(laplacian(n));
  CHECK_FALSE(large.exact);
  CHECK(large.condition == Approx(laplacian_condition(n)).epsilon(0.02));
  CHECK(large.lambda_min == Approx(2.0 - 2.0 * std::cos(std::acos(-1.0) / (n + 1))).epsilon(1e-6));

  // A large singular matrix: the Laplacian with a zero row sum everywhere (free-free ends).
  SpMat free_free = laplacian(n);
  free_free.coeffRef(0, 0) = 1.0;
  free_free.coeffRef(n - 1, n - 1) = 1.0;
  CHECK(std::isinf(estimate_condition(free_free).condition));
}
