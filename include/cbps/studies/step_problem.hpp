// The problem a step solved, as `cbps matrices` writes it: the boxed problem with its lambda by
// the exact path (with Coulomb friction, the bounds ±mu lambda_n at the fixed point the step
// reaches), and the same A and b posed on Coulomb's cone for a file of the field (FCLIB) when
// the scene's friction is a box.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "cbps/io/stored_problem.hpp"
#include "cbps/scene/scene.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/system.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps {

/// A step's boxed problem and its exact answer.
struct StepProblem {
  System sys;             ///< the step's system, with A (Simulation::build_system)
  StoredProblem problem;  ///< A = J Minv Jᵀ, b, the bounds lambda satisfies, the scene's cfm
  VecX lambda;            ///< by the exact path, to its rounding floor (6.2)
  SolverSummary direct;   ///< the exact path's summary
  bool coulomb = false;   ///< rows with Coulomb's bounds ±mu lambda_n (5.4)
};

/// The problem of step `at_step` of `scene` (a new Simulation stepped there, progress as
/// step_to's under `command` unless `quiet`), solved by the exact path with the scene's solver
/// settings (its cfm; with Coulomb friction iterated to the fixed point of the bounds, as the
/// step itself would). ComputationError, naming `what`, when the Coulomb bounds reach no fixed
/// point by `cbps lcp`'s verdict: then no boxed problem is the step's.
StepProblem solved_step_problem(const Scene& scene,
                                long at_step,
                                const std::string& command,
                                const std::string& what,
                                bool quiet);

/// labels.json of a `cbps matrices` folder (docs/outputs.md): the scene and step, each row's and
/// column's label, the system's form (the push), its cfm, under a substepping scheme which
/// substep it is and what the scheme changed (softness.mtx when it softens rows), and with
/// Coulomb friction each friction row's normal row and mu at the fixed point `step` reached.
nlohmann::json step_labels(const Scene& scene,
                           const System& sys,
                           const StepProblem& step,
                           long at_step);

/// A boxed problem with its contacts posed in Coulomb's cone instead of their boxes.
struct PosedOnCones {
  StoredProblem problem;  ///< the same A and b; each contact's rows in the cone of mu
  VecX lambda;            ///< the exact path's answer on cones
  SolverSummary direct;
  UnitFreeResidual unit_free;  ///< of lambda (system/unit_free.hpp)
  bool verified = false;       ///< lambda passes cbps's verdict (is_solved)
};

/// `boxed` (the step's problem of `sys`) with its contacts in Coulomb's cone under `law`, each of
/// the mu its rows were built with (contacts_in_cones: the cone replaces the box, the rows' own
/// bounds lifted), solved by the exact path on cones from zero. InputError for a system without
/// contacts.
PosedOnCones pose_on_cones(const System& sys, const StoredProblem& boxed, FrictionLaw law);

/// The step's problem as an FCLIB file at `path` (FCLIB's local problem; with `global` its global
/// one, M, H, G): on a scene with contacts in cones the problem the step solved, with its answer
/// as /solution; on a scene whose friction is a box the same A and b posed on Coulomb's cone
/// under `law` (pose_on_cones), with /solution only where the exact path verified its answer.
/// Returns what was written (verified false: no /solution). InputError naming the scene and
/// step `at_step` where the step has no contacts to put in cones.
PosedOnCones write_step_fclib(const std::string& path,
                              const Scene& scene,
                              const System& sys,
                              const StepProblem& step,
                              long at_step,
                              FrictionLaw law,
                              bool global);

}  // namespace cbps
