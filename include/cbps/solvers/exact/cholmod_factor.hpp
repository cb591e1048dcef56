// A CHOLMOD factorization of H = A + εI for a symmetric sparse A (only its lower triangle is
// read), kept between solves: the exact paths' factor (direct, active set, ADMM) and the one
// the condition estimate of studies/conditioning.hpp inverts with. CHOLMOD itself stays behind
// it: direct_cholmod.cpp is the only file that sees CHOLMOD's headers.
#pragma once

#include <memory>

#include "cbps/base/types.hpp"

namespace cbps {

class CholmodFactor {
 public:
  CholmodFactor();
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  /// Simplicial LDLᵀ instead of CHOLMOD's choice (supernodal where the flops per nonzero of L
  /// are high) from the next factor() on, unless its analysis counts more than 1e8 flops:
  /// body space's H = M + Jᵀ D⁻¹ J factors in half the time simplicially with Debian's
  /// reference BLAS (pyramid base 40: 11 ms against 21 ms for 2.2e7 flops), and updates
  /// (update()) need a simplicial factor anyway; past 1e8 flops the supernodal factor is the
  /// faster by far (the 101,568-row pyramid: 9.8e8 flops, its solve 1.6 s against 4.9 s), and an
  /// update turns it simplicial then.
  void set_simplicial(bool simplicial) { simplicial_ = simplicial; }
  /// Orders (CHOLMOD's choice: AMD, METIS, …) and factors H = A + eps I. Returns false if H is
  /// not positive definite in floating point (a zero or negative pivot).
  bool factor(const SpMat& A, double eps);
  /// Factors A + eps I again with the ordering of the last factor() (same pattern as then).
  bool refactor(const SpMat& A, double eps);
  /// The factor of H ± C Cᵀ from that of H (CHOLMOD's multiple-rank update/downdate, Davis &
  /// Hager, SIAM J. Matrix Anal. Appl. 20(3) 1999 and 22(4) 2001): C is n × k in H's own row
  /// order. The factor becomes simplicial LDLᵀ (later refactor() calls stay simplicial). False
  /// when the result is not positive definite; then the factor is invalid.
  bool update(const SpMat& C, bool up);
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
  bool simplicial_ = false;
};

}  // namespace cbps
