// The problem a step solved, and the same posed on Coulomb's cone (step_problem.hpp).
#include "cbps/studies/step_problem.hpp"

#include "cbps/base/error.hpp"
#include "cbps/io/fclib_file.hpp"
#include "cbps/solvers/paper/coulomb.hpp"
#include "cbps/studies/explain.hpp"
#include "cbps/studies/run.hpp"

namespace cbps {

StepProblem solved_step_problem(const Scene& scene,
                                long at_step,
                                const std::string& command,
                                const std::string& what,
                                bool quiet) {
  Simulation sim(scene);
  step_to(sim, at_step, command, quiet);
  StepProblem out;
  out.sys = sim.build_system();
  const System& sys = out.sys;
  SolverSettings exact = scene.solver;
  exact.method = kExactMethod;
  exact.tolerance = 0.0;
  out.lambda = VecX::Zero(sys.rows());
  out.direct = sim.solve_system(sys, sys.b, out.lambda, exact);
  out.coulomb = sys.coulomb().any();
  // With Coulomb friction the boxed problem is the one whose bounds ±mu lambda_n come from
  // lambda itself: lambda must solve it, by `cbps lcp`'s verdict (a singular resting contact may
  // leave the direct path a little above its rounding floor, never above that).
  if (out.coulomb &&
      !is_solved(coulomb_unit_free(sys.problem(), sys.coulomb(), out.lambda, scene.solver.cfm),
                 out.lambda))
    throw ComputationError(what + ": the Coulomb bounds did not reach a fixed point (" +
                           out.direct.message + "), so no boxed problem is the step's");
  out.problem = stored_problem(sys, scene.solver.cfm);
  // The bounds lambda satisfies: Coulomb rows at ±mu lambda_n.
  coulomb_bounds(sys.problem(), sys.coulomb(), out.lambda, out.problem.cmin, out.problem.cmax);
  return out;
}

PosedOnCones pose_on_cones(const System& sys, const StoredProblem& boxed, FrictionLaw law) {
  PosedOnCones out;
  out.problem = boxed;
  out.problem.cones = contacts_in_cones(sys, law);
  if (out.problem.cones.empty()) throw InputError("it has no contacts");
  for (const int n : out.problem.cones.normal) {  // the cone replaces the box: the rows' own sets
    out.problem.cmin(n) = 0.0;
    out.problem.cmax(n) = kInf;
    for (const int t : {n + 1, n + 2}) {
      out.problem.cmin(t) = -kInf;
      out.problem.cmax(t) = kInf;
    }
  }
  SolverOptions exact;
  exact.method = kExactMethod;
  exact.tolerance = 0.0;
  out.lambda = VecX::Zero(out.problem.rows());
  out.direct = solve(out.problem.problem(), out.lambda, exact);
  out.unit_free = unit_free_residual(out.problem.problem(), out.lambda);
  out.verified = is_solved(out.unit_free, out.lambda);
  return out;
}

nlohmann::json step_labels(const Scene& scene,
                           const System& sys,
                           const StepProblem& step,
                           long at_step) {
  nlohmann::json labels;
  labels["scene"] = scene.name;
  labels["step"] = at_step;
  labels["rows"] = sys.labels;
  labels["columns"] = column_labels(scene, sys);
  const SchemeSettings& scheme = scene.world.scheme;
  if (scheme.kind != Scheme::Paper)
    labels["scheme"] = {{"name", scheme_names().at(static_cast<std::size_t>(scheme.kind))},
                        {"substeps", scheme.substeps},
                        {"h", sys.dt},
                        {"note", scheme_note(scheme)},
                        {"softness", sys.softness.size() > 0 ? "softness.mtx" : "none"}};
  labels["system"] = sys.push == PushMode::Improved
                         ? "velocity system of the improved push (8.1): b without the push terms"
                         : "the one system of the original push (5.2.3, 6.2.9)";
  labels["cfm"] = scene.solver.cfm;
  if (!step.coulomb) return labels;
  nlohmann::json rows = nlohmann::json::array();
  for (long i = 0; i < sys.contacts.contacts(); ++i) {
    const int n = sys.contacts.normal[static_cast<std::size_t>(i)];
    for (const int k : {n + 1, n + 2})  // its friction rows
      rows.push_back({{"row", k}, {"normal_row", n}, {"mu", sys.contacts.mu(i)}});
  }
  labels["coulomb"] = {
      {"note",
       "Coulomb friction (5.4): the bounds of these rows are -mu lambda_n and +mu lambda_n "
       "with lambda_n the lambda of their normal row at the fixed point the step converged "
       "to; lambda.mtx solves the boxed problem with the bounds written here."},
      {"rows", rows},
      {"solve", step.direct.message}};
  return labels;
}

namespace {

constexpr const char* kFclibMathInfo =
    "u = W r + q with W = A = J Minv J^T (1/kg) and q = -b (m/s^2) of the step (6.2.9); r in N";
constexpr const char* kFclibGlobalMathInfo =
    "M v = H r + G l + f, u = H^T v + w with M = Minv^-1 (kg, kg m^2), H = J^T of the contact "
    "rows, G = J^T of the free rows, f = 0, w = -b (m/s^2) of the step (6.2.9): v = Minv J^T "
    "lambda (m/s^2), u = A r - b; r in N";

}  // namespace

PosedOnCones write_step_fclib(const std::string& path,
                              const Scene& scene,
                              const System& sys,
                              const StepProblem& step,
                              long at_step,
                              FrictionLaw law,
                              bool global) {
  const char* math = global ? kFclibGlobalMathInfo : kFclibMathInfo;
  const FclibForm form = global ? FclibForm::Global : FclibForm::Local;
  const std::string title = scene.name + ", step " + std::to_string(at_step);
  // The law the step solved: its contacts', or the scene's where it has none.
  if (is_cone(sys.contacts.empty() ? scene.world.friction : sys.contacts.law)) {
    // The problem the step solved, with its answer.
    if (sys.cones() == nullptr) throw InputError(title + " has no contacts in friction cones");
    const FclibInfo info{title,
                         "written by cbps matrices: the step's contacts in Coulomb's cone, law " +
                             std::string(cone_law_name(sys.contacts.law)) +
                             "; /solution by the direct path (" + step.direct.message + ")",
                         math};
    write_fclib(path, step.problem, info, &step.lambda, form);
    return PosedOnCones{step.problem, step.lambda, step.direct, {}, true};
  }
  PosedOnCones posed;
  try {
    posed = pose_on_cones(sys, step.problem, law);
  } catch (const InputError& e) {
    throw InputError(title + ": " + e.what());
  }
  const FclibInfo info{
      title + ", posed on Coulomb's cone",
      "written by cbps matrices: the step solved the scene's box (friction=" +
          std::string(friction_name(sys.contacts.law)) +
          "); this file holds the same A and b with each contact in Coulomb's cone, mu = " +
          mu_text(posed.problem.cones) + ", law " + std::string(cone_law_name(law)) + "; " +
          (posed.verified ? "/solution by the direct path (" + posed.direct.message + ")"
                          : "no /solution: the direct path did not verify an answer (" +
                                posed.direct.message + ")"),
      math};
  write_fclib(path, posed.problem, info, posed.verified ? &posed.lambda : nullptr, form);
  return posed;
}

}  // namespace cbps
