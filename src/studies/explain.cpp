#include "cbps/studies/explain.hpp"

#include <algorithm>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/io/json_numbers.hpp"
#include "cbps/step/push.hpp"
#include "cbps/studies/run.hpp"

namespace cbps {

bool angular_column(const std::string& label) {
  const std::size_t dot = label.rfind('.');
  return dot != std::string::npos && dot + 1 < label.size() && label[dot + 1] == 'w';
}

namespace {

/// Refuses, naming the sizes, a system whose dense J, Minv and A would not fit the text.
void check_printable(const System& sys, const std::string& scene, long at_step) {
  const double dense = static_cast<double>(sys.rows()) * 6.0 * sys.blocks() +
                       36.0 * sys.blocks() * sys.blocks() +
                       static_cast<double>(sys.rows()) * sys.rows();
  if (dense <= kMaxExplainEntries) return;
  std::ostringstream why;
  why << scene << ", step " << at_step << ": " << sys.rows() << " rows and " << sys.blocks()
      << " movable bodies make a dense J of " << sys.rows() << " x " << 6 * sys.blocks()
      << ", Minv " << 6 * sys.blocks() << " x " << 6 * sys.blocks() << " and A " << sys.rows()
      << " x " << sys.rows() << " (" << number_text(dense) << " numbers); explain prints at most "
      << number_text(kMaxExplainEntries) << "; use `cbps matrices`, which writes them sparse";
  throw InputError(why.str());
}

/// Units (9): every row of this project is a force row (lambda in N: J's linear part a unit
/// vector, its angular part r × n in m), so A is kg^-1 throughout. A row with no linear part
/// would be a torque row (lambda in N m) and mix A's units; say so if one appears.
std::string unit_of_A(const System& sys, const std::vector<std::string>& cols) {
  const SpMat Jt = SpMat(sys.J.transpose());
  bool torque_rows = false;
  for (Eigen::Index k = 0; k < Jt.outerSize(); ++k) {
    bool linear = false, any = false;
    for (SpMat::InnerIterator it(Jt, k); it; ++it) {
      if (it.value() == 0.0) continue;
      any = true;
      if (!angular_column(cols[static_cast<std::size_t>(it.row())])) linear = true;
    }
    if (any && !linear) torque_rows = true;
  }
  return torque_rows ? "mixed units: kg^-1 between force rows, kg^-1 m^-1 between a force row "
                       "and a torque row, kg^-1 m^-2 between torque rows"
                     : "kg^-1 (every row is a force row, lambda in N)";
}

/// The explanation of the step `at_step` that `sim` is at (explain_step).
Explained explain_current(const Scene& scene, const Simulation& sim, long at_step) {
  Explained e;
  e.scene = scene.name;
  e.step = at_step;
  e.t = sim.time();
  e.method = std::string(to_string(scene.solver.method));
  e.cfm = scene.solver.cfm;
  e.sys = sim.build_system();
  const System& sys = e.sys;
  check_printable(sys, scene.name, at_step);
  e.cols = column_labels(scene, sys);
  // The system shown, solved from the step's warm start as the step solves it. "w ≈ 0" and
  // "at a bound" mean within the tolerance the scene asks for (raised to w's rounding floor),
  // as the teaching page judges them: a solve that stopped short of it, such as PGS at its
  // sweep limit, leaves rows missing their condition.
  e.shown = teaching_system(sim, sys, sys.upsilon, sim.initial_lambda(sys), false);
  e.tol = std::max(e.shown.tolerance, e.shown.rounding_floor);
  e.all_satisfied = std::all_of(
      e.shown.status.begin(), e.shown.status.end(), [](const RowStatus& s) { return s.satisfied; });
  e.coulomb = sys.coulomb().any();
  e.improved = sys.push == PushMode::Improved;
  e.integrator = scene.world.integrator;
  e.scheme = scene.world.scheme;
  e.A_unit = unit_of_A(sys, e.cols);
  e.system_shown =
      e.improved ? "the velocity system of the improved push (8.1): upsilon holds restitution only "
                   "(8.2); its v2 is kept. The position system (same J, Minv, A; upsilon_position "
                   "adds the push term) is solved apart and only moves the positions this step"
                 : "the one system of the original push (5.2.3, 5.3): upsilon holds the Baumgarte "
                   "push term and restitution; its v2 moves the bodies and is kept";
  if (e.scheme.kind != Scheme::Paper)
    e.system_shown = scheme_note(e.scheme) + "; " + e.system_shown;
  for (const std::string& c : e.cols) {
    e.v_units.emplace_back(angular_column(c) ? "rad/s" : "m/s");
    e.f_units.emplace_back(angular_column(c) ? "N m" : "N");
  }
  return e;
}

}  // namespace

Explained explain_step(const Scene& scene, long at_step) {
  Simulation sim(scene);
  step_to(sim, at_step, "explain");
  return explain_current(scene, sim, at_step);
}

TeachingStep teaching_step(const Scene& scene, long at_step, bool method_chosen) {
  Simulation sim(scene);
  step_to(sim, at_step, "explain");
  System shown = sim.build_system();
  std::vector<std::string> bodies;
  for (int body : shown.body_of_block)
    bodies.push_back(scene.bodies[static_cast<std::size_t>(body)].name);
  std::optional<Method> method;
  if (!method_chosen && shown.cones() != nullptr && is_iterative(scene.solver.method))
    method = kExactMethod;
  std::vector<std::string> columns = column_labels(scene, shown);
  return teaching_step(sim, std::move(shown), std::move(columns), std::move(bodies), method);
}

std::string scheme_note(const SchemeSettings& scheme) {
  const std::string name = scheme_names().at(static_cast<std::size_t>(scheme.kind));
  std::string note = "the first of " + std::to_string(scheme.substeps) + " substeps of the " +
                     name + " scheme (dt here is the substep h = dt/" +
                     std::to_string(scheme.substeps) + "; docs/schemes.md)";
  switch (scheme.kind) {
    case Scheme::SoftStep:
      return note +
             ": the soft push system (the position system, with softness on A's diagonal and "
             "the soft push in upsilon_position) moves the bodies, then this rigid relax gives "
             "the velocity kept";
    case Scheme::Xpbd:
      return note +
             ": beta = 1 (the whole violation over h), compliance/h^2 on A's diagonal, lambda "
             "from 0";
    case Scheme::Paper:
    case Scheme::Tgs:
      break;
  }
  return note;
}

namespace {

nlohmann::json scheme_json(const Explained& e) {
  const System& sys = e.sys;
  nlohmann::json out = {{"name", scheme_names().at(static_cast<std::size_t>(e.scheme.kind))},
                        {"substeps", e.scheme.substeps},
                        {"h", sys.dt}};
  if (sys.softness.size() > 0)
    out["softness"] = {
        {"unit", "kg^-1"}, {"note", kSoftnessNote}, {"value", vector_json(sys.softness)}};
  return out;
}

}  // namespace

nlohmann::json explain_json(const Explained& e) {
  const System& sys = e.sys;
  const TeachingSystem& x = e.shown;
  nlohmann::json out;
  out["scene"] = e.scene;
  out["step"] = e.step;
  out["t"] = e.t;
  out["dt"] = sys.dt;
  out["system"] = {{"push", e.improved ? "improved" : "original"},
                   {"shown", e.improved ? "velocity" : "one"},
                   {"note", e.system_shown}};
  out["row_labels"] = sys.labels;
  out["column_labels"] = e.cols;
  out["J"] = {{"equation", "6.1"},
              {"unit", "1 (linear columns), m (angular columns)"},
              {"value", dense_json(MatX(sys.J))}};
  out["Minv"] = {{"equation", "6.1.2"},
                 {"unit", "kg^-1 (linear block), kg^-1 m^-2 (angular block)"},
                 {"value", dense_json(MatX(sys.Minv))}};
  out["A"] = {{"equation", "6.2.9"}, {"unit", e.A_unit}, {"value", dense_json(MatX(sys.A))}};
  out["b"] = {{"equation", "6.2.9"}, {"unit", "m/s^2"}, {"value", vector_json(sys.b)}};
  out["upsilon"] = {{"equation", "5.1.2"}, {"unit", "m/s"}, {"value", vector_json(sys.upsilon)}};
  if (e.improved)
    out["upsilon_position"] = {{"equation", "8.1"},
                               {"unit", "m/s"},
                               {"note", "the position system's bias; not the system shown"},
                               {"value", vector_json(position_bias(sys))}};
  out["cmin"] = {{"equation", "5.1"}, {"unit", "N"}, {"value", vector_json(x.cmin)}};
  out["cmax"] = {{"equation", "5.1"}, {"unit", "N"}, {"value", vector_json(x.cmax)}};
  if (e.coulomb) {
    out["cmin"]["note"] = kCoulombNote;
    out["cmax"]["note"] = kCoulombNote;
  }
  if (sys.cones() != nullptr) {
    nlohmann::json contacts = nlohmann::json::array();
    for (long i = 0; i < sys.contacts.contacts(); ++i) {
      const int n = sys.contacts.normal[static_cast<std::size_t>(i)];
      contacts.push_back({{"normal_row", n},
                          {"mu", sys.contacts.mu(i)},
                          {"status", x.status[static_cast<std::size_t>(n)].where}});
    }
    out["cones"] = {{"law", std::string(cone_law_name(sys.contacts.law))},
                    {"note", kConeNote},
                    {"contacts", contacts}};
    out["cmin"]["note"] = kConeNote;
    out["cmax"]["note"] = kConeNote;
  }
  out["cfm"] = {{"value", e.cfm}, {"unit", "kg^-1"}, {"note", kCfmNote}};
  out["v1"] = {{"equation", "6.1.1"}, {"unit", "m/s, rad/s"}, {"value", vector_json(sys.v1)}};
  out["integrator"] = integrator_names().at(static_cast<std::size_t>(e.integrator));
  out["scheme"] = scheme_json(e);
  if (e.integrator == Integrator::Gyroscopic)
    out["v1"]["note"] =
        "the angular parts after Bullet's implicit gyroscopic step (one Newton step on "
        "I (w' - w) + dt w' x I w' = 0 in the body frame; docs/integrators.md): the v1 the "
        "step solved from";
  out["fext"] = {{"equation", "6.1.3"}, {"unit", "N, N m"}, {"value", vector_json(sys.fext)}};
  out["lambda"] = {{"equation", "7.1.1"}, {"unit", "N"}, {"value", vector_json(x.lambda)}};
  out["w"] = {{"equation", "6.2"},
              {"unit", "m/s^2"},
              {"note", "w = A lambda - b, with A = J Minv J^T"},
              {"value", vector_json(x.w)}};
  nlohmann::json where = nlohmann::json::array(), satisfied = nlohmann::json::array();
  for (const RowStatus& s : x.status) {
    where.push_back(s.where);
    satisfied.push_back(s.satisfied);
  }
  out["status"] = {{"equation", "6.2"},
                   {"note",
                    "free: cmin < lambda < cmax and w = 0; at cmin: w >= 0; at cmax: w <= 0; "
                    "within tolerance (the requested solver tolerance, N, or the rounding floor "
                    "of w where that is larger, plus eps |lambda|)"},
                   {"tolerance", e.tol},
                   {"value", where},
                   {"satisfied", satisfied}};
  out["v2"] = {{"equation", "12.3.1"}, {"unit", "m/s, rad/s"}, {"value", vector_json(x.v2)}};
  out["solver"] = {{"method", e.method},
                   {"iterations", x.summary.iterations},
                   {"residual", number_json(x.summary.residual)},
                   {"message", x.summary.message}};
  return out;
}

}  // namespace cbps
