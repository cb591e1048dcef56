// `cbps lcp`: a stored problem (a `cbps matrices` folder, a Siconos file or an FCLIB file)
// solved by one method and judged by cbps's own residual, whatever the method claims.
//
// Both are held in the paper's convention (6.2): w = A lambda − b, cmin ≤ lambda ≤ cmax, which
// is Siconos' w = M z + q, lb ≤ z ≤ ub with M = A, q = −b, lb = cmin, ub = cmax. The verdict is
// "solved" only if the unit-free residual of the returned lambda (system/unit_free.hpp) is ≤
// kSolvedTolerance (with a cfm.txt, that of A + eps E).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cbps/io/stored_problem.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps {

/// What a solver returned, before cbps's own check.
struct LcpOutcome {
  VecX lambda;
  int iterations = 0;
  bool no_solution = false;  ///< Lemke's ray termination
  bool time_limit = false;   ///< stopped by --time-limit before the method's own end
  bool pivots = false;       ///< iterations are Lemke's pivots
  std::string message;
  /// Where the exact path factored: "body", "row" or empty (no factorization: the sweeps,
  /// Lemke, or the active set of a small problem on blocks of A), and why.
  std::string space;
  std::string space_reason;
  /// A peer (siconos:NAME, bullet:NAME; peers.hpp): its own word, whether that word was
  /// success, its iterations as it reports them (−1: not exposed), and its conversion to its
  /// storage apart from its solve, s.
  bool peer = false;
  std::string peer_status;
  bool peer_said_ok = false;
  int peer_iterations = -1;
  double convert_time_s = 0.0, peer_solve_time_s = 0.0;
};

/// What the verdict and the report say of the problem: from a StoredProblem, or from a generated
/// one (which no rank holds whole: its residual and scale come measured on the distributed
/// vectors).
struct LcpFacts {
  long rows = 0;
  double cfm = 0.0;
  std::string
      kind;  ///< "cbps matrices folder", "Siconos file", "FCLIB file", "generated on N ranks"
  /// The problem, when one process holds it (solved as A + eps E with a cfm.txt).
  const StoredProblem* stored = nullptr;
  double scale = 0.0;          ///< without `stored`: scale_of measured elsewhere (reported)
  bool lambda_in_json = true;  ///< false: "lambda": null (too large to print)
};

/// The facts of a problem this process holds.
LcpFacts lcp_facts(const StoredProblem& p);

/// Refuses (InputError, exit 2) a spec that cannot run on this problem: the methods that read J
/// on a problem without J and Minv, contacts_first without row kinds, the exact paths on a
/// non-symmetric A (they solve the QP of 6.2). `path` names the problem in the message.
void check_applicable(const SolverSpec& spec, const StoredProblem& p, const std::string& path);

/// Every method but tao:TYPE: solve() with the options solver_options() builds from the spec
/// (the ones a scene's solver block with this spec would give), iterations and tolerance, from
/// lambda = 0, with the problem's cfm in the options (solve() applies it: A + eps E).
/// `time_limit` (s, 0: none) bounds the solve (SolverOptions::time_limit).
LcpOutcome solve_stored(const SolverSpec& spec,
                        const StoredProblem& p,
                        int iterations,
                        double tolerance,
                        double time_limit = 0.0);

/// cbps's verdict on a returned lambda.
struct LcpVerdict {
  double residual = 0.0;  ///< natural map, ∞-norm, N (∞ when lambda has the wrong size)
  /// scale_of, max(1, ‖b‖∞, max |A_ij|): reported beside the residual for its size, not the
  /// verdict's (that is unit_free's)
  double scale = 1.0;
  /// is_solved(unit_free, lambda): relative ≤ kSolvedTolerance, lambda finite
  bool solved = false;
  /// "solved", "no_solution" (Lemke's ray), "time limit" (not solved when --time-limit
  /// stopped the method) or "failed"
  std::string status;
  /// A peer whose word disagrees with cbps's verdict: "peer said ok; unit-free residual R >
  /// 1e-09" (or "peer said failed; unit-free residual ... <= ..."); empty otherwise.
  std::string peer_disagrees;
  /// A problem with cones (an FCLIB file): lambda measured against the cone law
  /// (system/cone_problem.hpp); empty for a boxed problem.
  std::optional<ConeMeasures> cone;
  /// The unit-free residual of lambda (system/unit_free.hpp), the verdict's: measured here where
  /// this process holds the problem, else as the ranks formed it from their rows; empty when
  /// lambda has the wrong size.
  std::optional<UnitFreeResidual> unit_free;
};
/// The verdict; `measured` and `measured_unit_free`: the natural-map and the unit-free residual
/// as the solver measured them on vectors no process holds whole (TAO, direct under MPI), else
/// measured here on lambda.
LcpVerdict judge(const LcpFacts& p,
                 const LcpOutcome& r,
                 std::optional<double> measured = {},
                 std::optional<UnitFreeResidual> measured_unit_free = {});

/// The text `cbps lcp` prints of `problem` solved by `solver` in `wall` s (the lines of
/// result.json's main fields).
std::string lcp_text(const std::string& problem,
                     const LcpFacts& p,
                     const std::string& solver,
                     const LcpOutcome& r,
                     const LcpVerdict& v,
                     double wall);
/// "unit-free residual R (X N over the force scale S N; solved at <= 1e-09)", the verdict's line.
std::string unit_free_text(const UnitFreeResidual& u);
/// "cone law L, N contacts: Signorini gap ..., FCLIB merit ..., Siconos error ...", the line of
/// the cone measures.
std::string cone_measures_text(FrictionLaw law, long contacts, const ConeMeasures& m);

/// result.json (docs/outputs.md) of `problem` solved by `solver` in `wall` s.
nlohmann::json lcp_result_json(const std::string& problem,
                               const LcpFacts& p,
                               const std::string& solver,
                               const LcpOutcome& r,
                               const LcpVerdict& v,
                               double wall);

}  // namespace cbps
