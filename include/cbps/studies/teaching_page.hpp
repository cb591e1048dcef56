// The teaching page of `cbps explain SCENE --html FILE`: one step's system (6.1, 6.2) as a
// self-contained HTML file (no network, no scripts, no fonts), for reading on a phone or on
// paper. teaching_step() solves the step as the simulation does and records what the page
// shows; teaching_page_html() renders it:
//   J (6.1) and M⁻¹ (6.1.2), A = J M⁻¹ Jᵀ and b = υ/Δt − J (v₁/Δt + M⁻¹ f_ext) (6.2.9),
//   λ within [cmin, cmax] (5.1) with w = Aλ − b (6.2), v₂ = v₁ + Δt M⁻¹ (Jᵀλ + f_ext) (12.3.1);
//   sparsity pictures of J and A (rows coloured by RowKind, columns grouped by body), the
//   solver's residual per sweep, the eigenvalues of A and its null space dimension.
// Under the improved push (8.1) both systems are shown: the velocity system and the position
// system (same J, M⁻¹, A; upsilon with the push term).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cbps/solvers/solver.hpp"
#include "cbps/system/system.hpp"

namespace cbps {

class Simulation;

/// Where row k's lambda sits and whether w = A lambda − b agrees with it (6.2): free (cmin <
/// lambda < cmax, w ≈ 0), at cmin (w ≥ 0) or at cmax (w ≤ 0); tol in m/s² (w's unit).
/// A contact in Coulomb's cone (docs/cones.md) gives its three rows its own status instead.
struct RowStatus {
  /// "free", "at cmin", "at cmax", "at cmin = cmax"; in a cone "cone: separated" (r = 0),
  /// "cone: sticking" (r inside K_mu, û = 0) or "cone: sliding" (r on K_mu's surface)
  std::string where;
  bool satisfied = true;  ///< the sign or zero condition of w holds within the tolerance
  bool at_bound() const { return where != "free" && where != "cone: sticking"; }
};
RowStatus row_status(double lambda, double cmin, double cmax, double w, double tol);
/// The status of a contact in Coulomb's cone of coefficient mu under `law`, r its lambda (N) and
/// u its rows of w (m/s²): satisfied when its natural map ‖r − P_K(r − û)‖₂ ≤ tol (N).
RowStatus cone_status(const Vec3& r, const Vec3& u, double mu, FrictionLaw law, double tol);

/// One solved system of the step: the one system of the original push (5.2.3, 5.3), or the
/// velocity or position system of the improved push (8.1).
struct TeachingSystem {
  std::string name;  ///< e.g. "velocity system (8.1)"
  std::string note;  ///< what it is for, one sentence
  VecX upsilon;      ///< c, m/s (6.1.4)
  VecX b;            ///< c, m/s² (6.2.9)
  VecX lambda;       ///< c, N: the solve's answer (7.1.1 / 6.2)
  VecX cmin, cmax;   ///< c, N: the bounds lambda satisfies (Coulomb rows: ±mu lambda_n, 5.4)
  VecX w;            ///< c, m/s²: A lambda − b (6.2), of A itself
  VecX v2;           ///< 6n, m/s and rad/s: v1 + dt Minv (Jᵀ lambda + fext) (12.3.1)
  /// c: each row judged within max(tolerance, rounding_floor) (+ cfm |lambda_k| with CFM)
  std::vector<RowStatus> status;
  double tolerance = 0.0;       ///< the residual the scene asks for (solver.tolerance), N
  double rounding_floor = 0.0;  ///< residual_floor of w = A lambda − b at lambda (direct.hpp), N
  SolverSummary summary;        ///< of the step's own solve
  /// Natural-map residual (N) after each sweep of `sweep_method` from the step's guess on the
  /// whole system (islands not split; Coulomb bounds at each iterate), index 0 = the guess.
  std::vector<double> sweep_residuals;
  std::string sweep_method;  ///< the scene's method if it sweeps, else the paper's (7.1.1)
};

/// One system of the current step of `sim` solved as the step solves it (the same guess,
/// method and settings; b from `upsilon`, 6.2.9), with what a reader checks: the bounds lambda
/// satisfies, w of A, each row's status against the requested tolerance, v2. The one report of
/// a solution that `cbps explain` prints and the teaching page draws. With `sweep_history` the
/// residual after every sweep too (sweep_residuals, sweep_method, with the scene's own settings):
/// one more solve. `method`, when given, solves the system instead of the scene's (the page's
/// exact answer on cones, beside the scene's sweeps).
TeachingSystem teaching_system(const Simulation& sim,
                               const System& sys,
                               const VecX& upsilon,
                               const VecX& guess,
                               bool sweep_history,
                               std::optional<Method> method = std::nullopt);

/// Everything the page shows of one step.
struct TeachingStep {
  std::string scene;
  long step = 0;                        ///< the system of step K (after K steps)
  double t = 0.0;                       ///< s
  std::string method;                   ///< the solver of the systems shown
  double cfm = 0.0;                     ///< kg⁻¹, a solver setting; A stays J Minv Jᵀ
  double solver_tolerance = 0.0;        ///< the scene's residual tolerance, N
  System sys;                           ///< J, Minv, A, v1, fext, labels, kind, dt
  std::vector<std::string> columns;     ///< J's column labels, "<body>.vx" … "<body>.wz"
  std::vector<std::string> bodies;      ///< the movable bodies' names, one per column block
  std::vector<TeachingSystem> systems;  ///< one, or two under the improved push (8.1)
  /// The command that writes this page again, as it was typed ("cbps explain chain --param n=2
  /// --html page.html"): shown on the page. Empty: "cbps explain SCENE --step K --html FILE".
  std::string command;
};

/// Solves `built`, the current system of `sim` (Simulation::build_system, built once by the caller,
/// who labels it), as its step would (same guess, method and settings) and records everything
/// the page shows. `columns` and `bodies` label J's columns (6n and n). `method`: solve the shown
/// systems by it instead (teaching_system).
TeachingStep teaching_step(const Simulation& sim,
                           System built,
                           std::vector<std::string> columns,
                           std::vector<std::string> bodies,
                           std::optional<Method> method = std::nullopt);

/// Where the page switches from tables to pictures and statistics.
struct TeachingLimits {
  int dense_rows = 60;  ///< tables of J, A and the row vectors up to this many rows
  /// The tables of J (6 columns a body, scrolling sideways), M⁻¹ and v up to this many bodies.
  int dense_bodies = 60;
  int eigen_rows = 400;  ///< eigenvalues of A (dense, O(c³)) up to this many rows
  int bar_rows = 250;    ///< λ's picture: one bar per row up to this many, then per bin of rows
};

/// The eigenvalues of a symmetric positive semidefinite A, ascending, and its null space
/// dimension: the eigenvalues ≤ tolerance = c · ε · max(λ_max, 0) (ε = 2⁻⁵², the usual
/// numerical-rank rule), kg⁻¹.
struct Spectrum {
  VecX values;
  double tolerance = 0.0;
  int null_dimension = 0;
};
Spectrum spectrum_of(const SpMat& A);

/// Text for HTML: & < > " ' as entities.
std::string html_escape(std::string_view text);

/// The page's <meta name="generator"> content, in its first 200 bytes: how `cbps explain --html`
/// knows that an existing FILE is a page it wrote (and may replace) and not the user's file.
inline constexpr std::string_view kTeachingPageGenerator = "cbps explain --html";
/// True when the file at `path` starts as a teaching page does (its generator line).
bool is_teaching_page(const std::string& path);

/// The page, one self-contained HTML document.
std::string teaching_page_html(const TeachingStep& step, const TeachingLimits& limits = {});

}  // namespace cbps
