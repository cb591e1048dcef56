// A global frictional-contact problem with its velocities eliminated (global_problem.hpp).
#include "global_problem.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <utility>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/system/system.hpp"

namespace cbps {

void in_cones(StoredProblem& p, long m, long e, const std::vector<double>& mu) {
  p.cmin = VecX::Constant(m + e, -kInf);
  p.cmax = VecX::Constant(m + e, kInf);
  p.cones.mu.resize(m / 3);
  for (long i = 0; i < m / 3; ++i) {
    p.cones.normal.push_back(static_cast<int>(3 * i));
    p.cones.mu(i) = mu[static_cast<std::size_t>(i)];
    p.cmin(3 * i) = 0.0;  // the normal row alone: [0, ∞) (the cone decides)
  }
}

bool block_inverse(const SpMat& M, SpMat& inverse, std::string& failure) {
  const long n = M.rows();
  std::vector<long> component(static_cast<std::size_t>(n), -1);
  std::vector<std::vector<long>> blocks;
  const SpMat pattern = SpMat(M.transpose()) + M;  // both triangles, whichever M stores
  for (long start = 0; start < n; ++start) {
    if (component[static_cast<std::size_t>(start)] >= 0) continue;
    std::vector<long> members{start};
    component[static_cast<std::size_t>(start)] = static_cast<long>(blocks.size());
    for (std::size_t k = 0; k < members.size(); ++k) {
      for (SpMat::InnerIterator it(pattern, members[k]); it; ++it) {
        long& c = component[static_cast<std::size_t>(it.row())];
        if (c >= 0) continue;
        c = static_cast<long>(blocks.size());
        members.push_back(it.row());
        if (static_cast<long>(members.size()) > kInverseBlock) return false;
      }
    }
    std::sort(members.begin(), members.end());
    blocks.push_back(std::move(members));
  }
  std::vector<Triplet> entries;
  for (const std::vector<long>& block : blocks) {
    const long size = static_cast<long>(block.size());
    Eigen::MatrixXd B(size, size);
    for (long r = 0; r < size; ++r)
      for (long c = 0; c < size; ++c)
        B(r, c) = M.coeff(block[std::size_t(r)], block[std::size_t(c)]);
    const Eigen::LLT<Eigen::MatrixXd> llt(B);
    if (llt.info() != Eigen::Success) {
      failure = "the block of rows " + std::to_string(block.front()) + ".." +
                std::to_string(block.back()) + " is not positive definite";
      return false;
    }
    const Eigen::MatrixXd D = llt.solve(Eigen::MatrixXd::Identity(size, size));
    for (long r = 0; r < size; ++r)
      for (long c = 0; c < size; ++c)
        if (D(r, c) != 0.0)
          entries.emplace_back(block[std::size_t(r)], block[std::size_t(c)], D(r, c));
  }
  inverse.resize(n, n);
  inverse.setFromTriplets(entries.begin(), entries.end());
  return true;
}

SpMat symmetric_from_triangle(const SpMat& M, std::string& note) {
  long upper = 0, lower = 0;  // stored entries off the diagonal, nonzero
  for (Eigen::Index j = 0; j < M.outerSize(); ++j)
    for (SpMat::InnerIterator it(M, j); it; ++it)
      if (it.value() != 0.0) {
        if (it.row() < it.col()) ++upper;
        if (it.row() > it.col()) ++lower;
      }
  note.clear();
  if ((upper == 0) == (lower == 0)) return M;  // both triangles (or a diagonal M): as stored
  note = "M stored as its " + std::string(upper > 0 ? "upper" : "lower") + " triangle (" +
         std::to_string(upper + lower) +
         " entries off the diagonal, none in the other): read as the symmetric M it is half of";
  SpMat diagonal(M.rows(), M.cols());
  diagonal.reserve(Eigen::VectorXi::Constant(M.cols(), 1));
  for (Eigen::Index j = 0; j < M.outerSize(); ++j)
    for (SpMat::InnerIterator it(M, j); it; ++it)
      if (it.row() == it.col()) diagonal.insert(it.row(), it.col()) = it.value();
  SpMat full = M + SpMat(M.transpose()) - diagonal;
  full.makeCompressed();
  return full;
}

StoredProblem eliminate_velocities(const GlobalProblem& g,
                                   const std::function<void(const std::string& why)>& fail_M) {
  const auto fail = [&](const std::string& why) {
    fail_M(why);
    throw InputError("M: " + why);  // fail_M throws; this is never reached
  };
  std::string triangle;
  const SpMat M = symmetric_from_triangle(g.M, triangle);
  const long n = M.rows(), m = g.H.cols(), e = g.G.cols();
  const SpMat asymmetry = M - SpMat(M.transpose());
  if (asymmetry.nonZeros() > 0 &&
      asymmetry.coeffs().cwiseAbs().maxCoeff() > 1e-12 * SpMat(M).coeffs().cwiseAbs().maxCoeff())
    fail("not symmetric (a mass matrix is; entries differ by up to " +
         number_text(asymmetry.coeffs().cwiseAbs().maxCoeff()) + ")");
  SpMatRow J(m + e, n);  // [Hᵀ; Gᵀ]
  {
    std::vector<Triplet> entries;
    for (const auto& [B, row0] : {std::pair<const SpMat*, long>{&g.H, 0}, {&g.G, m}})
      for (Eigen::Index j = 0; j < B->outerSize(); ++j)
        for (SpMat::InnerIterator it(*B, j); it; ++it)
          entries.emplace_back(row0 + it.col(), it.row(), it.value());
    J.setFromTriplets(entries.begin(), entries.end());
  }
  SpMat Minv, A;  // A = J M⁻¹ Jᵀ (6.2.9)
  VecX Minv_f;
  std::string failure;
  const bool blocks = block_inverse(M, Minv, failure);
  if (!failure.empty()) fail(failure);
  if (blocks) {
    A = compute_A(J, Minv);
    Minv_f = Minv * g.f;
  } else {  // M⁻¹ is not formed: M⁻¹ Jᵀ by its sparse LDLᵀ
    const Eigen::SimplicialLDLT<SpMat> ldlt(M);  // M's lower triangle (symmetric, checked)
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all())
      fail("not symmetric positive definite (its LDL^T has a pivot <= 0)");
    A = J * SpMat(ldlt.solve(SpMat(J.transpose())));
    Minv_f = ldlt.solve(g.f);
  }
  StoredProblem p;
  if (!triangle.empty()) p.notes.push_back(triangle);
  p.A = 0.5 * (A + SpMat(A.transpose()));  // symmetric to the bit, as J M⁻¹ Jᵀ is
  const VecX q = J * Minv_f;
  p.b.resize(m + e);
  p.b.head(m) = -(q.head(m) + g.w);
  if (e > 0) p.b.tail(e) = -(q.tail(e) + g.b_G);
  p.A.makeCompressed();  // coeffs(): every stored value
  if (!p.b.allFinite() || !p.A.coeffs().allFinite())
    fail("H^T M^-1 H or H^T M^-1 f overflows (entries beyond the range of a double)");
  in_cones(p, m, e, g.mu);
  if (blocks) {
    p.J = J;
    p.Minv = Minv;
  } else {
    p.without_jacobian = "a global problem whose M couples more than " +
                         std::to_string(kInverseBlock) +
                         " rows: A = H^T M^-1 H formed by a sparse LDL^T of M";
  }
  return p;
}

}  // namespace cbps
