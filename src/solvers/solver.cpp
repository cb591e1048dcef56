// solve(): any method on the boxed problem, with constraint-force mixing and islands, through
// the one table of methods (methods.hpp); the questions solver.hpp asks of a method, read there.
#include "cbps/solvers/solver.hpp"

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>

#include "cbps/base/error.hpp"
#include "cbps/solvers/islands.hpp"
#include "cbps/solvers/methods.hpp"

namespace cbps {

std::string_view to_string(Method method) {
  for (const MethodName& entry : method_table())  // a method's first name is its own
    if (entry.method == method) return entry.name;
  return "?";
}

bool method_from_string(std::string_view name, Method& method) {
  const MethodName* entry = find_method_name(name);
  if (entry == nullptr || to_string(entry->method) != name) return false;  // not an alias
  method = entry->method;
  return true;
}

Method method_of(std::string_view name) {
  Method method = kPaperMethod;
  if (!method_from_string(name, method))
    throw std::invalid_argument("unknown method '" + std::string(name) +
                                "' (valid: " + method_names() + ")");
  return method;
}

std::string method_names() {
  std::string names;
  for (const MethodName& entry : method_table()) {
    if (to_string(entry.method) != entry.name) continue;  // an alias
    if (!names.empty()) names += ", ";
    names += entry.name;
  }
  return names;
}

bool is_iterative(Method method) { return method_entry(method).iterative; }

bool needs_jacobian(Method method) { return method_entry(method).needs_jacobian; }

bool reads_A(Method method, bool cones) {
  const MethodEntry& e = method_entry(method);
  return cones ? e.reads_A_on_cones : e.reads_A;
}

bool needs_symmetric(Method method, bool cones) {
  const MethodEntry& e = method_entry(method);
  return cones ? e.symmetric_on_cones : e.symmetric;
}

bool is_siconos_fc3d(Method method) {
  const MethodEntry& e = method_entry(method);
  return e.library == Library::Siconos && e.laws == kCoulombLaw;
}

bool takes_cones(Method method) { return method_entry(method).laws != 0; }

long most_rows(Method method) { return method_entry(method).max_rows; }

bool counts_pivots(Method method) { return method_entry(method).pivots; }

bool takes_cone_law(Method method, FrictionLaw law) {
  return (method_entry(method).laws &
          (law == FrictionLaw::CoulombCone ? kCoulombLaw : kRelaxationLaw)) != 0;
}

bool relaxation_in_range(Method method, double omega) {
  if (method_entry(method).damping) return omega > 0.0 && omega <= 1.0;
  return omega > 0.0 && omega < 2.0;
}

const char* relaxation_range(Method method) {
  return method_entry(method).damping ? "(0, 1]" : "(0, 2)";
}

std::string to_string(RowOrder order) {
  switch (order) {
    case RowOrder::Natural:
      return "natural";
    case RowOrder::Reverse:
      return "reverse";
    case RowOrder::Random:
      return "random";
  }
  return "?";
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
    case Termination::NoSolution:
      return "no solution found";
    case Termination::PeerUnsolved:
      return "not solved by cbps's residual";
    case Termination::TimeLimit:
      return "time limit";
  }
  return "?";
}

namespace {

/// One method on the whole problem, as it is (no CFM, no islands).
SolverSummary solve_whole(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  return method_entry(options.method).solve(problem, lambda, options);
}

/// An iterative method on each island of A apart, each to its own tolerance.
SolverSummary solve_islands(const std::vector<std::vector<int>>& islands,
                            const BoxedProblem& problem,
                            VecX& lambda,
                            const SolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (lambda.size() != problem.rows()) lambda = VecX::Zero(problem.rows());
  SolverSummary total;
  total.termination = Termination::ResidualTolerance;
  total.islands = static_cast<int>(islands.size());
  SolverOptions each = options;
  each.describe = false;  // one message for all islands, below
  for_each_island(islands, problem, lambda, [&](const BoxedProblem& island, VecX& lambda_I) {
    const SolverSummary s = solve_whole(island, lambda_I, each);
    total.iterations = std::max(total.iterations, s.iterations);
    total.delta = std::max(total.delta, s.delta);
    max_keep_nan(total.residual, s.residual);
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
      << " islands solved apart), at most " << count_text(total.iterations, "sweep")
      << ", residual " << total.residual << " N";
  total.message = msg.str();
  return total;
}

}  // namespace

SolverSummary with_cfm_applied(
    const BoxedProblem& problem,
    const SolverOptions& options,
    const std::function<SolverSummary(const BoxedProblem&, const SolverOptions&)>& run) {
  if (options.cfm == 0.0 || method_entry(options.method).sweeps_factors)
    return run(problem, options);
  // A left out: A + eps E stays J Minv Jᵀ + (cfm + eps) E, through J and Minv.
  const SpMat mixed = problem.A_formed() ? with_cfm(problem.A, options.cfm) : SpMat();
  BoxedProblem regularised = with_matrix(problem, problem.A_formed() ? mixed : problem.A);
  regularised.A_rows = nullptr;  // Aᵀ + eps E is formed again by solve() where needed
  regularised.symmetric = problem.symmetric;  // eps on the diagonal keeps a symmetric A so
  regularised.cfm = problem.cfm + options.cfm;
  SolverOptions plain = options;
  plain.cfm = 0.0;
  return run(regularised, plain);
}

namespace {

/// solve() once A is known to suit the method: whole, or island by island.
SolverSummary solve_split(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  // The direct path splits by itself (options.direct.split_islands). The methods that read J
  // run whole (an island's problem carries no J): the matrix-free rows of different islands
  // never meet, and the shock order's sweep treats islands apart anyway; only the stopping is
  // common.
  // The peers are handed the problem whole, as an engine hands it to them.
  // A problem with cones runs whole too (its contacts are numbered in the whole problem's rows).
  if (!options.split_islands || !is_iterative(options.method) || needs_jacobian(options.method) ||
      method_entry(options.method).library != Library::Cbps || problem.cones != nullptr) {
    return solve_whole(problem, lambda, options);
  }
  const auto islands = find_islands(problem.A);
  if (islands.size() <= 1) return solve_whole(problem, lambda, options);
  return solve_islands(islands, problem, lambda, options);
}

}  // namespace

namespace {
/// solve() under its deadline, if any.
SolverSummary solve_posed(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options);
}  // namespace

bool past_deadline(const SolverOptions& options) {
  return options.deadline != std::chrono::steady_clock::time_point::max() &&
         std::chrono::steady_clock::now() >= options.deadline;
}

SolverSummary solve(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  if (options.time_limit > 0.0 &&
      options.deadline == std::chrono::steady_clock::time_point::max()) {
    // One deadline for this solve and every solve inside it (solve_posed may call solve again).
    SolverOptions timed = options;
    timed.deadline = std::chrono::steady_clock::now() +
                     std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                         std::chrono::duration<double>(options.time_limit));
    SolverSummary s = solve_posed(problem, lambda, timed);
    // An exact path stops at its next iteration past the deadline with its best lambda: short of
    // its tolerance because of the limit, not of the method.
    if (s.termination == Termination::NotConverged && past_deadline(timed)) {
      s.termination = Termination::TimeLimit;
      s.message += "; stopped at the time limit of " + number_text(options.time_limit) + " s";
    }
    return s;
  }
  return solve_posed(problem, lambda, options);
}

namespace {

SolverSummary solve_posed(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  const MethodEntry& method = method_entry(options.method);
  if (options.cfm != 0.0 && !method.sweeps_factors) {
    // Every method with an explicit A solves A + eps E; the matrix-free sweep puts eps on its
    // own diagonal.
    return with_cfm_applied(problem, options, [&](const BoxedProblem& p, const SolverOptions& o) {
      return solve(p, lambda, o);
    });
  }
  if (!problem.A_formed() && reads_A(options.method, problem.cones != nullptr)) {
    // A left out by the caller (a step solved in body space): formed here for a method that
    // reads its entries.
    const SpMat A = formed_A(problem);
    return solve(with_matrix(problem, A), lambda, options);
  }
  // What the method needs of A, tested here once per solve (every method comes through here).
  if (problem.cones != nullptr && !takes_cones(options.method))
    throw InputError("method '" + std::string(to_string(options.method)) +
                     "' solves the boxed problem of 6.2; this problem's contacts live in friction "
                     "cones (" +
                     std::to_string(problem.cones->contacts()) + " contacts), which " +
                     kConeMethodNames + " solve (docs/cones.md)");
  if (problem.cones != nullptr && !takes_cone_law(options.method, problem.cones->law))
    throw InputError(
        "method '" + std::string(to_string(options.method)) + "' on cones solves " +
        (problem.cones->law == FrictionLaw::CoulombCone
             ? std::string("the convex relaxation (ccp), the QP over the cones it minimises; this "
                           "problem's law is Coulomb's, which nsgs, direct and siconos:fc3d-* "
                           "solve")
             : std::string("Coulomb's law only; this problem's law is the convex relaxation "
                           "(ccp), which nsgs, direct, apgd, admm and pgs-nesterov solve")) +
        " (docs/cones.md)");
  if (method.sweeps_factors && problem.has_factors()) {
    // The matrix-free sweep solves the problem of J Minv Jᵀ + cfm E and never reads A: it must
    // be A's, or the residual it reports is not A's (issue 28: Minv doubled, "residual
    // tolerance reached" at 1e-10 N while A's residual was 3.6 N).
    const double mismatch = factors_mismatch(problem);
    if (!(mismatch <= kFactorsTolerance))
      throw InputError("method '" + std::string(method.name) +
                       "' sweeps J Minv J^T, never A, and they differ: |A x - "
                       "J Minv J^T x| is " +
                       number_text(mismatch) + " of |A| |x| on a test vector (at most " +
                       number_text(kFactorsTolerance) +
                       "); J, Minv and A are not one problem's. Pass matching ones, or solve A "
                       "with a method that reads it (pgs)");
  }
  // A's columns are its rows only when A is symmetric. The sweeps of 7.1.1 read A column by
  // column (SpMat is column-major), so for any other A they get Aᵀ (rows_of, sweep.hpp), formed
  // here once; the methods that minimise the QP ½ λᵀAλ − bᵀλ of 6.2 need the symmetry itself.
  // One pass over A's entries, measured at 1.3 to 2 times one PGS sweep on the base-20
  // pyramid (370k nonzeros): the price of never sweeping the wrong matrix.
  // symmetry_tolerance ≥ kSymmetryTolerance: its own pass over A only when that is exceeded.
  // A step's A = J Minv Jᵀ is symmetric by construction (BoxedProblem::symmetric): not tested.
  const double asymmetry = problem.symmetric ? 0.0 : max_asymmetry(problem.A);
  if (asymmetry > kSymmetryTolerance && asymmetry > symmetry_tolerance(problem.A)) {
    if (needs_symmetric(options.method, problem.cones != nullptr))
      throw InputError("method '" + std::string(to_string(options.method)) +
                       "' minimises the QP 1/2 lambda^T A lambda - b^T lambda of 6.2, which is the "
                       "boxed LCP only for a symmetric A; max |A - A^T| = " +
                       number_text(asymmetry) + " > " + number_text(symmetry_tolerance(problem.A)) +
                       ". lemke or a sweeping method (pgs, psor, sgs, jacobi, rbgs, block-pgs) "
                       "solves any A (the sweeps need A_kk > 0)");
    if (problem.A_rows == nullptr) {
      const SpMat A_rows = problem.A.transpose();  // column k = row k of A
      BoxedProblem rows = problem;
      rows.A_rows = &A_rows;
      return solve_split(rows, lambda, options);
    }
  }
  return solve_split(problem, lambda, options);
}

}  // namespace

}  // namespace cbps
