// The exact path under MPI (include/cbps/distributed/exact.hpp): the library's interior point and
// crossover on each rank's rows, their Newton systems in body space on PETSc and SuperLU_dist.
//
// Low-rank corrections: the crossover changes the free rows a few at a time, and SuperLU_dist
// has no factor update. A row k joining or leaving changes H by Δω_k J_kᵀ J_k, so for a set of
// changed rows U = [J_kᵀ], C = diag(Δω_k) (Woodbury; as in the Schur-complement updates of
// active-set QP solvers, Gill, Murray, Saunders & Wright, "Sparse matrix methods in optimization",
// SIAM J. Sci. Stat. Comput. 5(3) 1984):
//   (H₀ + U C Uᵀ)⁻¹ g = z₀ − Z S⁻¹ Uᵀ z₀,  z₀ = H₀⁻¹ g,  Z = H₀⁻¹ U,  S = C⁻¹ + Uᵀ Z,
// one solve with the old factor per changed row (kept while the row stays changed) and a small
// dense S on every rank; past kMaxCorrections changed rows H is factored anew.
#include "cbps/distributed/exact.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/solvers/exact/interior_point.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/unit_free.hpp"
#include "petsc_util.hpp"

namespace cbps::distributed {

namespace {

/// Rows changed against the last factorization that low-rank corrections take at most.
constexpr long kMaxCorrections = 64;

/// The body space's work vectors: two laid out as λ's rows, two as the bodies' columns of J.
struct Vectors {
  Vec rows = nullptr;    ///< c entries, this rank's rows
  Vec rows2 = nullptr;   ///< another
  Vec bodies = nullptr;  ///< 6n entries, this rank's bodies
  Vec bodies2 = nullptr;
  ~Vectors() {
    for (Vec* v : {&rows, &rows2, &bodies, &bodies2}) VecDestroy(v);
  }
};

/// Body space on PETSc: (A + diag d)⁻¹ r = D⁻¹ (r − J u), u = H⁻¹ Jᵀ D⁻¹ r, H = M + Jᵀ D⁻¹ J,
/// D = d + cfm, D⁻¹ = 0 on dropped rows; H assembled from each rank's rows of J (ADD_VALUES, the
/// entries of other ranks' bodies sent at assembly) and factored by SuperLU_dist.
class DistributedBodySpace final : public NewtonSystem {
 public:
  DistributedBodySpace(const LocalSystem& local, Mat J, Mat Minv)
      : local_(local), J_(J), Minv_(Minv) {
    CBPS_PETSC_CHECK(MatCreateVecs(J_, &v_.bodies, &v_.rows));
    CBPS_PETSC_CHECK(VecDuplicate(v_.rows, &v_.rows2));
    CBPS_PETSC_CHECK(VecDuplicate(v_.bodies, &v_.bodies2));
    make_H();
  }
  ~DistributedBodySpace() override {
    clear_corrections();
    MatDestroy(&F_);
    MatDestroy(&H_);
  }
  DistributedBodySpace(const DistributedBodySpace&) = delete;
  DistributedBodySpace& operator=(const DistributedBodySpace&) = delete;

  bool factor(const VecX& d, const std::vector<char>& dropped) override {
    VecX omega(d.size());
    for (Eigen::Index k = 0; k < d.size(); ++k)
      omega(k) = dropped[std::size_t(k)] ? 0.0 : 1.0 / (d(k) + local_.cfm);
    if (factored_ && correct(omega)) return true;
    clear_corrections();
    omega_ = omega;
    base_omega_ = omega;
    assemble_H();
    MatFactorInfo info;
    CBPS_PETSC_CHECK(MatFactorInfoInitialize(&info));
    if (F_ == nullptr) {
      // H is symmetric positive definite: no row permutation for stability (SuperLU_dist's
      // default, MC64, would also spoil H's symmetric pattern), unless PETSC_OPTIONS says.
      PetscBool given = PETSC_FALSE;
      CBPS_PETSC_CHECK(PetscOptionsHasName(nullptr, nullptr, "-mat_superlu_dist_rowperm", &given));
      if (!given)
        CBPS_PETSC_CHECK(PetscOptionsSetValue(nullptr, "-mat_superlu_dist_rowperm", "NOROWPERM"));
      CBPS_PETSC_CHECK(MatGetFactor(H_, MATSOLVERSUPERLU_DIST, MAT_FACTOR_LU, &F_));
      IS rows = nullptr, columns = nullptr;
      CBPS_PETSC_CHECK(MatGetOrdering(H_, MATORDERINGNATURAL, &rows, &columns));
      CBPS_PETSC_CHECK(MatLUFactorSymbolic(F_, H_, rows, columns, &info));
      ISDestroy(&rows);
      ISDestroy(&columns);
    }
    CBPS_PETSC_CHECK(MatLUFactorNumeric(F_, H_, &info));
    ++factorizations_;
    MatFactorError error = MAT_FACTOR_NOERROR;
    CBPS_PETSC_CHECK(MatFactorGetError(F_, &error));
    factored_ = MpiReduction().all(error == MAT_FACTOR_NOERROR);
    return factored_;
  }

  void apply(const VecX& r, VecX& x) const override {
    // g = Jᵀ (ω r), u = H⁻¹ g, x = ω (r − J u).
    const VecX wr = omega_.cwiseProduct(r);
    {
      const Placed in(v_.rows, wr);
      CBPS_PETSC_CHECK(MatMultTranspose(J_, v_.rows, v_.bodies));
    }
    CBPS_PETSC_CHECK(MatSolve(F_, v_.bodies, v_.bodies2));
    if (!changed_.empty()) woodbury(v_.bodies2);
    x.resize(r.size());
    {
      const Placed out(v_.rows, x);
      CBPS_PETSC_CHECK(MatMult(J_, v_.bodies2, v_.rows));
    }
    for (Eigen::Index k = 0; k < x.size(); ++k) x(k) = omega_(k) * (r(k) - x(k));
  }

  void times_A(const VecX& x, VecX& y) const override {
    // y = J (Minv (Jᵀ x)) + cfm x.
    {
      const Placed in(v_.rows, x);
      CBPS_PETSC_CHECK(MatMultTranspose(J_, v_.rows, v_.bodies));
    }
    CBPS_PETSC_CHECK(MatMult(Minv_, v_.bodies, v_.bodies2));
    y.resize(x.size());
    {
      const Placed out(v_.rows, y);
      CBPS_PETSC_CHECK(MatMult(J_, v_.bodies2, v_.rows));
    }
    if (local_.cfm != 0.0) y += local_.cfm * x;
  }

  /// SuperLU_dist's factor size is not exposed through PETSc: 0.
  long factor_nonzeros() const override { return 0; }
  int factorizations() const override { return factorizations_; }
  long updates() const override { return updates_; }
  const char* space() const override { return "body"; }

 private:
  /// An Eigen vector's storage lent to a PETSc vector of this rank's rows while in scope.
  struct Placed {
    Placed(Vec v, const VecX& x) : v_(v) { CBPS_PETSC_CHECK(VecPlaceArray(v_, x.data())); }
    ~Placed() { VecResetArray(v_); }
    Placed(const Placed&) = delete;
    Placed& operator=(const Placed&) = delete;
    Vec v_;
  };

  /// A row whose weight differs from the last factorization's: its global index, Δω (kg⁻¹'s
  /// inverse: D⁻¹'s units), z = H₀⁻¹ J_kᵀ.
  struct Changed {
    long row = 0;
    double delta = 0.0;
    Vec z = nullptr;
  };

  /// H's pattern, once: M's 6×6 block of every body and, for every row of J, the entries its
  /// nonzeros couple (J_kᵀ J_k), through PETSc's preallocator so that H is allocated exactly.
  void make_H() {
    PetscInt owned = 0;
    PetscInt columns = 0;
    CBPS_PETSC_CHECK(MatGetLocalSize(J_, nullptr, &owned));
    CBPS_PETSC_CHECK(MatGetSize(J_, nullptr, &columns));
    Mat pattern = nullptr;
    CBPS_PETSC_CHECK(MatCreate(PETSC_COMM_WORLD, &pattern));
    CBPS_PETSC_CHECK(MatSetType(pattern, MATPREALLOCATOR));
    CBPS_PETSC_CHECK(MatSetSizes(pattern, owned, owned, columns, columns));
    CBPS_PETSC_CHECK(MatSetUp(pattern));
    add_entries(pattern, VecX::Ones(local_.rows()), true);
    CBPS_PETSC_CHECK(MatAssemblyBegin(pattern, MAT_FINAL_ASSEMBLY));
    CBPS_PETSC_CHECK(MatAssemblyEnd(pattern, MAT_FINAL_ASSEMBLY));
    CBPS_PETSC_CHECK(MatCreate(PETSC_COMM_WORLD, &H_));
    CBPS_PETSC_CHECK(MatSetSizes(H_, owned, owned, columns, columns));
    CBPS_PETSC_CHECK(MatSetType(H_, MATAIJ));
    CBPS_PETSC_CHECK(MatPreallocatorPreallocate(pattern, PETSC_TRUE, H_));
    MatDestroy(&pattern);
    CBPS_PETSC_CHECK(MatSetOption(H_, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
    CBPS_PETSC_CHECK(MatSetOption(H_, MAT_SYMMETRIC, PETSC_TRUE));  // M ≻ 0, Jᵀ D⁻¹ J ⪰ 0
  }

  /// M's blocks of this rank's bodies and ω_k J_kᵀ J_k of its rows, added into `target`
  /// (every entry of the pattern when `pattern`, with zero weights too).
  void add_entries(Mat target, const VecX& omega, bool pattern) const {
    std::vector<PetscInt> index(6);
    std::vector<PetscScalar> values(36);
    for (long B = 0; B < local_.bodies; ++B) {
      for (int i = 0; i < 6; ++i) index[std::size_t(i)] = PetscInt(6 * (local_.first_body + B) + i);
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) values[std::size_t(6 * i + j)] = local_.M[std::size_t(B)](i, j);
      CBPS_PETSC_CHECK(
          MatSetValues(target, 6, index.data(), 6, index.data(), values.data(), ADD_VALUES));
    }
    const SpMatRow& J = local_.J;
    for (Eigen::Index k = 0; k < J.rows(); ++k) {
      const double w = omega(k);
      if (w == 0.0 && !pattern) continue;
      index.clear();
      std::vector<double> j;
      for (SpMatRow::InnerIterator it(J, k); it; ++it) {
        index.push_back(static_cast<PetscInt>(it.col()));
        j.push_back(it.value());
      }
      const std::size_t m = index.size();
      values.assign(m * m, 0.0);
      for (std::size_t a = 0; a < m; ++a)
        for (std::size_t c = 0; c < m; ++c) values[a * m + c] = w * j[a] * j[c];
      CBPS_PETSC_CHECK(MatSetValues(
          target, PetscInt(m), index.data(), PetscInt(m), index.data(), values.data(), ADD_VALUES));
    }
  }

  void assemble_H() {
    CBPS_PETSC_CHECK(MatZeroEntries(H_));
    add_entries(H_, omega_, false);
    CBPS_PETSC_CHECK(MatAssemblyBegin(H_, MAT_FINAL_ASSEMBLY));
    CBPS_PETSC_CHECK(MatAssemblyEnd(H_, MAT_FINAL_ASSEMBLY));
  }

  void clear_corrections() {
    for (auto& [row, c] : cache_) VecDestroy(&c.z);
    cache_.clear();
    changed_.clear();
  }

  /// The new weights as low-rank corrections of the last factorization, when they differ from
  /// its weights only in rows kept or dropped (ω 0 ↔ ω₀) and few of them (kMaxCorrections):
  /// true, with S factored; false when a factorization is the better way. Collective.
  bool correct(const VecX& omega) {
    std::vector<double> mine;  // (global row, Δω) of this rank's changed rows
    bool weights_kept = true;
    for (Eigen::Index k = 0; k < omega.size(); ++k) {
      if (omega(k) == base_omega_(k)) continue;
      if (omega(k) != 0.0 && base_omega_(k) != 0.0) weights_kept = false;
      mine.push_back(double(local_.first_row + k));
      mine.push_back(omega(k) - base_omega_(k));
    }
    const MpiReduction all;
    const long count = static_cast<long>(all.sum(double(mine.size() / 2)));
    if (!all.all(weights_kept) || count > kMaxCorrections) return false;
    // Every rank learns every changed row, in rank order.
    int size = 1;
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    const int n = static_cast<int>(mine.size());
    std::vector<int> counts(std::size_t(size), 0);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, PETSC_COMM_WORLD);
    std::vector<int> displacements(std::size_t(size), 0);
    for (int r = 1; r < size; ++r)
      displacements[std::size_t(r)] =
          displacements[std::size_t(r - 1)] + counts[std::size_t(r - 1)];
    std::vector<double> every(std::size_t(2 * count));
    MPI_Allgatherv(mine.data(),
                   n,
                   MPI_DOUBLE,
                   every.data(),
                   counts.data(),
                   displacements.data(),
                   MPI_DOUBLE,
                   PETSC_COMM_WORLD);
    std::vector<Changed> changed;
    for (long i = 0; i < count; ++i) {
      const long row = static_cast<long>(every[std::size_t(2 * i)]);
      auto it = cache_.find(row);
      if (it == cache_.end()) {
        it = cache_.emplace(row, Changed{row, 0.0, solve_row(row)}).first;
        ++updates_;
      }
      it->second.delta = every[std::size_t(2 * i + 1)];
      changed.push_back(it->second);
    }
    // S = C⁻¹ + Uᵀ Z: (Uᵀ Z)_ij = (J z_j)_{k_i}, gathered from the rows' ranks.
    const Eigen::Index m = static_cast<Eigen::Index>(changed.size());
    changed_ = std::move(changed);
    omega_ = omega;
    if (m == 0) return true;  // the factored system itself
    const std::vector<Changed>& rows = changed_;
    MatX S(m, m);
    for (Eigen::Index j = 0; j < m; ++j) S.col(j) = rows_of(rows, rows[std::size_t(j)].z);
    S = 0.5 * (S + S.transpose()).eval();  // symmetric in exact arithmetic
    for (Eigen::Index i = 0; i < m; ++i) S(i, i) += 1.0 / rows[std::size_t(i)].delta;
    S_ = Eigen::PartialPivLU<MatX>(S);
    return true;
  }

  /// z = H₀⁻¹ J_kᵀ for the global row `row` (a body vector; the row's rank fills J_kᵀ).
  Vec solve_row(long row) {
    CBPS_PETSC_CHECK(VecSet(v_.bodies, 0.0));
    const long k = row - local_.first_row;
    if (k >= 0 && k < local_.rows()) {
      for (SpMatRow::InnerIterator it(local_.J, k); it; ++it) {
        const PetscInt column = static_cast<PetscInt>(it.col());
        const PetscScalar value = it.value();
        CBPS_PETSC_CHECK(VecSetValues(v_.bodies, 1, &column, &value, INSERT_VALUES));
      }
    }
    CBPS_PETSC_CHECK(VecAssemblyBegin(v_.bodies));
    CBPS_PETSC_CHECK(VecAssemblyEnd(v_.bodies));
    Vec z = nullptr;
    CBPS_PETSC_CHECK(VecDuplicate(v_.bodies, &z));
    CBPS_PETSC_CHECK(MatSolve(F_, v_.bodies, z));
    return z;
  }

  /// (J v)_{k_i} for the changed rows k_i, on every rank.
  VecX rows_of(const std::vector<Changed>& changed, Vec v) const {
    CBPS_PETSC_CHECK(MatMult(J_, v, v_.rows2));
    const PetscScalar* values = nullptr;
    CBPS_PETSC_CHECK(VecGetArrayRead(v_.rows2, &values));
    VecX mine = VecX::Zero(static_cast<Eigen::Index>(changed.size()));
    for (std::size_t i = 0; i < changed.size(); ++i) {
      const long k = changed[i].row - local_.first_row;
      if (k >= 0 && k < local_.rows()) mine(Eigen::Index(i)) = values[k];
    }
    CBPS_PETSC_CHECK(VecRestoreArrayRead(v_.rows2, &values));
    VecX every(mine.size());
    MPI_Allreduce(mine.data(),
                  every.data(),
                  static_cast<int>(mine.size()),
                  MPI_DOUBLE,
                  MPI_SUM,
                  PETSC_COMM_WORLD);
    return every;
  }

  /// u ← u − Z S⁻¹ Uᵀ u: H₀⁻¹ g corrected to (H₀ + U C Uᵀ)⁻¹ g.
  void woodbury(Vec u) const {
    const VecX t = S_.solve(rows_of(changed_, u));
    for (std::size_t j = 0; j < changed_.size(); ++j)
      CBPS_PETSC_CHECK(VecAXPY(u, -t(Eigen::Index(j)), changed_[j].z));
  }

  const LocalSystem& local_;
  Mat J_;
  Mat Minv_;
  Mat H_ = nullptr;
  Mat F_ = nullptr;
  mutable Vectors v_;
  VecX omega_;       ///< D⁻¹ of the current system, this rank's rows
  VecX base_omega_;  ///< D⁻¹ of the last factorization
  bool factored_ = false;
  int factorizations_ = 0;
  long updates_ = 0;
  std::map<long, Changed> cache_;  ///< z of every row corrected since the last factorization
  std::vector<Changed> changed_;   ///< the rows the current system corrects
  Eigen::PartialPivLU<MatX> S_;
};

/// A copy of a rank's rows with every entry's absolute value.
SpMatRow absolute(const SpMatRow& m) {
  SpMatRow a = m;
  for (Eigen::Index k = 0; k < a.nonZeros(); ++k) a.valuePtr()[k] = std::abs(a.valuePtr()[k]);
  return a;
}

/// The whole of a vector laid out as J's rows (this rank's `mine`) on rank 0, empty elsewhere.
/// Collective.
VecX gather_rows(Mat J, const VecX& mine) {
  Vec v = nullptr;
  CBPS_PETSC_CHECK(MatCreateVecs(J, nullptr, &v));
  CBPS_PETSC_CHECK(VecPlaceArray(v, mine.data()));
  VecX whole = gather_vector(v);
  CBPS_PETSC_CHECK(VecResetArray(v));
  VecDestroy(&v);
  return whole;
}

}  // namespace

FactorsGap factors_gap_across_ranks(const LocalSystem& local) {
  const long c = local.total_rows;
  const long columns = local.total_columns;
  const VecX x = factors_test_vector(0, c);
  const VecX mine = x.segment(local.first_row, local.rows());
  // Jᵀ x summed over the ranks' rows; Minv (Jᵀ x) from each rank's bodies' rows, summed.
  VecX Jt_x = VecX::Zero(columns);
  VecX Jt_x_mine = local.J.transpose() * mine;
  MPI_Allreduce(Jt_x_mine.data(), Jt_x.data(), int(columns), MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  VecX Minv_y_mine = VecX::Zero(columns);
  Minv_y_mine.segment(6 * local.first_body, 6 * local.bodies) = local.Minv * Jt_x;
  VecX Minv_y = VecX::Zero(columns);
  MPI_Allreduce(
      Minv_y_mine.data(), Minv_y.data(), int(columns), MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  const VecX factors_x = local.J * Minv_y + local.cfm * mine;  // J Minv Jᵀ x + cfm x (6.2.9)
  const FactorsGap gap = factors_gap(SpMat(local.A), x, factors_x);
  const MpiReduction all;
  return FactorsGap{all.max(gap.difference), all.max(gap.size)};
}

namespace {

/// A_kk = J_k Minv J_kᵀ (+ cfm) of this rank's rows into `diagonal`, from the rows of J Minv;
/// returns max_i Σ_k |A_ik| bounded above by (|J Minv| |J|ᵀ 1)_i (+ cfm), for the rounding floor.
/// Collective.
double diagonal_and_row_sum(const LocalSystem& local, Mat J, Mat Minv, VecX& diagonal) {
  const long columns = local.total_columns;
  const long column_begin = 6 * local.first_body;
  const long owned_columns = 6 * local.bodies;
  diagonal = VecX::Zero(local.rows());
  double row_sum = 0.0;
  Mat JMinv = nullptr;
  CBPS_PETSC_CHECK(MatMatMult(J, Minv, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &JMinv));
  std::vector<Triplet> absolute_JMinv;
  for (Eigen::Index k = 0; k < local.J.rows(); ++k) {
    PetscInt count = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* values = nullptr;
    const PetscInt row = static_cast<PetscInt>(local.first_row + k);
    CBPS_PETSC_CHECK(MatGetRow(JMinv, row, &count, &cols, &values));
    for (PetscInt e = 0; e < count; ++e) {
      diagonal(k) += values[e] * local.J.coeff(k, cols[e]);
      absolute_JMinv.emplace_back(int(k), int(cols[e]), std::abs(values[e]));
    }
    CBPS_PETSC_CHECK(MatRestoreRow(JMinv, row, &count, &cols, &values));
    diagonal(k) += local.cfm;
  }
  MatDestroy(&JMinv);
  SpMatRow rows_abs(local.J.rows(), columns);
  rows_abs.setFromTriplets(absolute_JMinv.begin(), absolute_JMinv.end());
  Mat absJMinv = matrix_from_rows(rows_abs, columns, column_begin, owned_columns);
  Mat absJ = matrix_from_rows(absolute(local.J), columns, column_begin, owned_columns);
  Vec ones = nullptr, body = nullptr, sums = nullptr;
  CBPS_PETSC_CHECK(MatCreateVecs(absJ, &body, &ones));
  CBPS_PETSC_CHECK(VecDuplicate(ones, &sums));
  CBPS_PETSC_CHECK(VecSet(ones, 1.0));
  CBPS_PETSC_CHECK(MatMultTranspose(absJ, ones, body));
  CBPS_PETSC_CHECK(MatMult(absJMinv, body, sums));
  PetscReal largest = 0.0;
  CBPS_PETSC_CHECK(VecNorm(sums, NORM_INFINITY, &largest));
  row_sum = static_cast<double>(largest) + local.cfm;
  for (Vec* v : {&ones, &body, &sums}) VecDestroy(v);
  MatDestroy(&absJ);
  MatDestroy(&absJMinv);
  return row_sum;
}

}  // namespace

DirectResult solve_direct_local(const MpiSession& session,
                                LocalSystem& local,
                                const SolverOptions& options,
                                bool gather) {
  DirectResult r;
  r.local_rows = local.rows();
  r.local_bodies = local.bodies;
  const long columns = local.total_columns;
  const long column_begin = 6 * local.first_body;
  const long owned_columns = 6 * local.bodies;
  Mat J = matrix_from_rows(local.J, columns, column_begin, owned_columns);
  Mat Minv = matrix_from_rows(local.Minv, columns, column_begin, owned_columns);
  const MpiReduction all;
  if (gather) {
    r.gathered.J = gather_matrix(J);
    r.gathered.Minv = gather_matrix(Minv);
    r.gathered.b = gather_rows(J, local.b);
    r.gathered.cmin = gather_rows(J, local.cmin);
    r.gathered.cmax = gather_rows(J, local.cmax);
  }

  // A_kk, the rounding floor's row sum; scale_of = max(1, ‖b‖∞, max A_kk).
  VecX diagonal;
  const double row_sum = diagonal_and_row_sum(local, J, Minv, diagonal);
  const double b_norm = all.max(local.b.size() > 0 ? local.b.lpNorm<Eigen::Infinity>() : 0.0);
  const double largest_diagonal = all.max(diagonal.size() > 0 ? diagonal.maxCoeff() : 0.0);
  r.scale = std::max({1.0, b_norm, largest_diagonal});
  const InteriorRows rows{local.b, local.cmin, local.cmax, diagonal, r.scale, row_sum};
  // The tolerance read in N and as a unit-free residual, as on one process (solvers/solver.cpp,
  // UnitFreeTarget::both at λ = 0), from every rank's rows.
  UnitFreeTarget target = unit_free_target_rows(local.b, diagonal, largest_diagonal);
  target.rho_b = all.max(target.rho_b);
  target.rho_max = all.max(target.rho_max);
  SolverOptions aimed = options;
  aimed.tolerance = target.both(options.tolerance, VecX());

  VecX lambda = VecX::Zero(local.rows());
  {
    DistributedBodySpace newton(local, J, Minv);
    const InteriorOutcome interior = run_interior_point(rows, newton, all, aimed, lambda);
    r.iterations = interior.iterations;
    r.solved = interior.solved;
    if (!r.solved) {
      const CrossoverOutcome x = bulk_crossover(rows, newton, all, aimed, interior.place, lambda);
      r.solved = x.solved;
      r.crossover = x.rounds;
      r.solves = x.steps;
      r.moved = x.moved;
    }
    // The residual of the answer returned, formed afresh.
    VecX w;
    newton.times_A(lambda, w);
    w -= local.b;
    r.residual = all.max(natural_map_residual(w, lambda, local.cmin, local.cmax));
    const UnitFreeResidual mine =
        unit_free_rows(w, lambda, local.b, local.cmin, local.cmax, diagonal, largest_diagonal);
    r.unit_free = unit_free_of(all.max(mine.residual), all.max(mine.scale));
    r.reductions = all.calls();
    r.factorizations = newton.factorizations();
    r.updates = newton.updates();
  }
  r.lambda = gather_rows(J, lambda);
  MatDestroy(&J);
  MatDestroy(&Minv);
  std::ostringstream msg;
  msg << "direct under MPI (interior point, body space M + Jt D^-1 J on SuperLU_dist across "
      << session.size() << (session.size() == 1 ? " rank" : " ranks") << "): " << r.iterations
      << " interior iterations, crossover " << r.crossover << " proximal steps and " << r.solves
      << " solves moving " << r.moved << " rows, " << r.factorizations << " factorizations and "
      << r.updates << " rows corrected by low-rank updates, residual " << r.residual << " N";
  if (!r.solved) msg << "; stopped short of the tolerance";
  r.message = msg.str();
  return r;
}

}  // namespace cbps::distributed
