// Sparse Cholesky by CHOLMOD (SuiteSparse): the factor object of cholmod_factor.hpp and the
// equality solve of 6.2.9. The only file that includes CHOLMOD.
#include <Eigen/CholmodSupport>
#include <chrono>
#include <cmath>
#include <sstream>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/solvers/exact/cholmod_factor.hpp"
#include "cbps/solvers/exact/direct.hpp"

namespace cbps {

struct CholmodFactor::Impl {
  cholmod_common common{};
  cholmod_factor* L = nullptr;
  bool ok = false;
  int default_nmethods = 0, default_ordering = 0, default_postorder = 0;  ///< CHOLMOD's own

  Impl() {
    cholmod_start(&common);
    common.print = 0;  // a non-positive-definite H is an expected outcome, not a message
    common.error_handler = nullptr;
    default_nmethods = common.nmethods;
    default_ordering = common.method[0].ordering;
    default_postorder = common.postorder;
  }
  ~Impl() {
    if (L != nullptr) cholmod_free_factor(&L, &common);
    cholmod_finish(&common);
  }
};

CholmodFactor::CholmodFactor() : impl_(std::make_unique<Impl>()) {}
CholmodFactor::~CholmodFactor() = default;

namespace {

/// Matrices whose entries all lie within this many places of the diagonal keep their order.
constexpr Eigen::Index kNaturalBand = 8;
/// set_simplicial's limit: a factorization counted above this many flops by the analysis is
/// supernodal after all. Measured on body space's H, `cbps lcp FOLDER --solver direct`: the
/// base-40 pyramid (2.2e7 flops) 2.3 s simplicial against 2.45 s supernodal; the base-92
/// pyramid at step 0 (101,568 rows, 9.8e8 flops) 4.9 s against 1.6 s.
constexpr double kSimplicialFlops = 1e8;

/// CHOLMOD's view of the lower triangle of a symmetric Eigen matrix (no copy). CHOLMOD's
/// interface takes non-const pointers but does not write through them here.
cholmod_sparse lower_view(const SpMat& A) {
  cholmod_sparse view = Eigen::viewAsCholmod(const_cast<SpMat&>(A));
  view.stype = -1;  // symmetric, lower triangle stored
  return view;
}

}  // namespace

bool CholmodFactor::factor(const SpMat& A, double eps) {
  if (impl_->L != nullptr) cholmod_free_factor(&impl_->L, &impl_->common);
  impl_->ok = false;
  n_ = A.rows();
  cholmod_sparse view = lower_view(A);
  impl_->common.supernodal = simplicial_ ? CHOLMOD_SIMPLICIAL : CHOLMOD_AUTO;
  // A band matrix (a chain's A is tridiagonal) has no fill beyond its band in its own order:
  // no fill-reducing ordering can do better, and AMD's analysis is most of the time there.
  Eigen::Index band = 0;
  for (Eigen::Index j = 0; j < A.outerSize() && band <= kNaturalBand; ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it) band = std::max(band, std::abs(it.row() - j));
  const bool natural = band <= kNaturalBand;
  impl_->common.nmethods = natural ? 1 : impl_->default_nmethods;
  impl_->common.method[0].ordering = natural ? CHOLMOD_NATURAL : impl_->default_ordering;
  impl_->common.postorder = natural ? 0 : impl_->default_postorder;
  impl_->L = cholmod_analyze(&view, &impl_->common);
  if (impl_->L == nullptr) throw ComputationError("CHOLMOD: analysis failed (out of memory?)");
  if (simplicial_ && impl_->common.fl > kSimplicialFlops) {
    // Too many flops for a simplicial factor: analysed again for CHOLMOD's choice (supernodal).
    cholmod_free_factor(&impl_->L, &impl_->common);
    impl_->common.supernodal = CHOLMOD_AUTO;
    impl_->L = cholmod_analyze(&view, &impl_->common);
    if (impl_->L == nullptr) throw ComputationError("CHOLMOD: analysis failed (out of memory?)");
  }
  return refactor(A, eps);
}

bool CholmodFactor::refactor(const SpMat& A, double eps) {
  cholmod_sparse view = lower_view(A);
  double beta[2] = {eps, 0.0};  // factors A + beta[0] I
  impl_->common.status = CHOLMOD_OK;
  cholmod_factorize_p(&view, beta, nullptr, 0, impl_->L, &impl_->common);
  if (impl_->common.status == CHOLMOD_OUT_OF_MEMORY) {
    throw ComputationError("CHOLMOD: out of memory in the factorization");
  }
  impl_->ok = impl_->common.status == CHOLMOD_OK && impl_->L->minor == impl_->L->n;
  return impl_->ok;
}

bool CholmodFactor::update(const SpMat& C, bool up) {
  if (!impl_->ok || C.cols() == 0) return impl_->ok;
  cholmod_factor* L = impl_->L;
  // CHOLMOD updates P H Pᵀ = L D Lᵀ: C's rows go to their places in P's order, sorted.
  const auto* perm = static_cast<const int*>(L->Perm);
  std::vector<int> inverse(static_cast<std::size_t>(n_));
  for (Eigen::Index k = 0; k < n_; ++k) inverse[std::size_t(perm[k])] = static_cast<int>(k);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(std::size_t(C.nonZeros()));
  for (Eigen::Index j = 0; j < C.outerSize(); ++j)
    for (SpMat::InnerIterator it(C, j); it; ++it)
      entries.emplace_back(inverse[std::size_t(it.row())], j, it.value());
  SpMat permuted(C.rows(), C.cols());
  permuted.setFromTriplets(entries.begin(), entries.end());
  permuted.makeCompressed();
  cholmod_sparse view = Eigen::viewAsCholmod(permuted);
  view.stype = 0;  // unsymmetric: C itself, every entry
  impl_->common.status = CHOLMOD_OK;
  const int done = cholmod_updown(up ? 1 : 0, &view, L, &impl_->common);
  if (impl_->common.status == CHOLMOD_OUT_OF_MEMORY) {
    throw ComputationError("CHOLMOD: out of memory in an update");
  }
  impl_->ok = done != 0 && impl_->common.status == CHOLMOD_OK && L->minor == L->n;
  return impl_->ok;
}

double CholmodFactor::rcond() const {
  if (!impl_->ok) return 0.0;
  return cholmod_rcond(impl_->L, &impl_->common);
}

bool CholmodFactor::valid() const { return impl_->ok; }

long CholmodFactor::nonzeros() const {
  return impl_->L == nullptr ? 0L : static_cast<long>(impl_->common.lnz);
}

void CholmodFactor::solve(const VecX& rhs, VecX& x) const {
  if (!impl_->ok) throw ComputationError("CHOLMOD: solve without a valid factor");
  x.resize(rhs.size());
  if (rhs.size() == 0) return;
  cholmod_dense B{};
  B.nrow = static_cast<std::size_t>(rhs.size());
  B.ncol = 1;
  B.nzmax = B.nrow;
  B.d = B.nrow;
  B.x = const_cast<double*>(rhs.data());
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, impl_->L, &B, &impl_->common);
  if (X == nullptr) throw ComputationError("CHOLMOD: solve failed (out of memory?)");
  std::copy_n(static_cast<const double*>(X->x), rhs.size(), x.data());
  cholmod_free_dense(&X, &impl_->common);
}

SolverSummary solve_cholesky(const SpMat& A, const VecX& b, VecX& lambda) {
  const auto start = std::chrono::steady_clock::now();
  SolverSummary s;
  s.termination = Termination::Direct;
  if (A.rows() == 0) {
    lambda.resize(0);
    s.message = "no rows";
    return s;
  }
  CholmodFactor llt;
  s.factorizations = 1;
  if (!llt.factor(A, 0.0)) {
    throw ComputationError(
        "direct solver: CHOLMOD found A = J Minv Jᵀ not positive definite (redundant rows?)");
  }
  llt.solve(b, lambda);
  s.iterations = 1;
  s.islands = 1;
  s.residual = (A * lambda - b).lpNorm<Eigen::Infinity>();  // all rows unbounded: |w|∞
  if (!std::isfinite(s.residual)) s.termination = Termination::NonFinite;
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ostringstream msg;
  msg << "CHOLMOD Cholesky, residual " << s.residual << " N";
  s.message = msg.str();
  return s;
}

double cholesky_rcond(const SpMat& A) {
  if (A.rows() == 0) return 1.0;
  CholmodFactor llt;
  return llt.factor(A, 0.0) ? llt.rcond() : 0.0;
}

}  // namespace cbps
