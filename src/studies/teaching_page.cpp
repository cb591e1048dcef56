// The teaching page's numbers (teaching_page.hpp): one step solved as the simulation solves it,
// with the residual after every sweep, the row statuses of 6.2 and the spectrum of A.
// teaching_page_html.cpp renders them.
#include "cbps/studies/teaching_page.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/paper/coulomb.hpp"
#include "cbps/step/push.hpp"
#include "cbps/step/simulation.hpp"

namespace cbps {

RowStatus row_status(double lambda, double cmin, double cmax, double w, double tol) {
  RowStatus s;
  const double tol_min = std::max(tol, 1e-12 * std::abs(cmin));
  const double tol_max = std::max(tol, 1e-12 * std::abs(cmax));
  if (std::isfinite(cmin) && std::isfinite(cmax) && cmax - cmin <= tol_min) {
    s.where = "at cmin = cmax";  // a fixed lambda (Coulomb friction with no normal force): any w
  } else if (std::isfinite(cmin) && lambda - cmin <= tol_min) {
    s.where = "at cmin";
    s.satisfied = w >= -tol;
  } else if (std::isfinite(cmax) && cmax - lambda <= tol_max) {
    s.where = "at cmax";
    s.satisfied = w <= tol;
  } else {
    s.where = "free";
    s.satisfied = std::abs(w) <= tol;
  }
  return s;
}

RowStatus cone_status(const Vec3& r, const Vec3& u, double mu, FrictionLaw law, double tol) {
  RowStatus s;
  const double t = std::hypot(r(1), r(2));  // ‖r_t‖
  s.where = r.norm() <= tol       ? "cone: separated"
            : t < mu * r(0) - tol ? "cone: sticking"
                                  : "cone: sliding";
  s.satisfied = cone_natural_map(r, u, mu, law).norm() <= tol;
  return s;
}

Spectrum spectrum_of(const SpMat& A) {
  Spectrum s;
  if (A.rows() == 0) return s;
  const Eigen::SelfAdjointEigenSolver<MatX> eigen(MatX(A), Eigen::EigenvaluesOnly);
  s.values = eigen.eigenvalues();  // ascending
  const double largest = std::max(0.0, s.values.maxCoeff());
  // The numerical-rank rule: an eigenvalue within c ε λ_max of zero is rounding of a zero one.
  s.tolerance = static_cast<double>(A.rows()) * std::numeric_limits<double>::epsilon() * largest;
  for (Eigen::Index k = 0; k < s.values.size(); ++k)
    if (s.values(k) <= s.tolerance) ++s.null_dimension;
  return s;
}

namespace {

/// Solves one system of the step (right-hand side b) from `guess` as the simulation does and
/// fills in everything the page shows of it.
/// The residual after every sweep of the step's method (PGS for the exact paths, which do not
/// sweep) from the step's guess on the whole system, into out.sweep_residuals.
void record_sweeps(const Simulation& sim,
                   const System& sys,
                   const VecX& guess,
                   TeachingSystem& out) {
  const SolverSettings& settings = sim.scene().solver;
  const BoxedProblem problem = sys.problem(out.b);
  SolverOptions options = sim.step_options(settings);
  options.split_islands = false;  // one residual of the whole system per sweep
  options.describe = false;
  if (sys.cones() != nullptr)
    options.method = kConeSweepMethod;  // the sweep that solves cones (docs/cones.md)
  else if (!is_iterative(options.method))
    options.method = kPaperMethod;
  out.sweep_method = std::string(to_string(options.method));
  out.sweep_residuals.push_back(coulomb_residual(problem, sys.coulomb(), guess, settings.cfm));
  options.after_sweep = [&](int, const VecX& lambda, double) {
    out.sweep_residuals.push_back(coulomb_residual(problem, sys.coulomb(), lambda, settings.cfm));
    return true;
  };
  VecX lambda = guess;
  if (sys.rows() > 0) solve_coulomb(problem, sys.coulomb(), lambda, options);
}

TeachingSystem solve_one(const Simulation& sim,
                         const System& sys,
                         const VecX& upsilon,
                         const VecX& guess,
                         std::string name,
                         std::string note,
                         std::optional<Method> method) {
  TeachingSystem out = teaching_system(sim, sys, upsilon, guess, true, method);
  out.name = std::move(name);
  out.note = std::move(note);
  return out;
}

}  // namespace

TeachingSystem teaching_system(const Simulation& sim,
                               const System& sys,
                               const VecX& upsilon,
                               const VecX& guess,
                               bool sweep_history,
                               std::optional<Method> method) {
  const SolverSettings& settings = sim.scene().solver;
  TeachingSystem out;
  out.upsilon = upsilon;
  out.b = compute_b(upsilon, sys.J, sys.v1, sys.Minv, sys.fext, sys.dt);  // (6.2.9)
  out.lambda = guess;
  SolverSettings shown = settings;
  if (method) shown.method = *method;
  out.summary = sim.solve_system(sys, out.b, out.lambda, shown);  // the step's solve (7.1.1 / 6.2)
  if (sweep_history) record_sweeps(sim, sys, guess, out);
  const BoxedProblem problem = sys.problem(out.b);

  // The bounds lambda satisfies (Coulomb rows: ±mu lambda_n at the answer, 5.4) and w = A
  // lambda − b (6.2) of A itself. Each row is judged against the tolerance the scene asks for
  // (not against the residual the solve reached, which no row can exceed): a solve that stops
  // short of it, such as PGS at its sweep limit, leaves rows missing their condition. The
  // tolerance is raised to the rounding floor of w where it is below that (tolerance 0: run
  // every sweep), and with CFM a row's w of A is eps lambda_k off what the solve met,
  // (A + eps E) lambda = b.
  coulomb_bounds(problem, sys.coulomb(), out.lambda, out.cmin, out.cmax);
  out.w = sys.A * out.lambda - out.b;
  out.tolerance = settings.tolerance;
  out.rounding_floor = residual_floor(problem, out.lambda);
  const double tolerance = std::max(out.tolerance, out.rounding_floor);
  for (Eigen::Index k = 0; k < out.w.size(); ++k) {
    const double tol = tolerance + settings.cfm * std::abs(out.lambda(k));
    out.status.push_back(row_status(out.lambda(k), out.cmin(k), out.cmax(k), out.w(k), tol));
  }
  const FrictionContacts* cones = sys.cones();
  for (long i = 0; cones != nullptr && i < cones->contacts(); ++i) {  // one status a contact
    const int n = cones->normal[static_cast<std::size_t>(i)];
    const RowStatus s = cone_status(
        out.lambda.segment<3>(n), out.w.segment<3>(n), cones->mu(i), cones->law, tolerance);
    for (int k = n; k < n + 3; ++k) out.status[static_cast<std::size_t>(k)] = s;
  }
  out.v2 = compute_v2(sys, out.lambda);  // (12.3.1)
  return out;
}

TeachingStep teaching_step(const Simulation& sim,
                           System built,
                           std::vector<std::string> columns,
                           std::vector<std::string> bodies,
                           std::optional<Method> method) {
  TeachingStep page;
  page.scene = sim.scene().name;
  page.step = sim.steps_done();
  page.t = sim.time();
  page.method = std::string(to_string(method.value_or(sim.scene().solver.method)));
  page.cfm = sim.scene().solver.cfm;
  page.solver_tolerance = sim.scene().solver.tolerance;
  page.sys = std::move(built);
  page.columns = std::move(columns);
  page.bodies = std::move(bodies);
  const System& sys = page.sys;
  const VecX guess = sim.initial_lambda(sys);  // the warm start (7)
  if (sys.push == PushMode::Improved) {
    page.systems.push_back(solve_one(sim,
                                     sys,
                                     sys.upsilon,
                                     guess,
                                     "velocity system (8.1)",
                                     "upsilon holds restitution only (8.2); its v2 is kept as "
                                     "the bodies' velocity",
                                     method));
    const TeachingSystem& velocity = page.systems.back();
    page.systems.push_back(solve_one(sim,
                                     sys,
                                     position_bias(sys),
                                     sim.position_guess(sys, velocity.lambda),
                                     "position system (8.1)",
                                     "upsilon adds each row's push term; its v2 only moves the "
                                     "bodies this step and is then dropped",
                                     method));
  } else {
    page.systems.push_back(solve_one(sim,
                                     sys,
                                     sys.upsilon,
                                     guess,
                                     "the one system (5.2.3, 5.3)",
                                     "upsilon holds the Baumgarte push term and restitution; "
                                     "its v2 moves the bodies and is kept",
                                     method));
  }
  return page;
}

bool is_teaching_page(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(200, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head.find("<meta name=\"generator\" content=\"" + std::string(kTeachingPageGenerator) +
                   "\">") != std::string::npos;
}

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

}  // namespace cbps
