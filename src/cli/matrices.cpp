// cbps matrices SCENE [--step K] --out DIR: the step's system as Matrix Market files.
#include <cstdio>
#include <memory>

#include "cbps/matrix_market.hpp"
#include "cbps/simulation.hpp"
#include "common.hpp"

namespace cbps::cli {

namespace {

struct MatricesOptions {
  SceneOptions scene;
  StepOptions step;
  long at_step = 0;
  std::string out;
};

int matrices_command(const MatricesOptions& o) {
  Scene scene = load_scene(o.scene);
  apply_step_options(scene, o.step);
  OutputDir dir(o.out);
  Simulation sim(scene);
  for (long s = 0; s < o.at_step; ++s) sim.step();
  const System sys = sim.build_system();
  VecX lambda;
  const SolverSummary direct =
      solve("direct", sys.A, sys.b, sys.cmin, sys.cmax, lambda, SolverOptions{});

  write_matrix_market(dir.file("J.mtx"), SpMat(sys.J), "J: c x 6n constraint Jacobian (6.1)");
  write_matrix_market(dir.file("Minv.mtx"), sys.Minv, "Minv: 6n x 6n inverse mass (6.1.2)");
  write_matrix_market(dir.file("A.mtx"), sys.A, "A = J Minv J^T, c x c, 1/kg (6.2.9)");
  write_matrix_market(dir.file("b.mtx"), sys.b, "b = upsilon/dt - J (v1/dt + Minv fext) (6.2.9)");
  write_matrix_market(dir.file("cmin.mtx"), sys.cmin, "cmin: lower bounds on lambda, N (5.1)");
  write_matrix_market(dir.file("cmax.mtx"), sys.cmax, "cmax: upper bounds on lambda, N (5.1)");
  write_matrix_market(dir.file("v1.mtx"), sys.v1, "v1: velocities, m/s and rad/s (6.1.1)");
  write_matrix_market(dir.file("fext.mtx"), sys.fext, "fext: forces and torques, N, N m (6.1.3)");
  write_matrix_market(dir.file("upsilon.mtx"), sys.upsilon, "upsilon: bias, m/s (5.1.2)");
  write_matrix_market(
      dir.file("lambda.mtx"), lambda, "lambda: direct solution, N (" + direct.message + ")");
  nlohmann::json labels;
  labels["scene"] = scene.name;
  labels["step"] = o.at_step;
  labels["rows"] = sys.labels;
  labels["columns"] = column_labels(scene, sys);
  write_text(dir.file("labels.json"), labels.dump(2) + "\n");
  char dt_text[40];
  std::snprintf(dt_text, sizeof dt_text, "%.17g\n", sys.dt);
  write_text(dir.file("dt.txt"), dt_text);
  dir.commit();
  std::printf("%s, step %ld: %d rows, %d movable bodies; wrote %s\n",
              scene.name.c_str(),
              o.at_step,
              sys.rows(),
              sys.blocks(),
              o.out.c_str());
  return 0;
}

}  // namespace

void register_matrices(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand("matrices", "write one step's system as Matrix Market files");
  auto o = std::make_shared<MatricesOptions>();
  add_scene_options(cmd, o->scene);
  add_step_options(cmd, o->step);
  cmd->add_option("--step", o->at_step, "the system of step K (after K steps)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--out", o->out, "output folder")->required();
  cmd->callback([&run, o] { run = [o] { return matrices_command(*o); }; });
}

}  // namespace cbps::cli
