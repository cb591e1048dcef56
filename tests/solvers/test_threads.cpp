// One thread means one thread (cbps/solvers/threads.hpp): the CHOLMOD factorization under the
// exact path starts no thread of its own once set_threads(1) has run. ctest runs every test case
// in a process of its own, so nothing has started OpenMP's threads before this one.
#include <catch2/catch.hpp>
#include <filesystem>
#include <iterator>

#include "cbps/solvers/exact/cholmod_factor.hpp"
#include "cbps/solvers/threads.hpp"

namespace {

/// The threads of this process now (Linux: one entry per task in /proc/self/task).
long process_threads() {
  const std::filesystem::directory_iterator tasks("/proc/self/task");
  return long(std::distance(tasks, std::filesystem::directory_iterator()));
}

/// The 7-point Laplacian of an n × n × n grid plus the identity: symmetric positive definite,
/// with supernodes large enough for CHOLMOD's parallel loops (n = 24: 13,824 rows).
cbps::SpMat grid_laplacian(int n) {
  const auto at = [n](int i, int j, int k) { return (i * n + j) * n + k; };
  std::vector<cbps::Triplet> t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const int r = at(i, j, k);
        t.emplace_back(r, r, 7.0);
        if (i + 1 < n) t.emplace_back(at(i + 1, j, k), r, -1.0);
        if (j + 1 < n) t.emplace_back(at(i, j + 1, k), r, -1.0);
        if (k + 1 < n) t.emplace_back(at(i, j, k + 1), r, -1.0);
      }
  cbps::SpMat A(n * n * n, n * n * n);
  A.setFromTriplets(t.begin(), t.end());  // the lower triangle, which is what CHOLMOD reads
  return A;
}

}  // namespace

TEST_CASE("one thread asked: a CHOLMOD factorization starts no thread", "[threads]") {
  const cbps::ThreadReport report = cbps::set_threads(1);
  CHECK(report.blas_threads == 1);
  if (report.openmp_threads > 0) CHECK(report.openmp_threads == 1);
  const cbps::SpMat A = grid_laplacian(24);
  const long before = process_threads();
  cbps::CholmodFactor factor;
  REQUIRE(factor.factor(A, 0.0));
  REQUIRE(factor.nonzeros() > 1000000);  // supernodal work CHOLMOD would share out
  CHECK(process_threads() == before);
  // And the factor is right: A x = b for a known x.
  const cbps::VecX x = cbps::VecX::LinSpaced(A.rows(), -1.0, 1.0);
  const cbps::VecX b = A.selfadjointView<Eigen::Lower>() * x;
  cbps::VecX solved;
  factor.solve(b, solved);
  CHECK((solved - x).lpNorm<Eigen::Infinity>() < 1e-10);
}
