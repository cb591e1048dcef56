// cbps matrices SCENE [--step K] --out DIR: the step's system as Matrix Market files.
//
// What is written is the problem the step solves: A = J Minv Jᵀ exactly (6.2.9); a constraint-
// force mixing eps, when the scene has one, apart in cfm.txt; with Coulomb friction (5.4) the
// bounds ±mu lambda_n that the step's lambda satisfies at its fixed point, said in labels.json;
// with Coulomb's cone (friction=cone) its contacts in cones.json, and with --fclib FILE the same
// problem as an FCLIB local problem with its solution (docs/cones.md).
#include <cstdio>
#include <memory>

#include "cbps/base/error.hpp"
#include "cbps/io/fclib_file.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/output_file.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/paper/coulomb.hpp"
#include "cbps/step/simulation.hpp"
#include "common.hpp"

namespace cbps::cli {

namespace {

struct MatricesOptions {
  SceneOptions scene;
  StepOptions step;
  long at_step = 0;
  std::string out;
  std::string fclib;  ///< --fclib FILE.hdf5: the step's cone problem as an FCLIB file too
  bool quiet = false;
};

int matrices_command(const MatricesOptions& o) {
  Scene scene = load_scene(o.scene);
  apply_step_options(scene, o.step);
  // --fclib never replaces a file: cbps cannot tell an FCLIB file it wrote from a user's.
  if (!o.fclib.empty())
    check_output_file(o.fclib, "--fclib " + o.fclib, false, "remove it or name another file");
  OutputDir dir(o.out);
  Simulation sim(scene);
  for (long s = 0; s < o.at_step; ++s) sim.step();
  const System sys = sim.build_system();
  // lambda by the exact path (to its rounding floor), with the scene's cfm and, with Coulomb
  // friction, iterated to the fixed point of the bounds, as the step itself would.
  SolverSettings exact = scene.solver;
  exact.method = Method::Direct;
  exact.tolerance = 0.0;
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary direct = sim.solve_system(sys, sys.b, lambda, exact);
  const bool coulomb = sys.coulomb().any();
  if (coulomb && direct.termination != Termination::Direct)
    throw ComputationError("matrices: " + scene.name + ", step " + std::to_string(o.at_step) +
                           ": the Coulomb bounds did not reach a fixed point (" + direct.message +
                           "), so no boxed problem is the step's; nothing written");
  VecX cmin, cmax;  // the bounds lambda satisfies: Coulomb rows at ±mu lambda_n
  coulomb_bounds(sys.problem(), sys.coulomb(), lambda, cmin, cmax);
  // The boxed problem the step solved, written by the one writer of a problem folder.
  StoredProblem problem = stored_problem(sys, scene.solver.cfm);
  problem.cmin = cmin;
  problem.cmax = cmax;
  ProblemNotes notes;
  if (coulomb)
    notes.bounds = "; Coulomb friction rows: -+mu lambda_n at the fixed point (labels.json)";
  write_problem(
      problem, [&](const std::string& name, const auto& write) { write(dir.file(name)); }, notes);
  if (!o.fclib.empty()) {
    if (sys.cones.empty())
      throw InputError("--fclib " + o.fclib + ": " + scene.name + ", step " +
                       std::to_string(o.at_step) +
                       " has no contacts in friction cones (FCLIB holds Coulomb's cone; run "
                       "the scene with friction=cone)");
    const FclibInfo info{
        scene.name + ", step " + std::to_string(o.at_step),
        "written by cbps matrices: the step's contacts in Coulomb's cone, law " +
            std::string(to_string(sys.cones.law)) + "; /solution by the direct path (" +
            direct.message + ")",
        "u = W r + q with W = A = J Minv J^T (1/kg) and q = -b (m/s^2) of the step (6.2.9); r "
        "in N"};
    write_fclib(o.fclib, problem, info, &lambda);
  }
  write_matrix_market(dir.file("upsilon.mtx"), sys.upsilon, "upsilon: bias, m/s (5.1.2)");
  write_matrix_market(
      dir.file("lambda.mtx"), lambda, "lambda: direct solution, N (" + direct.message + ")");
  nlohmann::json labels;
  labels["scene"] = scene.name;
  labels["step"] = o.at_step;
  labels["rows"] = sys.labels;
  labels["columns"] = column_labels(scene, sys);
  labels["system"] = scene.world.push == PushMode::Improved
                         ? "velocity system of the improved push (8.1): b without the push terms"
                         : "the one system of the original push (5.2.3, 6.2.9)";
  labels["cfm"] = scene.solver.cfm;
  if (coulomb) {
    nlohmann::json rows = nlohmann::json::array();
    for (int k = 0; k < sys.rows(); ++k) {
      const int n = sys.normal_row[static_cast<std::size_t>(k)];
      if (n >= 0) rows.push_back({{"row", k}, {"normal_row", n}, {"mu", sys.mu(k)}});
    }
    labels["coulomb"] = {
        {"note",
         "Coulomb friction (5.4): the bounds of these rows are -mu lambda_n and +mu lambda_n "
         "with lambda_n the lambda of their normal row at the fixed point the step converged "
         "to; lambda.mtx solves the boxed problem with the bounds written here."},
        {"rows", rows},
        {"solve", direct.message}};
  }
  write_text(dir.file("labels.json"), labels.dump(2) + "\n");
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
  cmd->add_option("--fclib",
                  o->fclib,
                  "also write the step's problem as an FCLIB local problem (HDF5) with its "
                  "solution, to a file that does not exist yet; needs contacts in friction cones "
                  "(friction=cone, docs/cones.md)");
  add_quiet_flag(cmd, o->quiet, "print nothing on success (errors still go to stderr)");
  cmd->callback([&run, o] { run = [o] { return matrices_command(*o); }; });
}

}  // namespace cbps::cli
