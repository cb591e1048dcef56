// Independent blocks of A (islands), found by union-find over A's graph, and their sub-problems.
#include "cbps/solvers/islands.hpp"

#include <algorithm>
#include <numeric>

namespace cbps {

SpMat principal_submatrix(const SpMat& A, const std::vector<int>& idx, std::vector<int>& local) {
  for (std::size_t k = 0; k < idx.size(); ++k) local[static_cast<std::size_t>(idx[k])] = int(k);
  const auto m = static_cast<Eigen::Index>(idx.size());
  SpMat S(m, m);
  Eigen::Index nnz = 0;
  for (const int j : idx) {
    for (SpMat::InnerIterator it(A, j); it; ++it) nnz += local[std::size_t(it.row())] >= 0;
  }
  S.resizeNonZeros(nnz);
  auto* outer = S.outerIndexPtr();
  auto* inner = S.innerIndexPtr();
  auto* value = S.valuePtr();
  Eigen::Index pos = 0;
  for (Eigen::Index k = 0; k < m; ++k) {
    outer[k] = static_cast<int>(pos);
    for (SpMat::InnerIterator it(A, idx[static_cast<std::size_t>(k)]); it; ++it) {
      const int r = local[static_cast<std::size_t>(it.row())];
      if (r < 0) continue;  // rows ascend in A, and idx is sorted, so r ascends too
      inner[pos] = r;
      value[pos] = it.value();
      ++pos;
    }
  }
  outer[m] = static_cast<int>(pos);
  for (const int i : idx) local[static_cast<std::size_t>(i)] = -1;
  return S;
}

VecX gather_rows(const VecX& v, const std::vector<int>& idx) {
  VecX out(static_cast<Eigen::Index>(idx.size()));
  for (std::size_t k = 0; k < idx.size(); ++k) out(Eigen::Index(k)) = v(idx[k]);
  return out;
}

void for_each_island(const std::vector<std::vector<int>>& islands,
                     const BoxedProblem& problem,
                     VecX& lambda,
                     const IslandSolve& solve_island) {
  const SpMat& A = problem.A;
  const bool formed = problem.A_formed();
  std::vector<int> local(static_cast<std::size_t>(A.rows()), -1);
  std::vector<int> blocks_I;
  std::vector<RowKind> kinds_I;
  for (const auto& rows : islands) {
    if (static_cast<Eigen::Index>(rows.size()) == problem.rows()) {
      solve_island(problem, lambda);
      continue;
    }
    // A left out: the island's A is J_I Minv J_Iᵀ (+ cfm E), J_I its rows of J.
    const SpMat A_I = formed ? principal_submatrix(A, rows, local) : SpMat();
    const SpMatRow J_I = formed ? SpMatRow() : select_rows(*problem.J, rows);
    const VecX b_I = gather_rows(problem.b, rows);
    const VecX cmin_I = gather_rows(problem.cmin, rows);
    const VecX cmax_I = gather_rows(problem.cmax, rows);
    BoxedProblem island{A_I, b_I, cmin_I, cmax_I};
    if (!formed) {
      island.J = &J_I;
      island.Minv = problem.Minv;
      island.cfm = problem.cfm;
      island.symmetric = true;
    }
    // A non-symmetric A's rows for the sweeps (rows_of): Aᵀ(I, I) = A(I, I)ᵀ.
    const SpMat A_rows_I =
        problem.A_rows != nullptr ? principal_submatrix(*problem.A_rows, rows, local) : SpMat();
    if (problem.A_rows != nullptr) island.A_rows = &A_rows_I;
    if (problem.blocks != nullptr && !problem.blocks->empty()) {
      // The island's rows keep their order, so the rows of a block stay consecutive.
      blocks_I.clear();
      for (const int row : rows)
        blocks_I.push_back((*problem.blocks)[static_cast<std::size_t>(row)]);
      island.blocks = &blocks_I;
    }
    if (problem.kinds != nullptr) {
      kinds_I.clear();
      for (const int row : rows) kinds_I.push_back((*problem.kinds)[static_cast<std::size_t>(row)]);
      island.kinds = &kinds_I;
    }
    VecX lambda_I = gather_rows(lambda, rows);
    solve_island(island, lambda_I);
    for (std::size_t k = 0; k < rows.size(); ++k) lambda(rows[k]) = lambda_I(Eigen::Index(k));
  }
}

namespace {

/// Union-find over the rows: join() puts two rows in one island, islands() lists them.
class RowUnion {
 public:
  explicit RowUnion(int n) : parent_(static_cast<std::size_t>(n)) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  void join(int i, int k) {
    const int ri = root(i), rk = root(k);
    if (ri != rk) parent_[static_cast<std::size_t>(std::max(ri, rk))] = std::min(ri, rk);
  }
  /// Roots are the smallest row of their island, so islands come out in order of first row.
  std::vector<std::vector<int>> islands() {
    const auto n = static_cast<int>(parent_.size());
    std::vector<int> island_of_root(parent_.size(), -1);
    std::vector<std::vector<int>> islands;
    for (int i = 0; i < n; ++i) {
      auto& slot = island_of_root[static_cast<std::size_t>(root(i))];
      if (slot < 0) {
        slot = static_cast<int>(islands.size());
        islands.emplace_back();
      }
      islands[static_cast<std::size_t>(slot)].push_back(i);
    }
    return islands;
  }

 private:
  int root(int i) {
    while (parent_[static_cast<std::size_t>(i)] != i) {
      auto& p = parent_[static_cast<std::size_t>(i)];
      p = parent_[static_cast<std::size_t>(p)];  // path halving
      i = p;
    }
    return i;
  }
  std::vector<int> parent_;
};

}  // namespace

std::vector<std::vector<int>> find_islands(const SpMat& A) {
  RowUnion rows(static_cast<int>(A.rows()));
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    for (SpMat::InnerIterator it(A, j); it; ++it)
      if (it.value() != 0.0) rows.join(static_cast<int>(it.row()), static_cast<int>(j));
  }
  return rows.islands();
}

std::vector<std::vector<int>> find_islands(const BoxedProblem& problem) {
  if (problem.A_formed()) return find_islands(problem.A);
  // A = J Minv Jᵀ (+ cfm E): rows meet in A only through a body (six columns of J) that both
  // act on and whose block of Minv is not zero.
  const SpMatRow& J = *problem.J;
  const SpMat& Minv = *problem.Minv;
  std::vector<char> moves(static_cast<std::size_t>((J.cols() + 5) / 6), 0);
  for (Eigen::Index j = 0; j < Minv.outerSize(); ++j)
    for (SpMat::InnerIterator it(Minv, j); it; ++it)
      if (it.value() != 0.0) moves[std::size_t(j / 6)] = 1;
  RowUnion rows(static_cast<int>(J.rows()));
  std::vector<int> first_row(moves.size(), -1);  // the first row acting on each body
  for (Eigen::Index k = 0; k < J.rows(); ++k) {
    for (SpMatRow::InnerIterator it(J, k); it; ++it) {
      const auto body = static_cast<std::size_t>(it.col() / 6);
      if (it.value() == 0.0 || !moves[body]) continue;
      if (first_row[body] < 0)
        first_row[body] = static_cast<int>(k);
      else
        rows.join(first_row[body], static_cast<int>(k));
    }
  }
  return rows.islands();
}

SpMatRow select_rows(const SpMatRow& J, const std::vector<int>& idx) {
  SpMatRow S(static_cast<Eigen::Index>(idx.size()), J.cols());
  Eigen::Index nnz = 0;
  for (const int k : idx) nnz += J.row(k).nonZeros();
  S.reserve(nnz);
  for (std::size_t r = 0; r < idx.size(); ++r) {
    S.startVec(static_cast<Eigen::Index>(r));
    for (SpMatRow::InnerIterator it(J, idx[r]); it; ++it)
      S.insertBack(static_cast<Eigen::Index>(r), it.col()) = it.value();
  }
  S.finalize();
  return S;
}

}  // namespace cbps
