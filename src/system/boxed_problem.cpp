// The boxed problem of 6.2: its residual, its scale, and constraint-force mixing.
#include "cbps/system/boxed_problem.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "cbps/system/system.hpp"

namespace cbps {

double clamp(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }

double natural_map_residual(const VecX& w, const VecX& lambda, const VecX& cmin, const VecX& cmax) {
  double r = 0.0;
  for (Eigen::Index k = 0; k < lambda.size(); ++k) {
    max_keep_nan(r, natural_map_row(lambda(k), w(k), cmin(k), cmax(k)));
  }
  return r;
}

double natural_map_residual(const BoxedProblem& problem, const VecX& lambda, double cfm) {
  if (lambda.size() == 0) return 0.0;
  const VecX w = times_A(problem, lambda) + cfm * lambda - problem.b;  // (A + eps E) λ − b (6.2)
  if (problem.cones != nullptr)
    return natural_map_residual(w, lambda, problem.cmin, problem.cmax, *problem.cones);
  return natural_map_residual(w, lambda, problem.cmin, problem.cmax);
}

SpMat with_cfm(const SpMat& A, double eps) {
  SpMat regularised = A;
  if (eps == 0.0) return regularised;
  for (Eigen::Index k = 0; k < A.rows(); ++k) regularised.coeffRef(k, k) += eps;
  return regularised;
}

double scale_of(const BoxedProblem& problem, double cfm) {
  double s = 1.0;
  if (problem.b.size() > 0) s = std::max(s, problem.b.lpNorm<Eigen::Infinity>());
  // eps itself where A has no diagonal entry (a diagonal of J Minv Jᵀ is ≥ 0: |A_kk + eps| ≥ eps)
  if (cfm != 0.0 && problem.rows() > 0) s = std::max(s, std::abs(cfm));
  if (!problem.A_formed()) {
    if (problem.rows() > 0)
      s = std::max(s, (diagonal_of_A(problem).array() + cfm).abs().maxCoeff());
    return s;
  }
  for (Eigen::Index j = 0; j < problem.A.outerSize(); ++j) {
    for (SpMat::InnerIterator it(problem.A, j); it; ++it)
      s = std::max(s, std::abs(it.value() + (it.row() == it.col() ? cfm : 0.0)));
  }
  return s;
}

double max_abs_row_sum(const SpMat& A) {
  double max_row_sum = 0.0;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {  // A symmetric: column sums = row sums
    double sum = 0.0;
    for (SpMat::InnerIterator it(A, j); it; ++it) sum += std::abs(it.value());
    max_row_sum = std::max(max_row_sum, sum);
  }
  return max_row_sum;
}

namespace {

/// J of a problem whose A was left out: it must carry J and Minv (BoxedProblem::A_formed).
const SpMatRow& factor_J(const BoxedProblem& problem) {
  if (!problem.has_factors() || problem.J->rows() != problem.rows())
    throw std::invalid_argument(
        "boxed problem: A is not c x c for c = " + std::to_string(problem.rows()) +
        " rows, and no J and Minv of those rows stand for it");
  return *problem.J;
}

}  // namespace

double max_abs_row_sum(const BoxedProblem& problem) {
  if (problem.A_formed()) return max_abs_row_sum(problem.A);
  if (problem.rows() == 0) return 0.0;
  const SpMatRow& J = factor_J(problem);
  const VecX reach = J.cwiseAbs().transpose() * VecX::Ones(J.rows());   // |J|ᵀ 1
  const VecX sums = J.cwiseAbs() * (problem.Minv->cwiseAbs() * reach);  // |J| |Minv| |J|ᵀ 1
  return sums.maxCoeff() + std::abs(problem.cfm);
}

VecX times_A(const BoxedProblem& problem, const VecX& x) {
  if (problem.A_formed()) return problem.A * x;
  return times_factors(factor_J(problem), *problem.Minv, problem.cfm, x);
}

VecX times_factors(const SpMatRow& J, const SpMat& Minv, double cfm, const VecX& x) {
  VecX y = J * (Minv * (J.transpose() * x));  // J Minv Jᵀ x (6.2.9)
  if (cfm != 0.0) y += cfm * x;
  return y;
}

VecX factors_test_vector(long first, long count) {
  VecX x(count);
  for (long k = 0; k < count; ++k) x(k) = std::sin(1.0 + double(first + k));
  return x;
}

FactorsGap factors_gap(const SpMat& A_rows, const VecX& x, const VecX& factors_x) {
  const Eigen::Index rows = A_rows.rows();
  VecX Ax = VecX::Zero(rows);
  VecX size = VecX::Zero(rows);  // Σ_k |A_ik x_k| for every row i (scattered by column)
  for (Eigen::Index j = 0; j < A_rows.outerSize(); ++j)
    for (SpMat::InnerIterator it(A_rows, j); it; ++it) {
      Ax(it.row()) += it.value() * x(j);
      size(it.row()) += std::abs(it.value() * x(j));
    }
  FactorsGap gap;
  for (Eigen::Index i = 0; i < rows; ++i) {
    max_keep_nan(gap.difference, std::abs(Ax(i) - factors_x(i)));
    max_keep_nan(gap.size, size(i));
  }
  return gap;
}

double factors_mismatch(const BoxedProblem& problem) {
  const Eigen::Index c = problem.A.rows();
  if (c == 0 || !problem.A_formed()) return 0.0;  // A left out: J Minv Jᵀ + cfm E by definition
  const VecX x = factors_test_vector(0, c);
  // J (Minv (Jᵀ x)) + cfm x, as BodySpace::times_A forms it.
  const VecX JMJx = times_factors(factor_J(problem), *problem.Minv, problem.cfm, x);
  return factors_gap(problem.A, x, JMJx).ratio();
}

VecX diagonal_of_A(const BoxedProblem& problem) {
  if (problem.A_formed()) return problem.A.diagonal();
  // A_kk = Σ_ij J_ki Minv_ij J_kj (6.2.9) row by row, without forming J Minv: for each entry
  // J_ki, column i of Minv met with row k of J (a row has at most 12 entries).
  const SpMatRow& J = factor_J(problem);
  const SpMat& Minv = *problem.Minv;
  VecX diagonal(J.rows());
  for (Eigen::Index k = 0; k < J.rows(); ++k) {
    const Eigen::Index start = J.outerIndexPtr()[k], end = J.outerIndexPtr()[k + 1];
    const int* cols = J.innerIndexPtr() + start;  // ascending
    const double* values = J.valuePtr() + start;
    double sum = 0.0;
    for (Eigen::Index i = 0; i < end - start; ++i) {
      for (SpMat::InnerIterator m(Minv, cols[i]); m; ++m) {
        const int* at = std::lower_bound(cols, cols + (end - start), static_cast<int>(m.row()));
        if (at != cols + (end - start) && *at == m.row())
          sum += values[i] * m.value() * values[at - cols];
      }
    }
    diagonal(k) = sum + problem.cfm;
  }
  return diagonal;
}

SpMat formed_A(const BoxedProblem& problem) {
  if (problem.A_formed()) return problem.A;
  return with_cfm(compute_A(factor_J(problem), *problem.Minv), problem.cfm);  // (6.2.9)
}

double max_asymmetry(const SpMat& A) {
  if (!A.isCompressed()) return max_asymmetry(SpMat(A));  // the walk below reads compressed columns
  const Eigen::Index n = A.outerSize();
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();  // ascending within each column (Eigen's invariant)
  const double* value = A.valuePtr();
  // next[i]: the first entry of column i not yet matched. Columns are visited in order j = 0, 1,
  // …; an entry (i, j) below the diagonal (i > j) meets its mirror (j, i) in column i, whose rows
  // above the diagonal come up in the same ascending order of j. So each column's upper part is
  // consumed front to back, and what is skipped over had no mirror.
  std::vector<int> next(outer, outer + n);
  double asymmetry = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    int p = next[std::size_t(j)];
    for (; p < outer[j + 1] && inner[p] < j; ++p)  // (r, j), r < j: its mirror (j, r) is absent
      asymmetry = std::max(asymmetry, std::abs(value[p]));
    for (; p < outer[j + 1]; ++p) {
      const int i = inner[p];
      if (i == j) continue;
      int& q = next[std::size_t(i)];
      for (; q < outer[i + 1] && inner[q] < j; ++q)  // column i's upper entries without a mirror
        asymmetry = std::max(asymmetry, std::abs(value[q]));
      if (q < outer[i + 1] && inner[q] == j) {
        asymmetry = std::max(asymmetry, std::abs(value[p] - value[q]));
        ++q;
      } else {
        asymmetry = std::max(asymmetry, std::abs(value[p]));
      }
    }
  }
  return asymmetry;
}

double symmetry_tolerance(const SpMat& A) {
  double largest = 1.0;
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k)
    largest = std::max(largest, std::abs(A.valuePtr()[k]));
  return kSymmetryTolerance * largest;
}

}  // namespace cbps
