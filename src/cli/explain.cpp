// cbps explain SCENE [--step K] [--json]: one step's system, labelled, for reading.
//
// Everything needed to redo the step by hand is printed: J, Minv, v1, fext, upsilon and dt give
// A = J Minv J^T and b = upsilon/dt − J (v1/dt + Minv fext) (6.2.9); lambda with cmin, cmax and
// w = A lambda − b shows which rows are free and which sit at a bound (6.2); v2 follows by
// 12.3.1. Every number has the same significant digits and every block its unit.
#include "cbps/studies/explain.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/paper/coulomb.hpp"
#include "cbps/step/push.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/studies/teaching_page.hpp"
#include "common.hpp"

namespace cbps::cli {

namespace {

/// Significant digits of every number in the text output.
constexpr int kDigits = 6;

struct ExplainOptions {
  SceneOptions scene;
  StepOptions step;
  long at_step = 0;
  bool json = false;
  std::string html;    ///< --html FILE: the teaching page (teaching_page.hpp)
  bool force = false;  ///< --force: replace FILE even when it is not a page cbps wrote
};

/// A number with kDigits significant digits; -0 is printed as 0.
std::string num(double x) {
  if (x == 0.0) return "0";
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", kDigits, x);
  return text;
}

std::size_t longest(const std::vector<std::string>& labels, std::size_t at_least = 0) {
  std::size_t w = at_least;
  for (const std::string& s : labels) w = std::max(w, s.size());
  return w;
}

int width(std::size_t w) { return static_cast<int>(w); }

/// Prints a matrix densely when it is narrow, else its nonzeros with their labels. Labels are
/// never cut: column widths come from the longest label and the widest number.
void print_matrix(const std::string& title,
                  const MatX& M,
                  const std::vector<std::string>& row_labels,
                  const std::vector<std::string>& col_labels) {
  std::printf(
      "%s  (%ld x %ld)\n", title.c_str(), static_cast<long>(M.rows()), static_cast<long>(M.cols()));
  if (M.rows() == 0 || M.cols() == 0) {
    std::printf("  (empty)\n");
    return;
  }
  const int row_w = width(longest(row_labels));
  if (M.cols() <= 12) {
    std::vector<int> col_w;
    for (Eigen::Index c = 0; c < M.cols(); ++c) {
      std::size_t w = col_labels[static_cast<std::size_t>(c)].size();
      for (Eigen::Index r = 0; r < M.rows(); ++r) w = std::max(w, num(M(r, c)).size());
      col_w.push_back(width(w));
    }
    std::printf("  %-*s", row_w, "");
    for (Eigen::Index c = 0; c < M.cols(); ++c)
      std::printf("  %*s",
                  col_w[static_cast<std::size_t>(c)],
                  col_labels[static_cast<std::size_t>(c)].c_str());
    std::printf("\n");
    for (Eigen::Index r = 0; r < M.rows(); ++r) {
      std::printf("  %-*s", row_w, row_labels[static_cast<std::size_t>(r)].c_str());
      for (Eigen::Index c = 0; c < M.cols(); ++c)
        std::printf("  %*s", col_w[static_cast<std::size_t>(c)], num(M(r, c)).c_str());
      std::printf("\n");
    }
    return;
  }
  std::printf("  (%ld columns: nonzero entries only, row by row)\n", static_cast<long>(M.cols()));
  const int col_w = width(longest(col_labels));
  for (Eigen::Index r = 0; r < M.rows(); ++r) {
    for (Eigen::Index c = 0; c < M.cols(); ++c) {
      if (M(r, c) == 0.0) continue;
      std::printf("  %-*s  %-*s  %s\n",
                  row_w,
                  row_labels[static_cast<std::size_t>(r)].c_str(),
                  col_w,
                  col_labels[static_cast<std::size_t>(c)].c_str(),
                  num(M(r, c)).c_str());
    }
  }
}

/// Prints a vector, one labelled entry a line, with each entry's unit.
void print_vector(const std::string& title,
                  const VecX& v,
                  const std::vector<std::string>& labels,
                  const std::vector<std::string>& units) {
  std::printf("%s  (%ld)\n", title.c_str(), static_cast<long>(v.size()));
  const int label_w = width(longest(labels));
  std::vector<std::string> values;
  for (Eigen::Index k = 0; k < v.size(); ++k) values.push_back(num(v(k)));
  const int value_w = width(longest(values));
  for (Eigen::Index k = 0; k < v.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    std::printf("  %-*s  %*s  %s\n",
                label_w,
                labels[i].c_str(),
                value_w,
                values[i].c_str(),
                units[i].c_str());
  }
}

void print_json(const Explained& e) { std::cout << explain_json(e).dump(2) << "\n"; }

/// lambda with its bounds, w and each row's status, one row a line (6.2, 7.1.1).
void print_solution_table(const Explained& e) {
  const TeachingSystem& x = e.shown;
  const std::vector<std::string>& rows = e.sys.labels;
  std::printf("lambda (7.1.1) within [cmin, cmax] (5.1), and w = A lambda - b (6.2)  (%d)\n",
              e.sys.rows());
  std::vector<std::vector<std::string>> table;
  table.push_back({"row", "cmin (N)", "lambda (N)", "cmax (N)", "w (m/s^2)", "status"});
  for (Eigen::Index k = 0; k < x.w.size(); ++k) {
    const RowStatus& s = x.status[static_cast<std::size_t>(k)];
    table.push_back({rows[static_cast<std::size_t>(k)],
                     num(x.cmin(k)),
                     num(x.lambda(k)),
                     num(x.cmax(k)),
                     num(x.w(k)),
                     s.where + (s.satisfied ? "" : " (w violates it)")});
  }
  std::vector<int> col_w(6, 0);
  for (const auto& line : table)
    for (std::size_t c = 0; c < line.size(); ++c)
      col_w[c] = std::max(col_w[c], width(line[c].size()));
  for (const auto& line : table) {
    std::printf("  %-*s", col_w[0], line[0].c_str());
    for (std::size_t c = 1; c < 5; ++c) std::printf("  %*s", col_w[c], line[c].c_str());
    std::printf("  %s\n", line[5].c_str());
  }
  std::printf(
      "  (free: cmin < lambda < cmax and w = 0; at cmin: w >= 0; at cmax: w <= 0; within "
      "%s N, the requested solver tolerance or the rounding floor of w if larger)\n",
      num(e.tol).c_str());
  if (!e.all_satisfied)
    std::printf(
        "  (some rows miss their condition: the solver stopped at residual %s N, before "
        "it met them)\n",
        num(x.summary.residual).c_str());
  if (e.coulomb) std::printf("  (%s)\n", kCoulombNote);
  if (e.sys.cones() != nullptr)
    std::printf(
        "  (%s; law %s)\n", kConeNote, std::string(cone_law_name(e.sys.contacts.law)).c_str());
}

void print_text(const Explained& e) {
  const System& sys = e.sys;
  const std::vector<std::string>& rows = sys.labels;
  std::printf("%s, step %ld (t = %s s, dt = %s s): %s, %s\n",
              e.scene.c_str(),
              e.step,
              num(e.t).c_str(),
              num(sys.dt).c_str(),
              count_text(sys.rows(), "row").c_str(),
              count_text(sys.blocks(), "movable body", "movable bodies").c_str());
  std::printf("System shown: %s.\n", e.system_shown.c_str());
  std::printf("Numbers to %d significant digits.\n\n", kDigits);
  print_matrix(
      "J: constraint Jacobian, rows j_c (5.1.3, 5.2.1), 6.1; unit 1 in the linear "
      "columns (vx, vy, vz), m in the angular ones (wx, wy, wz)",
      MatX(sys.J),
      rows,
      e.cols);
  std::printf("\n");
  print_matrix(
      "Minv = blockdiag(m^-1 E3, I^-1) (6.1.2); kg^-1 (linear block), kg^-1 m^-2 "
      "(angular block)",
      MatX(sys.Minv),
      e.cols,
      e.cols);
  std::printf("\n");
  print_matrix("A = J Minv J^T (6.2.9); " + e.A_unit, MatX(sys.A), rows, rows);
  std::printf("\n");
  if (sys.softness.size() > 0) {
    const std::vector<std::string> per_kg(rows.size(), "kg^-1");
    print_vector(std::string("softness: ") + kSoftnessNote, sys.softness, rows, per_kg);
    std::printf("\n");
  }
  print_vector("v1: velocities at the start of the step (6.1.1)", sys.v1, e.cols, e.v_units);
  std::printf("\n");
  print_vector(
      "fext: external forces and torques, gravity included (6.1.3)", sys.fext, e.cols, e.f_units);
  std::printf("\n");
  const std::vector<std::string> ms(rows.size(), "m/s"), ms2(rows.size(), "m/s^2");
  print_vector("upsilon: velocity bias (5.1.2, 5.2.3, 8.2)", sys.upsilon, rows, ms);
  if (e.improved) {
    std::printf("\n");
    print_vector("upsilon_position: the position system's bias (8.1), not the system shown",
                 position_bias(sys),
                 rows,
                 ms);
  }
  std::printf("\n");
  print_vector("b = upsilon/dt - J (v1/dt + Minv fext) (6.2.9)", sys.b, rows, ms2);
  std::printf("\n");
  print_solution_table(e);
  std::printf("\n");
  print_vector("v2 = v1 + dt Minv (J^T lambda + fext) (12.3.1)", e.shown.v2, e.cols, e.v_units);
  if (e.cfm > 0.0)
    std::printf("\neps = %s kg^-1: %s; w of A is eps lambda off on free rows\n",
                num(e.cfm).c_str(),
                kCfmNote);
  std::printf("\nsolver %s: %s\n", e.method.c_str(), e.shown.summary.message.c_str());
}

/// explain --html FILE: the teaching page of the step, which takes any size the step takes
/// (pictures and statistics instead of dense tables above its limits).
/// On a scene on friction cones without --solver the shown system is solved exactly (`direct`)
/// and the scene's own sweeps (nsgs, 100 by default) are drawn beside it: a handout whose rows
/// are red because the sweeps stopped short teaches the wrong answer.
void write_page(const Scene& scene,
                const Simulation& sim,
                long at_step,
                const std::string& html,
                bool solver_given) {
  const System shown = sim.build_system();
  std::vector<std::string> bodies;
  for (int body : shown.body_of_block)
    bodies.push_back(scene.bodies[static_cast<std::size_t>(body)].name);
  std::optional<Method> method;
  if (!solver_given && shown.cones() != nullptr && is_iterative(scene.solver.method))
    method = kExactMethod;
  TeachingStep step = teaching_step(sim, column_labels(scene, shown), bodies, method);
  step.command = invocation_text();
  write_output_file(html, "--html " + html, teaching_page_html(step));
  std::printf("%s, step %ld: %s, %s; wrote %s\n",
              scene.name.c_str(),
              at_step,
              count_text(shown.rows(), "row").c_str(),
              count_text(shown.blocks(), "movable body", "movable bodies").c_str(),
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
  Simulation sim(scene);
  step_to(sim, o.at_step, "explain");
  if (!o.html.empty()) {
    write_page(scene, sim, o.at_step, o.html, !o.step.solver.empty());
    return 0;
  }
  const Explained e = explain_step(scene, sim, o.at_step);
  if (o.json)
    print_json(e);
  else
    print_text(e);
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
