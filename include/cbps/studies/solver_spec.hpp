// A solver as the command line names it (`--solver`, `cbps converge --solvers`, stress cases):
// NAME[:OMEGA][:order=natural|reverse|random][:contacts_first=on|off][:warm=on|off|F]
// [:warm_friction=on|off|G][:key=value]..., e.g. `psor:1.3`, `pgs:order=random`, `jacobi:0.7`,
// `sgs`, `matrix-free`, `block-pgs`, `direct`, `apgd:restart=off`,
// `pgs:order=random:warm=0.85:warm_friction=0` (Bullet's warm start); the keys of a method's own
// parameters set its MethodSettings.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cbps/scene/scene.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/solver.hpp"

namespace cbps {

/// The sweeps one solve of a stored problem may take at most (`cbps lcp --iterations`, Python's
/// solve(iterations=)): a budget for a whole problem, unlike a scene's sweeps per step
/// (SolveSettings::max_iterations).
inline constexpr int kProblemIterations = 10000;
/// The sweeps each solver may take at most in the studies that run every solver to a tolerance
/// (`cbps converge --iterations`, `cbps profile --budget-iterations`).
inline constexpr int kStudyIterations = 100000;

/// One parsed spec. The names:
///   pgs          7.1.1 (omega = 1); psor:OMEGA is PGS with relaxation 0 < OMEGA < 2
///   jacobi       projected Jacobi; jacobi:OMEGA damps it, 0 < OMEGA ≤ 1
///   sgs          symmetric Gauss-Seidel (forward and backward sweep), sgs:OMEGA is SSOR
///   block-pgs    contact manifolds solved as blocks (block_pgs_sweep)
///   matrix-free  7.1.1 without A (MatrixFreePgs), the sequential-impulse form
///   pgs-nesterov PGS with Nesterov momentum and restart (restart=on|off), pgs-nesterov:OMEGA
///   apgd         accelerated projected gradient descent (grow=, shrink=, restart=on|off)
///   shock        PGS level by level from the ground up (level_sweeps=), shock:OMEGA
///   direct       the exact path (6.2); active-set the previous one
///   lemke        Lemke's complementary pivoting on the dense A (any square A, ≤ 3000 rows)
/// order applies to pgs, psor, pgs-nesterov and matrix-free; contacts_first=on (pgs, psor,
/// matrix-free) sweeps every contact normal row before every friction row. warm=F starts each row
/// from F times the previous step's lambda (on: 1, the default; off: 0, from lambda = 0), F in
/// [0, 1]; warm_friction=G the friction rows from G times theirs (default: F).
/// solver_spec_help() lists them all for --help.
struct SolverSpec {
  std::string text;                     ///< as given
  Method method = kPaperMethod;         ///< psor is the paper's method with its relaxation
  double relaxation = 1.0;              ///< omega
  RowOrder order = RowOrder::Natural;   ///< Gauss-Seidel forms
  bool contacts_first = false;          ///< pgs, psor, matrix-free
  double warm = 1.0;                    ///< warm-start factor F (SolverSettings::warm)
  std::optional<double> warm_friction;  ///< G of the friction rows, unset: F
  MethodSettings methods;               ///< the keys of a method's own parameters
  /// TAO's type for `tao:TYPE` (PETSc/TAO, docs/distributed.md), else empty. Only the CLI's
  /// parse_cli_solver_list (src/cli/tao_solvers.hpp) sets it, in a build with PETSc; `method`
  /// is then unused.
  std::string tao;
};

/// Parses one spec; throws InputError naming `what` (the option or JSON path) and the spec:
/// "--solver 'psor:3': relaxation factor '3' must be a number in (0, 2)".
SolverSpec parse_solver_spec(const std::string& text, const std::string& what = "solver");
/// A comma-separated list of specs (`pgs,psor:1.3,direct`).
std::vector<SolverSpec> parse_solver_list(const std::string& text,
                                          const std::string& what = "solvers");

/// Every name the grammar accepts, as the "unknown solver" messages list them: "pgs,
/// psor:OMEGA, sgs[:OMEGA], ..., lemke". A command that also takes tao:TYPE adds it
/// (src/cli/tao_solvers.hpp).
std::string solver_names();
/// True if the name before the first ':' of `text` is one of solver_names().
bool is_solver_name(const std::string& text);

/// Sets a scene's solver settings from a parsed spec: method, relaxation, row order, contacts
/// first, warm-start factors, the method's own parameters; the other settings stay.
void apply_solver_spec(const SolverSpec& spec, SolverSettings& settings);

/// The options of one solve by `spec`, built the way a scene's solver block with that spec gives
/// them (apply_solver_spec, then SolverSettings::options(): islands split, seed 0): at most
/// `max_iterations` sweeps, stopping at natural-map residual `tolerance`, N. The one way `cbps
/// lcp` and `cbps profile` turn a spec into SolverOptions; callers change what they own after.
SolverOptions solver_options(const SolverSpec& spec, int max_iterations, double tolerance);

/// The options of one run of a study by `spec` (`cbps converge`, `cbps profile`):
/// solver_options with tolerance 0 and no delta stop (the study stops the sweeps itself, in
/// SolverOptions::after_sweep), the whole problem at once (after_sweep sees all of lambda), no
/// message, and the stored problem's constraint-force mixing `cfm`, kg⁻¹.
SolverOptions study_options(const SolverSpec& spec, int max_iterations, double cfm);

/// Every name the grammar accepts with one line on what it is and its keys, for --help.
std::string solver_spec_help();

}  // namespace cbps
