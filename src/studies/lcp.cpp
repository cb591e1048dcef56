#include "cbps/studies/lcp.hpp"

#include <cmath>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/io/json_numbers.hpp"
#include "cbps/solvers/exact/active_set.hpp"
#include "cbps/solvers/peers/peers.hpp"
#include "cbps/solvers/solver.hpp"

namespace cbps {

namespace {

/// Where the exact path factored and why (the summary's `space`, what the problem carries).
void explain_space(const SolverSpec& spec,
                   const StoredProblem& p,
                   const SolverSummary& s,
                   LcpOutcome& r) {
  r.space = s.space;
  const std::string method(to_string(spec.method));
  if (s.space == "body") {
    r.space_reason = "body: J and Minv present";
  } else if (s.space == "row") {
    const std::string moved = p.cones.empty()
                                  ? ""
                                  : ", or a body-space solve of direct on cones lost accuracy "
                                    "and it moved to row space (its message says when)";
    r.space_reason = p.has_jacobian() ? "row: J and Minv present, but Minv is not block diagonal "
                                        "with definite 6 x 6 blocks or A is not J Minv J^T" +
                                            moved
                                      : "row: " + p.without_jacobian;
  } else if (spec.method == kExactMethod) {
    r.space_reason = "none: " + std::to_string(p.rows()) +
                     " rows, fewer than 500 or no bounded row: the active-set path on A "
                     "itself (" +
                     (p.has_jacobian() ? "J and Minv present" : p.without_jacobian) + ")";
  } else if (s.route == kActiveSetRoute) {
    r.space_reason = "none: the active-set path factors blocks of A itself";
  } else {
    r.space_reason = "none: " + method + " factors no Newton system";
  }
}

}  // namespace

LcpFacts lcp_facts(const StoredProblem& p) {
  LcpFacts f;
  f.rows = p.rows();
  f.cfm = p.cfm;
  f.kind = p.folder ? "cbps matrices folder" : p.fclib ? "FCLIB file" : "Siconos file";
  f.stored = &p;
  return f;
}

void check_applicable(const SolverSpec& spec, const StoredProblem& p, const std::string& path) {
  const std::string what = "--solver " + spec.text;
  if (!p.cones.empty() && !takes_cone_law(spec.method, p.cones.law))
    throw InputError(
        what + ": " + path + ": its " + std::to_string(p.cones.contacts()) +
        " contacts live in friction cones (" + std::string(cone_law_name(p.cones.law)) + "); " +
        std::string(to_string(spec.method)) +
        (takes_cones(spec.method) ? " does not solve that law"
                                  : " solves the boxed problem of 6.2") +
        ". Use --solver nsgs or direct (cones: " + kConeMethodNames + "; docs/cones.md)");
  if (needs_jacobian(spec.method) && !p.has_jacobian())
    throw InputError(what + ": " + path + ": " + p.without_jacobian + "; " +
                     std::string(to_string(spec.method)) +
                     (method_entry(spec.method).sweeps_factors
                          ? " sweeps on J and Minv (7.1.1 without A)"
                          : " takes its levels from the bodies of J's rows") +
                     ", so it needs a `cbps matrices` folder with J.mtx and Minv.mtx");
  if (spec.contacts_first && p.kinds.empty())
    throw InputError(what + ": " + path +
                     ": contacts_first needs each row's kind, which only a `cbps matrices` "
                     "folder's labels.json gives; drop it or use `cbps converge SCENE`");
  // The exact paths on the boxed problem solve the QP of 6.2 (on cones direct takes any A).
  if (!is_iterative(spec.method) && needs_symmetric(spec.method)) require_symmetric(p, what);
  if (const long most = most_rows(spec.method); most > 0 && p.rows() > most)
    throw InputError(what + ": the problem has " + std::to_string(p.rows()) + " rows; " +
                     std::string(to_string(spec.method)) + " takes at most " +
                     std::to_string(most) + " (a dense copy of A; use --solver pgs or direct)");
  if (is_peer(spec.method)) {
    const std::string refusal = peer_refusal(spec.method, p.problem());
    if (!refusal.empty()) throw InputError(what + ": " + path + ": " + refusal);
  }
}

LcpOutcome solve_stored(const SolverSpec& spec,
                        const StoredProblem& p,
                        int iterations,
                        double tolerance,
                        double time_limit) {
  if (is_iterative(spec.method) && !is_peer(spec.method)) {
    // The sweeps divide by (A + eps E)_kk (7.1.1); a peer meets the problem as it is.
    for (long k = 0; k < p.rows(); ++k) {
      const double a_kk = p.A.coeff(k, k) + p.cfm;
      if (!(a_kk > 0.0)) {
        LcpOutcome r;
        r.lambda = VecX::Zero(p.rows());
        r.message = spec.text + ": not run, it needs a positive diagonal; A[" + std::to_string(k) +
                    "," + std::to_string(k) + "] = " + number_text(a_kk);
        r.space_reason = "none: not run";
        return r;
      }
    }
  }
  SolverOptions options = solver_options(spec, iterations, tolerance);
  options.cfm = p.cfm;
  options.time_limit = time_limit;
  options.tolerance_unit_free = !p.folder;  // a Siconos or FCLIB file: its simulator's units
  VecX lambda = VecX::Zero(p.rows());
  const SolverSummary s = solve(p.problem(), lambda, options);
  LcpOutcome r;
  r.lambda = lambda;
  r.iterations = s.iterations;
  r.no_solution = s.termination == Termination::NoSolution;
  r.time_limit = s.termination == Termination::TimeLimit;
  r.pivots = counts_pivots(spec.method);
  r.message = s.message;
  explain_space(spec, p, s, r);
  if (is_peer(spec.method)) {
    r.peer = true;
    r.peer_status = s.peer_status;
    r.peer_said_ok = s.peer_said_ok;
    r.peer_iterations = s.peer_iterations;
    r.convert_time_s = s.convert_time_s;
    r.peer_solve_time_s = s.peer_solve_time_s;
  }
  return r;
}

LcpVerdict judge(const LcpFacts& p,
                 const LcpOutcome& r,
                 std::optional<double> measured,
                 std::optional<UnitFreeResidual> measured_unit_free) {
  // cbps's own check of the returned lambda (unit_free.hpp), independent of the solver's claim.
  LcpVerdict v;
  const bool sized = r.lambda.size() == p.rows;
  v.residual = !sized     ? kInf
               : measured ? *measured
               : p.stored != nullptr
                   ? natural_map_residual(p.stored->problem(), r.lambda, p.stored->cfm)
                   : kInf;
  v.scale = p.stored != nullptr ? scale_of(p.stored->problem(), p.stored->cfm) : p.scale;
  // A problem no process holds whole (TAO, the exact path under MPI): its unit-free residual as
  // the ranks formed it from their rows.
  if (sized)
    v.unit_free = p.stored != nullptr
                      ? unit_free_residual(p.stored->problem(), r.lambda, p.stored->cfm)
                      : measured_unit_free;
  v.solved = sized && v.unit_free && is_solved(*v.unit_free, r.lambda);
  v.status = v.solved        ? "solved"
             : r.no_solution ? "no_solution"
             : r.time_limit  ? "time limit"
                             : "failed";
  if (sized && p.stored != nullptr && !p.stored->cones.empty()) {
    const StoredProblem& s = *p.stored;
    const VecX w = s.A * r.lambda + s.cfm * r.lambda - s.b;  // w = (A + eps E) λ − b (6.2)
    v.cone = cone_measures(s.cones, r.lambda, w, s.b);
  }
  if (r.peer && r.peer_said_ok != v.solved) {  // a peer runs in one process: unit_free is set
    const double relative = v.unit_free ? v.unit_free->relative : kInf;
    v.peer_disagrees = std::string(r.peer_said_ok ? "peer said ok" : "peer said failed") +
                       "; unit-free residual " + number_text(relative) +
                       (v.solved ? " <= " : " > ") + number_text(kSolvedTolerance);
  }
  return v;
}

nlohmann::json lcp_result_json(const std::string& problem,
                               const LcpFacts& p,
                               const std::string& solver,
                               const LcpOutcome& r,
                               const LcpVerdict& v,
                               double wall) {
  const bool sized = r.lambda.size() == p.rows;
  nlohmann::json j;
  j["problem"] = problem;
  j["rows"] = p.rows;
  j["cfm"] = p.cfm;
  j["read_notes"] = p.stored != nullptr ? nlohmann::json(p.stored->notes) : nlohmann::json::array();
  j["solver"] = solver;
  j["status"] = v.status;
  j["iterations"] = r.iterations;
  j["wall_time_s"] = wall;
  j["residual"] = number_json(v.residual);
  j["scale"] = v.scale;
  j["message"] = r.message;
  j["space"] = r.space.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.space);
  j["space_reason"] = r.space_reason;
  if (r.peer) {
    j["peer"] = {
        {"status", r.peer_status},
        {"said_ok", r.peer_said_ok},
        {"iterations",
         r.peer_iterations < 0 ? nlohmann::json(nullptr) : nlohmann::json(r.peer_iterations)},
        {"convert_time_s", r.convert_time_s},
        {"solve_time_s", r.peer_solve_time_s},
        {"disagrees",
         v.peer_disagrees.empty() ? nlohmann::json(nullptr) : nlohmann::json(v.peer_disagrees)}};
  } else {
    j["peer"] = nullptr;
  }
  if (v.cone) {
    const ConeMeasures& c = *v.cone;
    j["cone"] = {{"law", std::string(cone_law_name(p.stored->cones.law))},
                 {"contacts", p.stored->cones.contacts()},
                 {"natural_map", number_json(c.natural_map)},
                 {"signorini", number_json(c.signorini)},
                 {"violation", number_json(c.violation)},
                 {"dissipation", number_json(c.dissipation)},
                 {"fclib_merit", number_json(c.fclib_merit)},
                 {"siconos_error", number_json(c.siconos_error)}};
  } else {
    j["cone"] = nullptr;
  }
  if (v.unit_free)
    j["unit_free"] = {{"residual", number_json(v.unit_free->residual)},
                      {"scale", number_json(v.unit_free->scale)},
                      {"relative", number_json(v.unit_free->relative)}};
  else
    j["unit_free"] = nullptr;
  j["lambda"] = !p.lambda_in_json ? nlohmann::json(nullptr)
                : sized           ? vector_json(r.lambda)
                                  : nlohmann::json::array();
  return j;
}

std::string unit_free_text(const UnitFreeResidual& u) {
  return "unit-free residual " + number_text(u.relative) + " (" + number_text(u.residual) +
         " N over the force scale " + number_text(u.scale) +
         " N; solved at <= " + number_text(kSolvedTolerance) + ")";
}

std::string cone_measures_text(FrictionLaw law, long contacts, const ConeMeasures& m) {
  return "cone law " + std::string(cone_law_name(law)) + ", " + std::to_string(contacts) +
         " contacts: Signorini gap " + number_text(m.signorini) + ", cone violation " +
         number_text(m.violation) + " N, dissipation gap " + number_text(m.dissipation) +
         ", FCLIB merit " + number_text(m.fclib_merit) + ", Siconos error " +
         number_text(m.siconos_error);
}

std::string lcp_text(const std::string& problem,
                     const LcpFacts& p,
                     const std::string& solver,
                     const LcpOutcome& r,
                     const LcpVerdict& v,
                     double wall) {
  std::string t = problem + ": " + std::to_string(p.rows) + " rows (" + p.kind + ")\n";
  if (p.stored != nullptr)
    for (const std::string& note : p.stored->notes) t += "read: " + note + "\n";
  if (p.cfm > 0.0)
    t += "cfm " + number_text(p.cfm) + " kg^-1 (cfm.txt): solving the boxed problem of A + eps E\n";
  t += solver + ": " + v.status + ", " + std::to_string(r.iterations) + " " +
       (r.pivots ? "pivots" : "iterations") + ", " + number_text(wall) + " s\n";
  if (v.unit_free) t += unit_free_text(*v.unit_free) + "\n";
  t += "residual " + number_text(v.residual) + " (natural map, infinity norm; data scale " +
       number_text(v.scale) + ")\n" + r.message + "\n";
  if (!v.peer_disagrees.empty()) t += v.peer_disagrees + "\n";
  if (v.cone)
    t += cone_measures_text(p.stored->cones.law, p.stored->cones.contacts(), *v.cone) + "\n";
  if (!r.space_reason.empty()) t += "space " + r.space_reason + "\n";
  return t;
}

}  // namespace cbps
