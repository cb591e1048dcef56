// `cbps check PROBLEM --lambda FILE` and Python's cbps.check: a given lambda (anyone's: an
// engine's, a peer's, a user's) judged against a stored problem, as cbps judges its own answers.
//
// The verdict is cbps's one verdict (system/unit_free.hpp): solved when lambda is finite and the
// largest term of the unit-free residual over the force scale S is at most kSolvedTolerance.
// Beside it: each row's or contact's status, the worst terms named by their labels, the cone
// measures (system/cone_problem.hpp: FCLIB's merit, Siconos' error) and, unless asked not to,
// the distance from the exact answer lambda* of `direct` (kExactMethod):
//   ‖w − w*‖∞ (b's units), max_k ρ_k |w_k − w*_k| / S (unit-free), ‖lambda − lambda*‖∞ (N) and,
//   where J is known, ‖Jᵀ(lambda − lambda*)‖∞ (N and N·m: the bodies' constraint forces).
// On a singular A lambda* is one of many answers, so ‖lambda − lambda*‖ may be large for a
// solved lambda; w* and Jᵀ lambda* are the same for every answer of a convex problem (the boxed
// problem of a symmetric A, the relaxation), which is why they are reported.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/cone_problem.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps {

struct CheckSettings {
  int worst = 10;          ///< how many of the largest terms to name
  bool exact = true;       ///< solve by direct and measure the distance from lambda*
  int iterations = 10000;  ///< direct's limit (its factorizations), as `cbps lcp`
  double tolerance = SolveSettings{}.tolerance;  ///< direct's, N, as `cbps lcp`
  double time_limit = 0.0;                       ///< s for direct, 0: none
};

/// One term of the residual: a row no contact owns, or a contact (its three rows).
struct CheckedTerm {
  long row = 0;       ///< the row, or the contact's normal row
  long contact = -1;  ///< the contact's index, −1 for a row
  std::string label;  ///< labels.json's ("contact A-B #F"), else "row k" or "contact i"
  /// A row: "at cmin", "at cmax", "between", "free" (no bound), "outside bounds"; a contact:
  /// "separated", "sticking" (inside the cone), "sliding" (on its surface), "outside cone".
  std::string status;
  double residual = 0.0;  ///< its term of the unit-free residual, N
  VecX lambda;            ///< its lambda (1 or 3 entries: r_n, r_t1, r_t2), N
  VecX w;                 ///< its w = A lambda − b (1 or 3 entries: u), b's units
};

/// How far lambda is from the exact answer lambda* (`direct` on the same problem).
struct ExactDistance {
  bool available = false;
  std::string why;          ///< when not available: direct refused or did not solve, and why
  std::string status;       ///< direct's verdict on lambda* ("solved")
  double relative = 0.0;    ///< lambda*'s unit-free residual
  double seconds = 0.0;     ///< direct's time, s
  double w_distance = 0.0;  ///< ‖w − w*‖∞, b's units
  double w_distance_relative = 0.0;      ///< max_k ρ_k |w_k − w*_k| / S
  double lambda_distance = 0.0;          ///< ‖lambda − lambda*‖∞, N
  std::optional<double> force_distance;  ///< ‖Jᵀ(lambda − lambda*)‖∞, where J is known
};

struct CheckReport {
  long rows = 0;
  long contacts = 0;
  FrictionLaw law = FrictionLaw::CoulombCone;  ///< the cones' law, when contacts > 0
  UnitFreeResidual unit_free;
  bool solved = false;
  double natural_map = 0.0;  ///< the natural map with unit step, ∞-norm, N (as `cbps lcp`)
  std::optional<ConeMeasures> cone;
  std::map<std::string, long> statuses;  ///< how many rows and contacts have each status
  std::vector<CheckedTerm> worst;        ///< the largest terms, largest first
  std::optional<ExactDistance> exact;    ///< when CheckSettings::exact
};

/// Judges lambda against p (with its cfm). InputError (exit 2) when lambda's length is not p's
/// rows or an entry is not finite.
CheckReport check_lambda(const StoredProblem& p, const VecX& lambda, const CheckSettings& s = {});

/// The report as JSON (docs/outputs.md, "cbps check").
nlohmann::json check_json(const std::string& problem, const CheckReport& r);
/// The report as text, the lines `cbps check` prints.
std::string check_text(const std::string& problem, const CheckReport& r);

}  // namespace cbps
