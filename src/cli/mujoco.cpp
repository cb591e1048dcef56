// cbps mujoco MODEL.xml --steps N --out DIR: MuJoCo's own constraint problem of each step asked,
// as a cbps problem folder beside MuJoCo's forces (io/mujoco_problem.hpp, docs/mujoco.md).
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cbps/io/mujoco_problem.hpp"
#include "common.hpp"

namespace cbps::cli {

struct MujocoOptions {
  MujocoRun run;
  std::string out;
  bool quiet = false;
};

void register_mujoco(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "mujoco",
      "MuJoCo's constraint problem of a step, exactly, beside its forces (docs/mujoco.md)");
  auto o = std::make_shared<MujocoOptions>();
  cmd->add_option("MODEL", o->run.model, "an MJCF model (or a .mjb binary model)")->required();
  cmd->add_option("--keyframe", o->run.keyframe, "start from this keyframe of the model");
  cmd->add_option("--steps", o->run.steps, "mj_step calls (default 1)")->check(positive());
  cmd->add_option("--every", o->run.every, "export steps 0, K, 2K, ... (default: only --step)")
      ->check(non_negative());
  cmd->add_option("--step", o->run.at, "export this step, 0 the first (repeatable; default 0)")
      ->transform(step_index());
  cmd->add_option("--mujoco-solver", o->run.solver, "pgs, cg or newton (default: the model's)");
  cmd->add_option("--mujoco-iterations", o->run.iterations, "(default: the model's)")
      ->check(non_negative());
  cmd->add_option("--mujoco-tolerance", o->run.tolerance, "(default: the model's)")
      ->check(non_negative());
  cmd->add_option("--ladder",
                  o->run.ladder,
                  "also solve each exported step's state again by MuJoCo's pgs, cg and newton "
                  "with 1, 2, 4, ... up to N iterations and tolerance 0, each answer's unit-free "
                  "residual in mujoco.json (default 0: none)")
      ->check(non_negative());
  add_out_option(cmd, o->out, "step-K/ per step exported")->required();
  add_quiet_flag(cmd, o->quiet, "no line per step exported");
  cmd->callback([&run, o] {
    run = [o] {
      if (o->run.every == 0 && o->run.at.empty()) o->run.at.push_back(0);
      OutputDir dir(o->out);
      run_mujoco(o->run, [&](const MujocoStep& s) {
        const std::string step = "step-" + std::to_string(s.step);
        std::filesystem::create_directories(dir.file(step));
        write_mujoco_step(s, o->run.model, [&](const std::string& name, const auto& write) {
          write(dir.file(step + "/" + name));
        });
        if (!o->quiet)
          std::printf("%s: %ld rows, %d contacts; MuJoCo %s: %d iterations\n",
                      step.c_str(),
                      s.problem.rows(),
                      s.solve.contacts,
                      s.solve.solver.c_str(),
                      s.solve.iterations);
      });
      dir.commit();
      return 0;
    };
  });
}

}  // namespace cbps::cli
