// cbps matrices SCENE [--step K] --out DIR: the step's system as Matrix Market files.
//
// What is written is the problem the step solves: A = J Minv Jᵀ exactly (6.2.9); a constraint-
// force mixing eps, when the scene has one, apart in cfm.txt; with Coulomb friction (5.4) the
// bounds ±mu lambda_n that the step's lambda satisfies at its fixed point, said in labels.json;
// with Coulomb's cone (friction=cone) its contacts in cones.json, and with --fclib FILE the same
// problem as an FCLIB local problem (global with --global) with its solution. With a box
// (friction=paper or coulomb), --fclib FILE --cone LAW writes the step's A and b posed on Coulomb's
// cone instead, which the step did not solve: the file's info says so, and its /solution is the
// cone answer of the exact path where that is verified (docs/cones.md).
#include <cstdio>

#include "cbps/base/error.hpp"
#include "cbps/io/fclib_file.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/output_file.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/step_problem.hpp"
#include "common.hpp"

namespace cbps::cli {

namespace {

/// /fclib_local/info/math_info of every file cbps matrices writes, and /fclib_global/info's.
struct MatricesOptions {
  SceneOptions scene;
  StepOptions step;
  long at_step = 0;
  std::string out;
  std::string fclib;    ///< --fclib FILE.hdf5: the step's cone problem as an FCLIB file too
  std::string cone;     ///< --cone LAW: with a box, pose the step's A, b on the cone for --fclib
  bool global = false;  ///< --global: --fclib's file holds FCLIB's global problem (M, H, G)
  bool quiet = false;
};

int matrices_command(const MatricesOptions& o) {
  Scene scene = load_scene(o.scene);
  apply_step_options(scene, o.step);
  // Everything --fclib and --cone ask is checked before any work. --fclib never replaces a
  // file: cbps cannot tell an FCLIB file it wrote from a user's.
  const bool cone_scene = is_cone(scene.world.friction);
  FrictionLaw law = cone_scene ? scene.world.friction : FrictionLaw::CoulombCone;
  if (!o.fclib.empty()) {
    check_output_file(o.fclib, "--fclib " + o.fclib, false, "remove it or name another file");
    if (!o.cone.empty() && !cone_law_from_string(o.cone, law))
      throw InputError("--cone " + o.cone + ": unknown; use coulomb or ccp");
    if (!cone_scene && o.cone.empty())
      throw InputError("--fclib " + o.fclib + ": " + scene.name + " has its friction in a box " +
                       "(friction=" + std::string(friction_name(scene.world.friction)) +
                       "); --cone coulomb|ccp poses the step's A and b on Coulomb's cone for " +
                       "the file, or run the scene with friction=cone (docs/cones.md)");
    if (cone_scene && law != scene.world.friction)
      throw InputError("--cone " + o.cone + ": " + scene.name + " solves its cones under " +
                       std::string(cone_law_name(scene.world.friction)) +
                       "; the scene's law is set by --param cone=LAW (coulomb or ccp)");
  }
  OutputDir dir(o.out);
  // lambda by the exact path, and the boxed problem it solves (with Coulomb friction, at the
  // fixed point of the bounds), written by the one writer of a problem folder.
  const std::string what = "matrices: " + scene.name + ", step " + std::to_string(o.at_step);
  StepProblem step;
  try {
    step = solved_step_problem(scene, o.at_step, "matrices", what, o.quiet);
  } catch (const ComputationError& e) {
    throw ComputationError(std::string(e.what()) + "; nothing written");
  }
  const System& sys = step.sys;
  ProblemNotes notes;
  if (step.coulomb)
    notes.bounds = "; Coulomb friction rows: -+mu lambda_n at the fixed point (labels.json)";
  write_problem(
      step.problem,
      [&](const std::string& name, const auto& write) { write(dir.file(name)); },
      notes);
  if (!o.fclib.empty()) {
    PosedOnCones posed;
    try {
      posed = write_step_fclib(o.fclib, scene, sys, step, o.at_step, law, o.global);
    } catch (const InputError& e) {
      throw InputError("--fclib " + o.fclib + ": " + e.what());
    }
    if (!posed.verified && !o.quiet)
      std::fprintf(stderr,
                   "cbps matrices: %s: no /solution in the file (unit-free residual %s): %s\n",
                   o.fclib.c_str(),
                   number_text(posed.unit_free.relative).c_str(),
                   posed.direct.message.c_str());
  }
  write_matrix_market(dir.file("upsilon.mtx"), sys.upsilon, "upsilon: bias, m/s (5.1.2)");
  write_matrix_market(dir.file("lambda.mtx"),
                      step.lambda,
                      "lambda: direct solution, N (" + step.direct.message + ")");
  if (sys.softness.size() > 0)
    write_matrix_market(dir.file("softness.mtx"),
                        sys.softness,
                        "softness: the step scheme's diagonal, kg^-1 (docs/schemes.md); the "
                        "system carrying the push solves (A + diag(softness)) lambda = b");
  write_text(dir.file("labels.json"), step_labels(scene, sys, step, o.at_step).dump(2) + "\n");
  dir.commit();
  if (o.quiet) return 0;
  std::printf("%s, step %ld: %s, %s; wrote %s%s%s\n",
              scene.name.c_str(),
              o.at_step,
              count_text(sys.rows(), "row").c_str(),
              count_text(sys.blocks(), "movable body", "movable bodies").c_str(),
              o.out.c_str(),
              o.fclib.empty() ? "" : " and ",
              o.fclib.c_str());
  return 0;
}

}  // namespace

void register_matrices(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand("matrices", "write one step's system as Matrix Market files");
  auto o = std::make_shared<MatricesOptions>();
  add_scene_options(cmd, o->scene);
  add_step_options(cmd, o->step, false);
  cmd->add_option("--step", o->at_step, "the system of step K (after K steps)")
      ->transform(step_index());
  add_out_option(cmd,
                 o->out,
                 "J, Minv, A, b and the rest of the step's system as Matrix Market "
                 "files")
      ->required();
  auto* fclib = cmd->add_option(
      "--fclib",
      o->fclib,
      "also write the step's problem as an FCLIB local problem (HDF5) with its solution, to a "
      "file that does not exist yet; needs contacts in friction cones (friction=cone) or "
      "--cone (docs/cones.md)");
  cmd->add_option("--cone",
                  o->cone,
                  "with --fclib on a scene whose friction is a box: write the step's A and b "
                  "with each contact posed in Coulomb's cone of the scene's mu, under LAW "
                  "(coulomb: De Saxce's, FCLIB's; ccp: the convex relaxation), which the step "
                  "did not solve (no default; on a cone scene it must name the scene's law)")
      ->needs(fclib);
  cmd->add_flag("--global",
                o->global,
                "with --fclib: write FCLIB's global problem (M = Minv^-1, H = J^T of the contact "
                "rows, G of the free rows, f = 0, w = -b) instead of the local one (W = A, q = -b)")
      ->needs(fclib);
  add_quiet_flag(cmd, o->quiet, "print nothing on success (errors still go to stderr)");
  cmd->callback([&run, o] { run = [o] { return matrices_command(*o); }; });
}

}  // namespace cbps::cli
