// The Newton matrix of the interior point on cones (cone_direct.cpp), factored in body space
// where the problem has J and Minv, in row space otherwise. Private to solvers/cone/.
#pragma once

#include <optional>
#include <vector>

#include "../exact/newton_system.hpp"
#include "cbps/solvers/exact/cholmod_factor.hpp"

namespace cbps {

/// The largest backward error of a body-space solve kept (InteriorSystem): an interior point's
/// Newton direction may be inexact, since its residuals are formed anew every iteration (the
/// 1,600-contact pyramid at rest: 1.8e-5 at most, 9 iterations in either space), but past this
/// the iterations grow (the 400-contact pile under the paper's box: 41 instead of 27 once its
/// solves reached 4e-4).
inline constexpr double kBodyAccuracy = 1e-4;

/// One constraint of the interior point: a finite bound of a row no contact owns, s = a (x_row −
/// h) ≥ 0 (a = ±1), or a contact's cone, s = (a x_n, x_t1, x_t2) in the second-order cone
/// (a = mu, row the normal). `at` is its first entry in s and z.
struct ConeConstraint {
  int row = 0;
  int at = 0;
  bool cone = false;
  double a = 1.0;
  double h = 0.0;
  int size() const { return cone ? 3 : 1; }
};

/// What body space reads of a problem, formed once per solve: J (column-major) and Jᵀ, Minv,
/// M = Minv⁻¹ (body_masses()) and the CFM in A.
struct BodyFactors {
  SpMat J, Jt, Minv, M;
  double cfm = 0.0;
};

/// The problem's BodyFactors where body_masses() finds M, nullopt otherwise (row space).
std::optional<BodyFactors> body_factors(const BoxedProblem& problem);

/// A' + Σ_k E_kᵀ W_k⁻² E_k + ρ I (InteriorSystem's B below), the fixed rows replaced by the
/// identity: the row-space Newton matrix. Its pattern (A's, the diagonal, each contact's 3×3
/// block) is the same for every W.
SpMat row_space_matrix(const SpMat& A_scaled,
                       const std::vector<char>& fixed,
                       const std::vector<ConeConstraint>& constraints,
                       const std::vector<Mat3>& Winv,
                       double rho);

/// The interior point's Newton matrix on the problem scaled to max A_kk = 1 (A' = A / md):
///   A' + B,   B = Σ_k E_kᵀ W_k⁻² E_k + ρ I,
/// E_k a constraint's map from x to its s (a bound's a on its row, a cone's diag(mu, 1, 1) on
/// its contact's rows), W_k its Nesterov–Todd scaling, the fixed rows out of the system (x = 0
/// there). factor() once per scaling, solve() any number of times; one ordering per object.
///
/// Row space factors A' + B by CHOLMOD. Body space (the problem has J and Minv, body_masses()):
/// with D = md B + cfm I (block diagonal, 3×3 per contact) and Ω = D⁻¹,
///   (A' + B)⁻¹ r = Ω (md r − J u),   u = (M + Jᵀ Ω J)⁻¹ Jᵀ Ω md r      (Woodbury),
/// CHOLMOD on M + Jᵀ Ω J, 6 rows a body where A' + B has 3 a contact and fills with every pair
/// of contacts on a body (pyramid of 1,600 contacts: 1,260 rows against 4,800). A cone's Ω is
/// formed from W, never by inverting the block of B: Ω = S⁻¹ W (md I + δ W S⁻² W)⁻¹ W S⁻¹, S =
/// diag(mu, 1, 1), δ = md ρ + cfm, a matrix with eigenvalues ≥ md inverted, so a contact
/// opening (W → 0 along a direction) gives Ω → 0 there to full relative accuracy. Each solve
/// refines twice against A' + B (A' x = J (Minv (Jᵀ x)) / md + cfm x / md).
///
/// Woodbury is not backward stable: where B spans 24 orders of magnitude (late iterations,
/// contacts both sticking and opening) the cancellation in md r − J u leaves solves with a
/// backward error ‖r − (A' + B) x‖∞ / (‖A' x‖∞ + ‖B x‖∞ + ‖r‖∞) of 1e-5 (the pyramid of 1,600
/// contacts at rest, harmless: 9 iterations in either space) up to 1 (the 400-contact pile
/// under the paper's box: the iterations double, the answer stalls at 1e-9 N). A solve whose
/// backward error exceeds kBodyAccuracy is done again in row space, and the object stays there.
class InteriorSystem {
 public:
  /// A_scaled = A / md; fixed: the rows out of the system; body: what body space reads, or
  /// nullptr for row space. Every argument must outlive the object.
  InteriorSystem(const SpMat& A_scaled,
                 double md,
                 const std::vector<char>& fixed,
                 const std::vector<ConeConstraint>& constraints,
                 const BodyFactors* body);
  /// Factors for the scalings W (Winv = W⁻¹), one per constraint (a bound's in its (0, 0)
  /// entry), and ρ; false when CHOLMOD fails.
  bool factor(const std::vector<Mat3>& W, const std::vector<Mat3>& Winv, double rho);
  /// x = (A' + B)⁻¹ r on the kept rows, 0 on the fixed rows (r must be 0 there); moves to row
  /// space where a body-space solve is not accurate enough. False when that factor fails.
  bool solve(const VecX& r, VecX& x);
  /// "body" while every solve was in body space, "row" otherwise.
  const char* space() const { return body_ ? "body" : "row"; }
  /// Factorizations in body space before the move to row space (all of them while in it).
  int body_factorizations() const { return body_factorizations_; }
  /// Numeric factorizations in both spaces.
  int factorizations() const { return factorizations_; }
  /// Nonzeros of the Cholesky factor (CHOLMOD's count), the largest of both spaces'.
  long factor_nonzeros() const { return nonzeros_; }

 private:
  bool factor_rows(const std::vector<Mat3>& Winv, double rho);
  bool factor_bodies(const std::vector<Mat3>& W, const std::vector<Mat3>& Winv, double rho);
  /// One Woodbury application (body space).
  void apply(const VecX& r, VecX& x) const;
  /// A' x = (J (Minv (Jᵀ x)) + cfm x) / md and B x (body space), both zero on the fixed rows.
  VecX A_times(const VecX& x) const;
  VecX B_times(const VecX& x) const;
  /// The analysed factor of H, or a new analysis where H's pattern differs from the last.
  bool factor_matrix(const SpMat& H);
  /// The body-space solve's backward error (see the class).
  double backward_error(const VecX& r, const VecX& x) const;

  const SpMat& A_;
  double md_;
  const std::vector<char>& fixed_;
  const std::vector<ConeConstraint>& constraints_;
  const BodyFactors* factors_ = nullptr;
  bool body_ = false;
  int body_factorizations_ = 0;
  int factorizations_ = 0;
  long nonzeros_ = 0;
  // Body space.
  SpMat Omega_;
  std::vector<Mat3> Winv_;  ///< the last scaling, for B_times()
  double rho_ = 0.0;
  // Both.
  CholmodFactor factor_;
  bool analysed_ = false;
  Eigen::Index pattern_nnz_ = -1;
};

}  // namespace cbps
