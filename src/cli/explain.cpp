// cbps explain SCENE [--step K] [--json]: one step's system, labelled, for reading.
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "cbps/error.hpp"
#include "cbps/simulation.hpp"
#include "common.hpp"

namespace cbps::cli {

namespace {

/// The most matrix entries explain prints (its dense J, Minv and A together; 8 bytes each, and
/// several copies as text and JSON).
constexpr double kMaxExplainEntries = 4e6;

struct ExplainOptions {
  SceneOptions scene;
  StepOptions step;
  long at_step = 0;
  bool json = false;
};

/// Prints a matrix densely when it is narrow, else its nonzeros with their labels.
void print_matrix(const char* title,
                  const MatX& M,
                  const std::vector<std::string>& row_labels,
                  const std::vector<std::string>& col_labels) {
  std::printf("%s  (%ld x %ld)\n", title, static_cast<long>(M.rows()), static_cast<long>(M.cols()));
  if (M.cols() <= 12) {
    std::printf("  %-22s", "");
    for (const std::string& c : col_labels) std::printf(" %12.12s", c.c_str());
    std::printf("\n");
    for (Eigen::Index r = 0; r < M.rows(); ++r) {
      std::printf("  %-22.22s", row_labels[static_cast<std::size_t>(r)].c_str());
      for (Eigen::Index c = 0; c < M.cols(); ++c) std::printf(" %12.5g", M(r, c));
      std::printf("\n");
    }
    return;
  }
  for (Eigen::Index r = 0; r < M.rows(); ++r) {
    for (Eigen::Index c = 0; c < M.cols(); ++c) {
      if (M(r, c) == 0.0) continue;
      std::printf("  [%s, %s] = %.10g\n",
                  row_labels[static_cast<std::size_t>(r)].c_str(),
                  col_labels[static_cast<std::size_t>(c)].c_str(),
                  M(r, c));
    }
  }
}

void print_vector(const char* title, const VecX& v, const std::vector<std::string>& labels) {
  std::printf("%s  (%ld)\n", title, static_cast<long>(v.size()));
  for (Eigen::Index k = 0; k < v.size(); ++k) {
    std::printf("  %-22s %.10g\n", labels[static_cast<std::size_t>(k)].c_str(), v(k));
  }
}

int explain_command(const ExplainOptions& o) {
  Scene scene = load_scene(o.scene);
  apply_step_options(scene, o.step);
  Simulation sim(scene);
  for (long s = 0; s < o.at_step; ++s) sim.step();

  System sys = sim.build_system();
  // explain prints J, Minv and A densely: refuse, naming the sizes, what would not fit.
  const double dense = static_cast<double>(sys.rows()) * 6.0 * sys.blocks() +
                       36.0 * sys.blocks() * sys.blocks() +
                       static_cast<double>(sys.rows()) * sys.rows();
  if (dense > kMaxExplainEntries) {
    std::ostringstream why;
    why << scene.name << ", step " << o.at_step << ": " << sys.rows() << " rows and "
        << sys.blocks() << " movable bodies make a dense J of " << sys.rows() << " x "
        << 6 * sys.blocks() << ", Minv " << 6 * sys.blocks() << " x " << 6 * sys.blocks()
        << " and A " << sys.rows() << " x " << sys.rows() << " (" << number_text(dense)
        << " numbers); explain prints at most " << number_text(kMaxExplainEntries)
        << "; use `cbps matrices`, which writes them sparse";
    throw InputError(why.str());
  }
  VecX lambda = sim.initial_lambda(sys);
  const SolverSummary summary = sim.solve_system(sys, lambda);
  const VecX v2 = compute_v2(sys.v1, sys.Minv, sys.J, lambda, sys.fext, sys.dt);
  const std::vector<std::string> cols = column_labels(scene, sys);
  const std::vector<std::string>& rows = sys.labels;
  // The bounds lambda satisfies: with Coulomb friction (5.4) those of the fixed point, ±mu
  // lambda_n, not the zeros the rows are built with.
  VecX cmin, cmax;
  bounds_at(sys, lambda, cmin, cmax);
  const bool coulomb = has_coulomb_rows(sys);
  const char* const coulomb_note =
      "Coulomb friction rows: bounds -mu lambda_n, +mu lambda_n at the fixed point lambda "
      "satisfies (5.4)";
  const double cfm = scene.solver.cfm;
  const char* const cfm_note =
      "constraint-force mixing, a solver setting: the solve used A + eps E; A is J Minv J^T";

  if (o.json) {
    nlohmann::json out;
    out["scene"] = scene.name;
    out["step"] = o.at_step;
    out["t"] = sim.time();
    out["dt"] = sys.dt;
    out["row_labels"] = rows;
    out["column_labels"] = cols;
    out["J"] = {{"equation", "6.1"}, {"value", dense_json(MatX(sys.J))}};
    out["Minv"] = {{"equation", "6.1.2"}, {"value", dense_json(MatX(sys.Minv))}};
    out["A"] = {{"equation", "6.2.9"}, {"value", dense_json(MatX(sys.A))}};
    out["b"] = {{"equation", "6.2.9"}, {"value", vector_json(sys.b)}};
    out["upsilon"] = {{"equation", "5.1.2"}, {"value", vector_json(sys.upsilon)}};
    out["cmin"] = {{"equation", "5.1"}, {"value", vector_json(cmin)}};
    out["cmax"] = {{"equation", "5.1"}, {"value", vector_json(cmax)}};
    if (coulomb) {
      out["cmin"]["note"] = coulomb_note;
      out["cmax"]["note"] = coulomb_note;
    }
    out["cfm"] = {{"value", cfm}, {"unit", "kg^-1"}, {"note", cfm_note}};
    out["v1"] = {{"equation", "6.1.1"}, {"value", vector_json(sys.v1)}};
    out["fext"] = {{"equation", "6.1.3"}, {"value", vector_json(sys.fext)}};
    out["lambda"] = {{"equation", "7.1.1"}, {"value", vector_json(lambda)}};
    out["v2"] = {{"equation", "12.3.1"}, {"value", vector_json(v2)}};
    out["solver"] = {{"method", scene.solver.method},
                     {"iterations", summary.iterations},
                     {"residual", summary.residual},
                     {"message", summary.message}};
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("%s, step %ld (t = %.6g s, dt = %.6g s): %d rows, %d movable bodies\n\n",
              scene.name.c_str(),
              o.at_step,
              sim.time(),
              sys.dt,
              sys.rows(),
              sys.blocks());
  print_matrix("J: constraint Jacobian, rows j_c (5.1.3, 5.2.1), 6.1", MatX(sys.J), rows, cols);
  print_matrix("Minv = blockdiag(m^-1 E3, I^-1) (6.1.2)", MatX(sys.Minv), cols, cols);
  print_matrix("A = J Minv J^T (6.2.9)", MatX(sys.A), rows, rows);
  print_vector("upsilon: velocity bias, m/s (5.1.2, 5.2.3)", sys.upsilon, rows);
  print_vector("b = upsilon/dt - J (v1/dt + Minv fext), m/s^2 (6.2.9)", sys.b, rows);
  print_vector("cmin, N (5.1)", cmin, rows);
  print_vector("cmax, N (5.1)", cmax, rows);
  if (coulomb) std::printf("  (%s)\n", coulomb_note);
  print_vector("lambda, N (7.1.1)", lambda, rows);
  print_vector("v2 = v1 + dt Minv (J^T lambda + fext), m/s and rad/s (12.3.1)", v2, cols);
  if (cfm > 0.0) std::printf("\neps = %.6g kg^-1: %s\n", cfm, cfm_note);
  std::printf("\nsolver %s: %s\n", scene.solver.method.c_str(), summary.message.c_str());
  return 0;
}

}  // namespace

void register_explain(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand("explain", "print one step's J, Minv, A, b, bounds, lambda, v2");
  auto o = std::make_shared<ExplainOptions>();
  add_scene_options(cmd, o->scene);
  add_step_options(cmd, o->step, false);
  cmd->add_option("--step", o->at_step, "explain the system of step K (after K steps)")
      ->check(non_negative());
  cmd->add_flag("--json", o->json, "dense arrays with row and column labels, as JSON");
  cmd->callback([&run, o] { run = [o] { return explain_command(*o); }; });
}

}  // namespace cbps::cli
