// Projected Gauss-Seidel (paper 7.1.1) and projected Jacobi over the explicit A.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>

#include "cbps/lcp.hpp"
#include "cbps/solver.hpp"

namespace cbps {

double clamp(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }

double natural_map_residual(const SpMat& A,
                            const VecX& b,
                            const VecX& cmin,
                            const VecX& cmax,
                            const VecX& lambda,
                            double cfm) {
  if (lambda.size() == 0) return 0.0;
  const VecX w = A * lambda + cfm * lambda - b;  // w = (A + eps E) λ − b (6.2)
  double r = 0.0;
  for (Eigen::Index k = 0; k < lambda.size(); ++k) {
    const double projected = clamp(lambda(k) - w(k), cmin(k), cmax(k));
    const double rk = std::abs(lambda(k) - projected);
    if (!(rk <= r)) r = rk;  // also propagates NaN
  }
  return r;
}

SpMat with_cfm(const SpMat& A, double eps) {
  SpMat regularised = A;
  if (eps == 0.0) return regularised;
  for (Eigen::Index k = 0; k < A.rows(); ++k) regularised.coeffRef(k, k) += eps;
  return regularised;
}

namespace {

/// Row j of 7.1.1 before clamping: (b_j − Σ_{i≠j} A_ji x_i) / A_jj, with x the values the
/// sweep reads (the current lambda for Gauss-Seidel, the previous sweep's for Jacobi).
/// Returns false for a row with A_jj = 0 (j_c = 0 acts on nothing; its lambda stays).
bool row_target(const SpMat& A, const VecX& b, const VecX& x, Eigen::Index j, double& target) {
  // A is symmetric: column j holds A_ij = A_ji.
  double sum = b(j);
  double A_jj = 0.0;
  for (SpMat::InnerIterator it(A, j); it; ++it) {
    if (it.row() == j) {
      A_jj = it.value();
    } else {
      sum -= it.value() * x(it.row());
    }
  }
  if (!(A_jj > 0.0)) return false;
  target = sum / A_jj;
  return true;
}

/// lambda_old + omega (target − lambda_old), exactly the target when omega = 1 (7.1.1).
double relax(double old, double target, double relaxation) {
  return relaxation == 1.0 ? target : old + relaxation * (target - old);
}

}  // namespace

namespace {

/// 7.1.1 over the rows row_at(0), row_at(1), …, row_at(count − 1).
template <class RowAt>
double sweep_rows(const SpMat& A,
                  const VecX& b,
                  const VecX& cmin,
                  const VecX& cmax,
                  VecX& lambda,
                  double relaxation,
                  Eigen::Index count,
                  RowAt row_at) {
  double delta = 0.0;
  double target = 0.0;
  for (Eigen::Index k = 0; k < count; ++k) {
    const Eigen::Index j = row_at(k);
    if (!row_target(A, b, lambda, j, target)) continue;
    const double next = clamp(relax(lambda(j), target, relaxation), cmin(j), cmax(j));  // (7.1.1)
    const double change = std::abs(next - lambda(j));
    if (!(change <= delta)) delta = change;  // also propagates NaN
    lambda(j) = next;
  }
  return delta;
}

}  // namespace

double pgs_sweep(const SpMat& A,
                 const VecX& b,
                 const VecX& cmin,
                 const VecX& cmax,
                 VecX& lambda,
                 double relaxation) {
  return sweep_rows(
      A, b, cmin, cmax, lambda, relaxation, A.outerSize(), [](Eigen::Index k) { return k; });
}

double pgs_sweep(const SpMat& A,
                 const VecX& b,
                 const VecX& cmin,
                 const VecX& cmax,
                 VecX& lambda,
                 double relaxation,
                 const std::vector<int>& rows) {
  return sweep_rows(A,
                    b,
                    cmin,
                    cmax,
                    lambda,
                    relaxation,
                    static_cast<Eigen::Index>(rows.size()),
                    [&](Eigen::Index k) { return Eigen::Index(rows[std::size_t(k)]); });
}

void sweep_order(RowOrder order, int rows, std::mt19937_64& rng, std::vector<int>& out) {
  out.resize(static_cast<std::size_t>(rows));
  std::iota(out.begin(), out.end(), 0);
  if (order == RowOrder::Reverse) std::reverse(out.begin(), out.end());
  if (order == RowOrder::Random) std::shuffle(out.begin(), out.end(), rng);
}

double block_pgs_sweep(const SpMat& A,
                       const VecX& b,
                       const VecX& cmin,
                       const VecX& cmax,
                       const std::vector<int>& row_blocks,
                       VecX& lambda,
                       double relaxation,
                       double regularization,
                       int* fallbacks) {
  const Eigen::Index c = A.outerSize();
  double delta = 0.0;
  double target = 0.0;
  const auto update = [&](Eigen::Index j, double next) {
    const double change = std::abs(next - lambda(j));
    if (!(change <= delta)) delta = change;  // also propagates NaN
    lambda(j) = next;
  };
  MatX M;
  VecX q;
  for (Eigen::Index first = 0; first < c;) {
    const int id = row_blocks[static_cast<std::size_t>(first)];
    Eigen::Index end = first + 1;
    while (id >= 0 && end < c && row_blocks[static_cast<std::size_t>(end)] == id) ++end;
    const Eigen::Index k = end - first;
    if (k == 1) {  // a row of its own: 7.1.1
      if (row_target(A, b, lambda, first, target))
        update(first, clamp(relax(lambda(first), target, relaxation), cmin(first), cmax(first)));
      first = end;
      continue;
    }
    // M = A_BB, q = A_BR lambda_R − b_B (A symmetric: column j of A is row j).
    M.setZero(k, k);
    q = -b.segment(first, k);
    for (Eigen::Index j = first; j < end; ++j) {
      for (SpMat::InnerIterator it(A, j); it; ++it) {
        if (it.row() >= first && it.row() < end) {
          M(it.row() - first, j - first) = it.value();
        } else {
          q(j - first) += it.value() * lambda(it.row());
        }
      }
    }
    // A_BB of a resting face has rank 6 of 12: Lemke's pivots on it break down numerically
    // (answers off by 0.5 of the scale). With delta I added it is positive definite and every
    // block solves; delta is a constraint-force-mixing term and biases lambda by O(delta),
    // which the residual of the whole system (reported) shows.
    M.diagonal().array() += regularization * M.diagonal().maxCoeff();
    const LcpResult z = solve_boxed_lemke(M, q, cmin.segment(first, k), cmax.segment(first, k));
    if (z.solved()) {
      for (Eigen::Index j = first; j < end; ++j)
        update(j, clamp(relax(lambda(j), z.z(j - first), relaxation), cmin(j), cmax(j)));
    } else {
      if (fallbacks != nullptr) ++*fallbacks;
      for (Eigen::Index j = first; j < end; ++j) {
        if (row_target(A, b, lambda, j, target))
          update(j, clamp(relax(lambda(j), target, relaxation), cmin(j), cmax(j)));
      }
    }
    first = end;
  }
  return delta;
}

double jacobi_sweep(const SpMat& A,
                    const VecX& b,
                    const VecX& cmin,
                    const VecX& cmax,
                    VecX& lambda,
                    double relaxation,
                    VecX& scratch) {
  scratch = lambda;  // the previous sweep's values
  double delta = 0.0;
  double target = 0.0;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    if (!row_target(A, b, scratch, j, target)) continue;
    lambda(j) = clamp(relax(scratch(j), target, relaxation), cmin(j), cmax(j));
    const double change = std::abs(lambda(j) - scratch(j));
    if (!(change <= delta)) delta = change;
  }
  return delta;
}

namespace {

/// Sweeps until a tolerance or the iteration limit; residual(lambda) is the natural-map
/// residual (computed only when a tolerance or the last sweep needs it).
template <class Sweep, class Residual>
SolverSummary iterate_rows(
    Eigen::Index rows, VecX& lambda, const SolverOptions& options, Sweep sweep, Residual residual) {
  const auto start = std::chrono::steady_clock::now();
  SolverSummary s;
  if (lambda.size() != rows) lambda = VecX::Zero(rows);
  if (rows == 0) {
    s.termination = Termination::ResidualTolerance;
    s.message = "no rows";
    return s;
  }
  s.residual = residual(lambda);
  if (options.residual_tolerance > 0.0 && s.residual <= options.residual_tolerance) {
    s.termination = Termination::ResidualTolerance;
  }
  double sweep_time = 0.0;  // s, in the sweeps alone (for after_sweep)
  while (s.termination == Termination::MaxIterations && s.iterations < options.max_iterations) {
    if (options.after_sweep) {  // the clock only for an observer: sweeps can be 1 µs
      const auto sweep_start = std::chrono::steady_clock::now();
      s.delta = sweep(lambda);
      sweep_time +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - sweep_start).count();
    } else {
      s.delta = sweep(lambda);
    }
    ++s.iterations;
    if (options.after_sweep && !options.after_sweep(s.iterations, lambda, sweep_time)) {
      s.termination = Termination::Stopped;
      s.residual = residual(lambda);
      break;
    }
    if (!std::isfinite(s.delta)) {
      s.termination = Termination::NonFinite;
      break;
    }
    if (options.delta_tolerance > 0.0 && s.delta <= options.delta_tolerance) {
      s.termination = Termination::DeltaTolerance;
    }
    if (options.residual_tolerance > 0.0 || s.iterations == options.max_iterations ||
        s.termination != Termination::MaxIterations) {
      s.residual = residual(lambda);
      if (options.residual_tolerance > 0.0 && s.residual <= options.residual_tolerance) {
        s.termination = Termination::ResidualTolerance;
      }
    }
  }
  if (!std::isfinite(s.residual)) s.termination = Termination::NonFinite;
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!options.describe) return s;
  std::ostringstream msg;
  msg << to_string(s.termination) << " after " << s.iterations << " sweeps, residual " << s.residual
      << " N, last change " << s.delta << " N";
  s.message = msg.str();
  return s;
}

template <class Sweep>
SolverSummary iterate(const SpMat& A,
                      const VecX& b,
                      const VecX& cmin,
                      const VecX& cmax,
                      VecX& lambda,
                      const SolverOptions& options,
                      Sweep sweep) {
  return iterate_rows(A.rows(), lambda, options, sweep, [&](const VecX& l) {
    return natural_map_residual(A, b, cmin, cmax, l);
  });
}

}  // namespace

SolverSummary solve_pgs(const SpMat& A,
                        const VecX& b,
                        const VecX& cmin,
                        const VecX& cmax,
                        VecX& lambda,
                        const SolverOptions& options) {
  if (options.order == RowOrder::Natural) {
    return iterate(A, b, cmin, cmax, lambda, options, [&](VecX& l) {
      return pgs_sweep(A, b, cmin, cmax, l, options.relaxation);
    });
  }
  std::mt19937_64 rng(options.seed);
  std::vector<int> rows;
  if (options.order == RowOrder::Reverse) sweep_order(options.order, int(A.rows()), rng, rows);
  return iterate(A, b, cmin, cmax, lambda, options, [&](VecX& l) {
    if (options.order == RowOrder::Random) sweep_order(options.order, int(A.rows()), rng, rows);
    return pgs_sweep(A, b, cmin, cmax, l, options.relaxation, rows);
  });
}

SolverSummary solve_matrix_free(const SpMatRow& J,
                                const SpMat& Minv,
                                const VecX& b,
                                const VecX& cmin,
                                const VecX& cmax,
                                VecX& lambda,
                                const SolverOptions& options) {
  const MatrixFreePgs pgs(J, Minv, options.cfm);
  if (lambda.size() != J.rows()) lambda = VecX::Zero(J.rows());
  VecX u = pgs.impulse(lambda);  // kept equal to W lambda by every sweep
  std::mt19937_64 rng(options.seed);
  std::vector<int> rows;  // empty: the natural order
  if (options.order == RowOrder::Reverse) sweep_order(options.order, pgs.rows(), rng, rows);
  SolverSummary s = iterate_rows(
      J.rows(),
      lambda,
      options,
      [&](VecX& l) {
        if (options.order == RowOrder::Random) sweep_order(options.order, pgs.rows(), rng, rows);
        return pgs.sweep(b, cmin, cmax, l, u, options.relaxation, rows);
      },
      [&](const VecX& l) { return pgs.residual(b, cmin, cmax, l, u); });
  if (options.describe) s.message.insert(0, "matrix-free: ");
  return s;
}

SolverSummary solve_sgs(const SpMat& A,
                        const VecX& b,
                        const VecX& cmin,
                        const VecX& cmax,
                        VecX& lambda,
                        const SolverOptions& options) {
  const Eigen::Index c = A.outerSize();
  return iterate(A, b, cmin, cmax, lambda, options, [&](VecX& l) {
    const double forward = pgs_sweep(A, b, cmin, cmax, l, options.relaxation);
    const double backward = sweep_rows(
        A, b, cmin, cmax, l, options.relaxation, c, [c](Eigen::Index k) { return c - 1 - k; });
    return std::max(forward, backward);
  });
}

SolverSummary solve_block_pgs(const SpMat& A,
                              const VecX& b,
                              const VecX& cmin,
                              const VecX& cmax,
                              VecX& lambda,
                              const SolverOptions& options) {
  if (options.row_blocks == nullptr || options.row_blocks->empty())
    return solve_pgs(A, b, cmin, cmax, lambda, options);
  if (options.row_blocks->size() != static_cast<std::size_t>(A.rows()))
    throw std::invalid_argument("solve_block_pgs: one block id per row expected");
  int fallbacks = 0;
  SolverSummary s = iterate(A, b, cmin, cmax, lambda, options, [&](VecX& l) {
    return block_pgs_sweep(A,
                           b,
                           cmin,
                           cmax,
                           *options.row_blocks,
                           l,
                           options.relaxation,
                           options.block_regularization,
                           &fallbacks);
  });
  if (options.describe) {
    std::ostringstream note;
    note << ", blocks regularised by " << options.block_regularization << " max A_jj";
    s.message.append(note.str());
  }
  if (fallbacks > 0 && options.describe) {
    s.message.append(", ");
    s.message.append(std::to_string(fallbacks));
    s.message.append(" blocks swept row by row (Lemke failed)");
  }
  return s;
}

SolverSummary solve_jacobi(const SpMat& A,
                           const VecX& b,
                           const VecX& cmin,
                           const VecX& cmax,
                           VecX& lambda,
                           const SolverOptions& options) {
  VecX scratch;
  return iterate(A, b, cmin, cmax, lambda, options, [&](VecX& l) {
    return jacobi_sweep(A, b, cmin, cmax, l, options.relaxation, scratch);
  });
}

bool is_solver_name(const std::string& method) {
  return method == "pgs" || method == "block-pgs" || method == "sgs" || method == "jacobi" ||
         method == "matrix-free" || method == "direct";
}

namespace {

SolverSummary solve_whole(const std::string& method,
                          const SpMat& A,
                          const VecX& b,
                          const VecX& cmin,
                          const VecX& cmax,
                          VecX& lambda,
                          const SolverOptions& options) {
  if (method == "pgs") return solve_pgs(A, b, cmin, cmax, lambda, options);
  if (method == "block-pgs") return solve_block_pgs(A, b, cmin, cmax, lambda, options);
  if (method == "sgs") return solve_sgs(A, b, cmin, cmax, lambda, options);
  if (method == "matrix-free")
    throw std::invalid_argument("solver 'matrix-free' works on J and Minv: solve_matrix_free");
  if (method == "jacobi") return solve_jacobi(A, b, cmin, cmax, lambda, options);
  if (method == "direct") {
    DirectOptions direct;
    direct.tolerance = options.residual_tolerance;  // one tolerance for every method
    return solve_direct(A, b, cmin, cmax, lambda, direct);
  }
  throw std::invalid_argument("unknown solver '" + method +
                              "' (valid: pgs, block-pgs, sgs, jacobi, direct)");
}

}  // namespace

SolverSummary solve(const std::string& method,
                    const SpMat& A,
                    const VecX& b,
                    const VecX& cmin,
                    const VecX& cmax,
                    VecX& lambda,
                    const SolverOptions& options) {
  if (options.cfm != 0.0) {  // every method solves A + eps E, the same way
    SolverOptions plain = options;
    plain.cfm = 0.0;
    return solve(method, with_cfm(A, options.cfm), b, cmin, cmax, lambda, plain);
  }
  if (!options.split_islands || method == "direct") {  // direct splits by itself
    return solve_whole(method, A, b, cmin, cmax, lambda, options);
  }
  const auto start = std::chrono::steady_clock::now();
  const auto islands = find_islands(A);
  if (islands.size() <= 1) return solve_whole(method, A, b, cmin, cmax, lambda, options);
  if (lambda.size() != A.rows()) lambda = VecX::Zero(A.rows());
  SolverSummary total;
  total.termination = Termination::ResidualTolerance;
  total.islands = static_cast<int>(islands.size());
  SolverOptions each = options;
  each.describe = false;  // one message for all islands, below
  const bool blocks = options.row_blocks != nullptr && !options.row_blocks->empty();
  std::size_t island = 0;  // for_each_island visits the islands in order
  std::vector<int> blocks_I;
  for_each_island(
      islands,
      A,
      b,
      cmin,
      cmax,
      lambda,
      [&](const SpMat& A_I, const VecX& b_I, const VecX& lo, const VecX& hi, VecX& lambda_I) {
        if (blocks) {  // the island's rows keep their order, so its blocks stay consecutive
          blocks_I.clear();
          for (const int row : islands[island]) {
            blocks_I.push_back((*options.row_blocks)[static_cast<std::size_t>(row)]);
          }
          each.row_blocks = &blocks_I;
        }
        ++island;
        const SolverSummary s = solve_whole(method, A_I, b_I, lo, hi, lambda_I, each);
        total.iterations = std::max(total.iterations, s.iterations);
        total.delta = std::max(total.delta, s.delta);
        if (!(s.residual <= total.residual)) total.residual = s.residual;  // NaN propagates
        // The worst termination: NonFinite > MaxIterations > DeltaTolerance > ResidualTolerance.
        if (s.termination == Termination::NonFinite ||
            (total.termination != Termination::NonFinite &&
             s.termination == Termination::MaxIterations) ||
            (total.termination == Termination::ResidualTolerance &&
             s.termination == Termination::DeltaTolerance)) {
          total.termination = s.termination;
        }
      });
  total.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ostringstream msg;
  msg << to_string(total.termination) << " (worst of " << total.islands
      << " islands solved apart), at most " << total.iterations << " sweeps, residual "
      << total.residual << " N";
  total.message = msg.str();
  return total;
}

std::string to_string(Termination t) {
  switch (t) {
    case Termination::ResidualTolerance:
      return "residual tolerance reached";
    case Termination::DeltaTolerance:
      return "change tolerance reached";
    case Termination::MaxIterations:
      return "iteration limit";
    case Termination::Direct:
      return "direct solve";
    case Termination::NotConverged:
      return "direct solve stopped short of its tolerance";
    case Termination::NonFinite:
      return "non-finite values";
    case Termination::Stopped:
      return "stopped by the caller";
  }
  return "?";
}

}  // namespace cbps
