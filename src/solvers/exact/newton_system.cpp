// The Newton matrices of the exact path (newton_system.hpp): body space by the Woodbury
// identity, row space on A + diag(d), both on CHOLMOD through cholmod_factor.hpp.
#include "newton_system.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "cbps/solvers/exact/cholmod_factor.hpp"
#include "cbps/solvers/islands.hpp"

namespace cbps {

namespace {

/// Body space updates its factor (instead of factoring anew) when at most
/// max(kUpdateRows, rows / kUpdateFraction) rows join or leave, and factors anew once
/// kUpdateRefresh times that many have changed since the last factorization (round-off).
constexpr long kUpdateRows = 64;
constexpr long kUpdateFraction = 50;
constexpr long kUpdateRefresh = 4;
/// ExactMemory keeps the body spaces of this many patterns.
constexpr std::size_t kKeptBodySpaces = 2;

/// Body space: (J Minv Jᵀ + diag D)⁻¹ r = D⁻¹ (r − J u), u = (M + Jᵀ D⁻¹ J)⁻¹ Jᵀ D⁻¹ r
/// (Woodbury), D = d + cfm; D⁻¹ = 0 on dropped rows. H = M + Jᵀ D⁻¹ J keeps one pattern (its
/// lower triangle), assembled here from precomputed positions, so CHOLMOD analyses it once.
class BodySpace final : public NewtonSystem {
 public:
  BodySpace(const BoxedProblem& problem, std::vector<Mat6> M)
      : J_(problem.J),
        Minv_(problem.Minv),
        cfm_(problem.cfm),
        M_(std::move(M)),
        j_outer_(J_->outerIndexPtr(), J_->outerIndexPtr() + J_->rows() + 1),
        j_inner_(J_->innerIndexPtr(), J_->innerIndexPtr() + J_->nonZeros()) {
    form_pattern();
  }

  /// True when the problem's J has the pattern this body space was made for (the same rows,
  /// columns and nonzero positions): then H keeps its pattern and CHOLMOD its analysis.
  bool same_pattern(const BoxedProblem& problem) const {
    const SpMatRow& J = *problem.J;
    if (J.cols() != static_cast<Eigen::Index>(6 * M_.size()) ||
        J.rows() + 1 != static_cast<Eigen::Index>(j_outer_.size()) ||
        J.nonZeros() != static_cast<Eigen::Index>(j_inner_.size()))
      return false;
    return std::equal(j_outer_.begin(), j_outer_.end(), J.outerIndexPtr()) &&
           std::equal(j_inner_.begin(), j_inner_.end(), J.innerIndexPtr());
  }

  /// This body space for another problem of the same pattern (same_pattern): its J, Minv, M and
  /// cfm, nothing factored yet, the counts from zero; the pattern and its analysis are kept.
  void rebind(const BoxedProblem& problem, std::vector<Mat6> M) {
    J_ = problem.J;
    Minv_ = problem.Minv;
    cfm_ = problem.cfm;
    M_ = std::move(M);
    factored_ = false;
    factorizations_ = 0;
    updates_ = 0;
    updated_rows_ = 0;
  }

  bool factor(const VecX& d, const std::vector<char>& dropped) override {
    VecX omega(d.size());
    for (Eigen::Index k = 0; k < d.size(); ++k)
      omega(k) = dropped[std::size_t(k)] ? 0.0 : 1.0 / (d(k) + cfm_);
    if (factored_ && update(omega)) return true;
    omega_ = std::move(omega);
    double* value = H_.valuePtr();
    std::fill(value, value + H_.nonZeros(), 0.0);
    for (std::size_t B = 0; B < M_.size(); ++B) {
      const int* pos = &m_position_[21 * B];
      int p = 0;
      for (int j = 0; j < 6; ++j)
        for (int i = j; i < 6; ++i) value[pos[p++]] += M_[B](i, j);
    }
    const SpMatRow& J = *J_;
    for (Eigen::Index k = 0; k < J.rows(); ++k) {
      const double w = omega_(k);
      if (w == 0.0) continue;
      const int begin = J.outerIndexPtr()[k], end = J.outerIndexPtr()[k + 1];
      const double* Jv = J.valuePtr();
      const int* pos = &j_position_[std::size_t(j_start_[std::size_t(k)])];
      for (int a = begin; a < end; ++a) {
        const double wa = w * Jv[a];
        for (int c = a; c < end; ++c) value[*pos++] += wa * Jv[c];
      }
    }
    ++factorizations_;
    factored_ = analysed_ ? factor_.refactor(H_, 0.0) : factor_.factor(H_, 0.0);
    analysed_ = true;
    updated_rows_ = 0;
    return factored_;
  }

  int factorizations() const override { return factorizations_; }
  long updates() const override { return updates_; }

  /// x = Ω (r − J H⁻¹ Jᵀ Ω r), Ω = D⁻¹ (0 on dropped rows): (A + D)⁻¹ r on the kept rows by
  /// the Woodbury identity. Rows with Ω r = 0 (the bound rows of a crossover round, the
  /// dropped ones) are skipped in Jᵀ; dropped rows are skipped in J.
  void apply(const VecX& r, VecX& x) const override {
    const SpMatRow& J = *J_;
    const int* outer = J.outerIndexPtr();
    const int* inner = J.innerIndexPtr();
    const double* value = J.valuePtr();
    VecX g = VecX::Zero(J.cols());
    for (Eigen::Index k = 0; k < J.rows(); ++k) {
      const double wr = omega_(k) * r(k);
      if (wr == 0.0) continue;
      for (int a = outer[k]; a < outer[k + 1]; ++a) g(inner[a]) += value[a] * wr;
    }
    VecX u;
    factor_.solve(g, u);
    x.resize(J.rows());
    for (Eigen::Index k = 0; k < J.rows(); ++k) {
      const double w = omega_(k);
      if (w == 0.0) {
        x(k) = 0.0;
        continue;
      }
      double Ju = 0.0;
      for (int a = outer[k]; a < outer[k + 1]; ++a) Ju += value[a] * u(inner[a]);
      x(k) = w * (r(k) - Ju);
    }
  }

  void times_A(const VecX& x, VecX& y) const override { y = times_factors(*J_, *Minv_, cfm_, x); }

  long factor_nonzeros() const override { return factor_.nonzeros(); }
  const char* space() const override { return "body"; }

 private:
  /// H for the new weights from the current factor, when they differ from the old only in rows
  /// kept or dropped (ω 0 ↔ ω_k) and there are few of those: H ± ω_k J_kᵀ J_k as rank-one
  /// updates and downdates. False when a factorization is the better way (or an update
  /// failed: then the caller factors anew).
  bool update(const VecX& omega) {
    std::vector<Eigen::Index> added, removed;
    for (Eigen::Index k = 0; k < omega.size(); ++k) {
      if (omega(k) == omega_(k)) continue;
      if (omega_(k) == 0.0)
        added.push_back(k);
      else if (omega(k) == 0.0)
        removed.push_back(k);
      else
        return false;  // a weight changed: a new H
    }
    const long changed = static_cast<long>(added.size() + removed.size());
    if (changed == 0) return true;
    const long limit = std::max(kUpdateRows, static_cast<long>(omega.size()) / kUpdateFraction);
    if (changed > limit || updated_rows_ + changed > kUpdateRefresh * limit) return false;
    const auto columns = [&](const std::vector<Eigen::Index>& rows, const VecX& weight) {
      std::vector<Eigen::Triplet<double>> entries;
      for (std::size_t q = 0; q < rows.size(); ++q) {
        const Eigen::Index k = rows[q];
        const double root = std::sqrt(weight(k));
        for (SpMatRow::InnerIterator it(*J_, k); it; ++it)
          entries.emplace_back(it.col(), static_cast<Eigen::Index>(q), root * it.value());
      }
      SpMat C(J_->cols(), static_cast<Eigen::Index>(rows.size()));
      C.setFromTriplets(entries.begin(), entries.end());
      return C;
    };
    // Updates first: H stays definite through the downdates that follow.
    if (!added.empty() && !factor_.update(columns(added, omega), true)) return factored_ = false;
    if (!removed.empty() && !factor_.update(columns(removed, omega_), false))
      return factored_ = false;
    omega_ = omega;
    updates_ += changed;
    updated_rows_ += changed;
    return true;
  }

  /// H's lower pattern and where each M block and each pair of J's entries adds into it.
  void form_pattern() {
    factor_.set_simplicial(true);
    // The lower triangle's pattern: every M block, and every pair of columns a row of J joins.
    const SpMatRow& J = *J_;
    const Eigen::Index n6 = J.cols();
    std::vector<Eigen::Triplet<double>> entries;
    for (Eigen::Index B = 0; B < n6 / 6; ++B)
      for (int j = 0; j < 6; ++j)
        for (int i = j; i < 6; ++i) entries.emplace_back(6 * B + i, 6 * B + j, 1.0);
    for (Eigen::Index k = 0; k < J.rows(); ++k) {
      for (SpMatRow::InnerIterator a(J, k); a; ++a)
        for (SpMatRow::InnerIterator c = a; c; ++c)
          entries.emplace_back(std::max(a.col(), c.col()), std::min(a.col(), c.col()), 1.0);
    }
    H_.resize(n6, n6);
    H_.setFromTriplets(entries.begin(), entries.end());
    H_.makeCompressed();
    const auto position = [&](Eigen::Index row, Eigen::Index col) {
      const int* inner = H_.innerIndexPtr();
      const int* first = inner + H_.outerIndexPtr()[col];
      const int* last = inner + H_.outerIndexPtr()[col + 1];
      return static_cast<int>(std::lower_bound(first, last, static_cast<int>(row)) - inner);
    };
    m_position_.reserve(21 * M_.size());
    for (Eigen::Index B = 0; B < n6 / 6; ++B)
      for (int j = 0; j < 6; ++j)
        for (int i = j; i < 6; ++i) m_position_.push_back(position(6 * B + i, 6 * B + j));
    j_start_.reserve(static_cast<std::size_t>(J.rows()));
    for (Eigen::Index k = 0; k < J.rows(); ++k) {
      j_start_.push_back(static_cast<long>(j_position_.size()));
      for (SpMatRow::InnerIterator a(J, k); a; ++a)
        for (SpMatRow::InnerIterator c = a; c; ++c)
          j_position_.push_back(position(std::max(a.col(), c.col()), std::min(a.col(), c.col())));
    }
  }

  const SpMatRow* J_;
  const SpMat* Minv_;
  double cfm_;
  std::vector<Mat6> M_;
  std::vector<int> j_outer_;  ///< J's pattern (outer and inner indices), for same_pattern
  std::vector<int> j_inner_;
  SpMat H_;                      ///< lower triangle of M + Jᵀ D⁻¹ J
  std::vector<int> m_position_;  ///< where each M block's lower entries sit in H_'s values
  std::vector<long> j_start_;    ///< row k's pairs start here in j_position_
  std::vector<int> j_position_;  ///< where each pair (a ≤ c) of row k's entries sits in H_
  VecX omega_;                   ///< D⁻¹, 0 on dropped rows, of the current factor
  CholmodFactor factor_;
  bool analysed_ = false;
  bool factored_ = false;  ///< factor_ holds H for omega_
  int factorizations_ = 0;
  long updates_ = 0;       ///< rows added or removed by updates, in all
  long updated_rows_ = 0;  ///< … since the last factorization
};

/// Row space: CHOLMOD on A + diag(d), dropped rows given a diagonal so large that they
/// decouple (x_k set to 0 after the solve): one pattern, one analysis.
class RowSpace final : public NewtonSystem {
 public:
  explicit RowSpace(const SpMat& A) : A_(&A) {
    K_ = A;
    SpMat I(A.rows(), A.cols());
    I.setIdentity();
    K_ = K_ + I;  // the diagonal in the pattern, whatever A holds there
    K_.makeCompressed();
    diagonal_.resize(static_cast<std::size_t>(A.rows()));
    double max_diagonal = 0.0;
    for (Eigen::Index j = 0; j < K_.cols(); ++j) {
      for (SpMat::InnerIterator it(K_, j); it; ++it)
        if (it.row() == j) diagonal_[std::size_t(j)] = &it.valueRef();
    }
    a_diagonal_ = A.diagonal();
    for (Eigen::Index k = 0; k < A.rows(); ++k)
      max_diagonal = std::max(max_diagonal, a_diagonal_(k));
    big_ = 1e30 * std::max(1.0, max_diagonal);
  }

  bool factor(const VecX& d, const std::vector<char>& dropped) override {
    dropped_ = &dropped;
    for (Eigen::Index k = 0; k < d.size(); ++k)
      *diagonal_[std::size_t(k)] = a_diagonal_(k) + (dropped[std::size_t(k)] ? big_ : d(k));
    ++factorizations_;
    const bool ok = analysed_ ? factor_.refactor(K_, 0.0) : factor_.factor(K_, 0.0);
    analysed_ = true;
    return ok;
  }

  int factorizations() const override { return factorizations_; }

  void apply(const VecX& r, VecX& x) const override {
    factor_.solve(r, x);
    for (Eigen::Index k = 0; k < x.size(); ++k)
      if ((*dropped_)[std::size_t(k)]) x(k) = 0.0;
  }

  void times_A(const VecX& x, VecX& y) const override { y = *A_ * x; }

  long factor_nonzeros() const override { return factor_.nonzeros(); }
  const char* space() const override { return "row"; }

 private:
  const SpMat* A_;
  SpMat K_;
  std::vector<double*> diagonal_;
  VecX a_diagonal_;
  double big_ = 0.0;
  const std::vector<char>* dropped_ = nullptr;
  CholmodFactor factor_;
  bool analysed_ = false;
  int factorizations_ = 0;
};

}  // namespace

bool NewtonSystem::solve(const VecX& d,
                         const std::vector<char>& dropped,
                         const VecX& r,
                         VecX& x,
                         int refinements) const {
  apply(r, x);
  VecX res, dx, Ax;
  for (int pass = 0; pass < refinements; ++pass) {
    times_A(x, Ax);
    res = r - Ax - d.cwiseProduct(x);
    for (Eigen::Index k = 0; k < res.size(); ++k)
      if (dropped[std::size_t(k)]) res(k) = 0.0;
    apply(res, dx);
    x += dx;
  }
  return x.allFinite();
}

bool check_input(const BoxedProblem& problem, const char* who, SolverSummary& s) {
  const SpMat& A = problem.A;
  const Eigen::Index n = problem.rows();
  if ((problem.A_formed() ? A.cols() != n : !problem.has_factors() || problem.J->rows() != n) ||
      problem.cmin.size() != n || problem.cmax.size() != n) {
    throw std::invalid_argument(std::string(who) + ": A (or J), b, cmin and cmax sizes differ");
  }
  std::ostringstream msg;
  msg << who << ": ";
  const auto non_finite = [&](const std::string& what) {
    s.termination = Termination::NonFinite;
    s.residual = std::numeric_limits<double>::quiet_NaN();
    msg << what;
    s.message = msg.str();
    return false;
  };
  const auto finite = [](const auto& M) {
    return Eigen::Map<const VecX>(M.valuePtr(), M.nonZeros()).allFinite();
  };
  if (!problem.b.allFinite() ||
      !(problem.A_formed() ? finite(A) : finite(*problem.J) && finite(*problem.Minv)))
    return non_finite(problem.A_formed() ? "A or b has non-finite entries"
                                         : "J, Minv or b has non-finite entries");
  Eigen::Index empty = -1;
  double gap = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double lo = problem.cmin(k), hi = problem.cmax(k);
    if (std::isnan(lo) || std::isnan(hi))
      return non_finite("row " + std::to_string(k) + ": cmin or cmax is NaN");
    if (lo > hi) {
      if (empty < 0) empty = k;
      gap = std::max(gap, lo - hi);
    }
  }
  if (empty < 0) return true;
  s.termination = Termination::NotConverged;
  s.residual = gap;
  msg << "row " << empty << ": cmin " << problem.cmin(empty) << " > cmax " << problem.cmax(empty)
      << ": no lambda is feasible (residual: the largest cmin - cmax, N)";
  s.message = msg.str();
  return false;
}

SolverSummary solve_around_null_rows(
    const BoxedProblem& problem,
    VecX& lambda,
    const std::function<SolverSummary(const BoxedProblem&, VecX&)>& solve_rest) {
  const SpMat& A = problem.A;
  const Eigen::Index n = problem.rows();
  std::vector<int> rest;
  std::vector<int> null;
  if (problem.A_formed()) {
    for (Eigen::Index k = 0; k < n; ++k) {
      bool coupled = false;
      for (SpMat::InnerIterator it(A, k); it && !coupled; ++it) coupled = it.value() != 0.0;
      (coupled ? rest : null).push_back(static_cast<int>(k));
    }
  } else {
    // A = J Minv Jᵀ + cfm E left out: positive semidefinite, so row k is null when A_kk = 0.
    const VecX diagonal = diagonal_of_A(problem);
    for (Eigen::Index k = 0; k < n; ++k)
      (diagonal(k) != 0.0 ? rest : null).push_back(static_cast<int>(k));
  }
  if (null.empty()) return solve_rest(problem, lambda);
  const auto start = std::chrono::steady_clock::now();
  if (lambda.size() != n) lambda = VecX::Zero(n);
  // A null row k (A_kk = 0: its j_c acts on nothing) has w_k = (A lambda)_k − b_k = −b_k whatever
  // lambda is, so the boxed LCP of 6.2 decides lambda_k by b_k and its bounds alone: b_k > 0
  // (w_k < 0) needs lambda_k = cmax_k, b_k < 0 needs cmin_k, b_k = 0 allows any point of the box
  // (the point nearest 0 is taken). A needed bound that is infinite has no solution: the row
  // keeps the box's point nearest 0 and its residual, |b_k|, shows it (NotConverged).
  Eigen::Index infeasible = -1;
  for (const int k : null) {
    const double b = problem.b(k), lo = problem.cmin(k), hi = problem.cmax(k);
    double value = clamp(0.0, lo, hi);
    if (lo == hi) {
      value = lo;  // a fixed row: w_k is free
    } else if (b > 0.0) {
      if (std::isfinite(hi))
        value = hi;
      else if (infeasible < 0)
        infeasible = k;
    } else if (b < 0.0) {
      if (std::isfinite(lo))
        value = lo;
      else if (infeasible < 0)
        infeasible = k;
    }
    lambda(k) = value;
  }
  // The other rows never meet the null ones in A (their entries there are 0): solved as they are,
  // with J's rows of their own when J is given (J_R Minv J_Rᵀ = A(R, R)), so body space stays.
  SolverSummary s;
  s.termination = Termination::Direct;
  if (!rest.empty()) {
    std::vector<int> local(static_cast<std::size_t>(A.rows()), -1);
    const SpMat A_R = problem.A_formed() ? principal_submatrix(A, rest, local) : SpMat();
    const VecX b_R = gather_rows(problem.b, rest);
    const VecX cmin_R = gather_rows(problem.cmin, rest);
    const VecX cmax_R = gather_rows(problem.cmax, rest);
    BoxedProblem reduced{A_R, b_R, cmin_R, cmax_R};
    reduced.cfm = problem.cfm;
    SpMatRow J_R;
    if (problem.J != nullptr) {
      J_R = select_rows(*problem.J, rest);
      reduced.J = &J_R;
      reduced.Minv = problem.Minv;
    }
    VecX lambda_R = gather_rows(lambda, rest);
    s = solve_rest(reduced, lambda_R);
    for (std::size_t r = 0; r < rest.size(); ++r) lambda(rest[r]) = lambda_R(Eigen::Index(r));
  }
  s.residual = natural_map_residual(problem, lambda);
  if (!std::isfinite(s.residual)) {
    s.termination = Termination::NonFinite;
  } else if (infeasible >= 0) {
    s.termination = Termination::NotConverged;
  }
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ostringstream msg;
  if (!s.message.empty()) msg << s.message << "; ";
  msg << null.size() << " row" << (null.size() == 1 ? "" : "s")
      << " with no entry in A (j_c = 0: w_k = -b_k) set from b_k and the bounds";
  if (infeasible >= 0) {
    msg << "; row " << infeasible << " has no solution: b = " << problem.b(infeasible)
        << " needs lambda at " << (problem.b(infeasible) > 0.0 ? "cmax" : "cmin")
        << ", which is infinite";
  }
  msg << "; residual " << s.residual << " N";
  s.message = msg.str();
  return s;
}

bool body_mass(const Mat6& Minv_block, Mat6& M_block) {
  const Eigen::LLT<Mat6> llt(Minv_block);
  if (llt.info() != Eigen::Success || !Minv_block.isApprox(Minv_block.transpose(), 1e-12))
    return false;
  const Mat6 inverse = llt.solve(Mat6::Identity());
  M_block = 0.5 * (inverse + inverse.transpose());
  return true;
}

std::optional<std::vector<Mat6>> body_masses(const BoxedProblem& problem) {
  if (!problem.has_factors()) return std::nullopt;
  const SpMat& Minv = *problem.Minv;
  const Eigen::Index n6 = Minv.rows();
  if (n6 % 6 != 0 || Minv.cols() != n6 || problem.J->cols() != n6) return std::nullopt;
  std::vector<Mat6> M(static_cast<std::size_t>(n6 / 6), Mat6::Zero());
  for (Eigen::Index j = 0; j < n6; ++j) {
    for (SpMat::InnerIterator it(Minv, j); it; ++it) {
      if (it.row() / 6 != j / 6) {
        if (it.value() != 0.0) return std::nullopt;  // not block diagonal
        continue;
      }
      M[std::size_t(j / 6)](it.row() % 6, j % 6) = it.value();
    }
  }
  for (Mat6& block : M)  // M = Minv⁻¹, block by block
    if (!body_mass(block, block)) return std::nullopt;
  // A = J Minv Jᵀ + cfm I is the contract of BoxedProblem; a stored folder whose A says
  // otherwise is solved in row space, on its A.
  if (!(factors_mismatch(problem) <= kFactorsTolerance)) return std::nullopt;
  return M;
}

/// The body spaces of the latest solves, the most recent last: at most kKeptBodySpaces (the
/// improved push's velocity and position systems take turns, 8.1).
struct ExactMemory {
  std::vector<std::shared_ptr<BodySpace>> body;
};

std::shared_ptr<ExactMemory> make_exact_memory() { return std::make_shared<ExactMemory>(); }

std::shared_ptr<NewtonSystem> make_body_space(const BoxedProblem& problem, ExactMemory* memory) {
  if (!problem.has_factors()) return nullptr;
  std::optional<std::vector<Mat6>> M = body_masses(problem);
  if (!M) return nullptr;
  if (memory == nullptr) return std::make_shared<BodySpace>(problem, std::move(*M));
  auto& kept = memory->body;
  for (auto it = kept.begin(); it != kept.end(); ++it) {
    if (!(*it)->same_pattern(problem)) continue;
    std::shared_ptr<BodySpace> found = *it;
    found->rebind(problem, std::move(*M));
    kept.erase(it);
    kept.push_back(found);
    return found;
  }
  kept.push_back(std::make_shared<BodySpace>(problem, std::move(*M)));
  if (kept.size() > kKeptBodySpaces) kept.erase(kept.begin());
  return kept.back();
}

std::shared_ptr<NewtonSystem> make_newton_system(const BoxedProblem& problem, ExactMemory* memory) {
  std::shared_ptr<NewtonSystem> system = make_body_space(problem, memory);
  if (!system && !problem.A_formed())
    throw std::logic_error("make_newton_system: A left out, and J and Minv allow no body space");
  if (!system) system = std::make_shared<RowSpace>(problem.A);
  return system;
}

}  // namespace cbps
