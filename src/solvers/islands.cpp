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
  std::vector<int> local(static_cast<std::size_t>(A.rows()), -1);
  std::vector<int> blocks_I;
  std::vector<RowKind> kinds_I;
  for (const auto& rows : islands) {
    if (static_cast<Eigen::Index>(rows.size()) == A.rows()) {
      solve_island(problem, lambda);
      continue;
    }
    const SpMat A_I = principal_submatrix(A, rows, local);
    const VecX b_I = gather_rows(problem.b, rows);
    const VecX cmin_I = gather_rows(problem.cmin, rows);
    const VecX cmax_I = gather_rows(problem.cmax, rows);
    BoxedProblem island{A_I, b_I, cmin_I, cmax_I};
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

std::vector<std::vector<int>> find_islands(const SpMat& A) {
  const auto n = static_cast<int>(A.rows());
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int i) {
    while (parent[static_cast<std::size_t>(i)] != i) {
      auto& p = parent[static_cast<std::size_t>(i)];
      p = parent[static_cast<std::size_t>(p)];  // path halving
      i = p;
    }
    return i;
  };
  for (int j = 0; j < n; ++j) {
    for (SpMat::InnerIterator it(A, j); it; ++it) {
      if (it.value() == 0.0) continue;
      const int ri = root(static_cast<int>(it.row()));
      const int rj = root(j);
      if (ri != rj) parent[static_cast<std::size_t>(std::max(ri, rj))] = std::min(ri, rj);
    }
  }
  // Roots are the smallest row of their island, so islands come out in order of first row.
  std::vector<int> island_of_root(static_cast<std::size_t>(n), -1);
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

}  // namespace cbps
