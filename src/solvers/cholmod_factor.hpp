// A CHOLMOD factorization of H = A + εI for a symmetric sparse A (only its lower triangle is
// read), kept between solves. Private to the library: direct_cholmod.cpp is the only file that
// sees CHOLMOD itself.
#pragma once

#include <memory>

#include "cbps/types.hpp"

namespace cbps {

class CholmodFactor {
 public:
  CholmodFactor();
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  /// Orders (CHOLMOD's choice: AMD, METIS, …) and factors H = A + eps I. Returns false if H is
  /// not positive definite in floating point (a zero or negative pivot).
  bool factor(const SpMat& A, double eps);
  /// Factors A + eps I again with the ordering of the last factor() (same pattern as then).
  bool refactor(const SpMat& A, double eps);
  /// CHOLMOD's cheap reciprocal condition estimate (min/max diagonal of the factor, squared);
  /// 0 when there is no valid factor.
  double rcond() const;
  /// x = H⁻¹ rhs with the current factor.
  void solve(const VecX& rhs, VecX& x) const;
  bool valid() const;
  /// Nonzeros of the factor L as CHOLMOD's analysis counted them (0 before any analysis).
  long nonzeros() const;
  Eigen::Index size() const { return n_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Eigen::Index n_ = 0;
};

}  // namespace cbps
