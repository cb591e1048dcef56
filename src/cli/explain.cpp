// cbps explain SCENE [--step K] [--json]: one step's system, labelled, for reading.
//
// Everything needed to redo the step by hand is printed: J, Minv, v1, fext, upsilon and dt give
// A = J Minv J^T and b = upsilon/dt − J (v1/dt + Minv fext) (6.2.9); lambda with cmin, cmax and
// w = A lambda − b shows which rows are free and which sit at a bound (6.2); v2 follows by
// 12.3.1. Every number has the same significant digits and every block its unit.
#include "cbps/studies/explain.hpp"

#include <cstdio>
#include <iostream>
#include <memory>

#include "cbps/base/error.hpp"
#include "cbps/studies/teaching_page.hpp"
#include "common.hpp"

namespace cbps::cli {

namespace {

struct ExplainOptions {
  SceneOptions scene;
  StepOptions step;
  long at_step = 0;
  bool json = false;
  std::string html;    ///< --html FILE: the teaching page (teaching_page.hpp)
  bool force = false;  ///< --force: replace FILE even when it is not a page cbps wrote
};

void print_json(const Explained& e) { std::cout << explain_json(e).dump(2) << "\n"; }

/// explain --html FILE: the teaching page of the step, which takes any size the step takes
/// (pictures and statistics instead of dense tables above its limits).
/// On a scene on friction cones without --solver the shown system is solved exactly (`direct`)
/// and the scene's own sweeps (nsgs, 100 by default) are drawn beside it: a handout whose rows
/// are red because the sweeps stopped short teaches the wrong answer.
void write_page(const Scene& scene, long at_step, const std::string& html, bool solver_given) {
  TeachingStep step = teaching_step(scene, at_step, solver_given);
  step.command = invocation_text();
  write_output_file(html, "--html " + html, teaching_page_html(step));
  std::printf("%s, step %ld: %s, %s; wrote %s\n",
              scene.name.c_str(),
              at_step,
              count_text(step.sys.rows(), "row").c_str(),
              count_text(step.sys.blocks(), "movable body", "movable bodies").c_str(),
              html.c_str());
}

int explain_command(const ExplainOptions& o) {
  Scene scene = load_scene(o.scene);
  apply_step_options(scene, o.step);
  // An existing FILE is replaced when it is a teaching page cbps wrote, else only with --force.
  if (!o.html.empty())
    check_output_file(o.html,
                      "--html " + o.html,
                      o.force || is_teaching_page(o.html),
                      "it is not a page cbps wrote; --force replaces it");
  if (!o.html.empty()) {
    write_page(scene, o.at_step, o.html, !o.step.solver.empty());
    return 0;
  }
  const Explained e = explain_step(scene, o.at_step);
  if (o.json)
    print_json(e);
  else
    print_explain_text(stdout, e);
  return 0;
}

}  // namespace

void register_explain(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "explain",
      "print one step's system for checking by hand: J, Minv, A, v1, fext, upsilon, b, bounds, "
      "lambda, w = A lambda - b with each row's status, v2, with units and equation numbers");
  auto o = std::make_shared<ExplainOptions>();
  add_scene_options(cmd, o->scene);
  add_step_options(cmd, o->step, false);
  cmd->add_option("--step", o->at_step, "explain the system of step K (after K steps)")
      ->transform(step_index());
  add_json_flag(cmd,
                o->json,
                "full-precision dense arrays with row and column labels, units, w and per-row "
                "status");
  cmd->add_option("--html",
                  o->html,
                  "write the teaching page to FILE instead: one self-contained HTML file with "
                  "the step's system, sparsity pictures, lambda against its bounds, the "
                  "residual per sweep and the eigenvalues of A")
      ->option_text("FILE")
      ->check(non_empty())
      ->excludes("--json");
  cmd->add_flag("--force",
                o->force,
                "with --html: replace FILE even when it is not a teaching page cbps wrote (a page "
                "cbps wrote is always replaced)")
      ->needs("--html");
  cmd->callback([&run, o] { run = [o] { return explain_command(*o); }; });
}

}  // namespace cbps::cli
