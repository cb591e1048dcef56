// Solvers of the boxed problem of 6.2 (system/boxed_problem.hpp): the methods, their one options
// struct, why they stop, and solve(), which runs any of them. They see only the problem, never
// bodies, so stored problems feed them as well. One header per family beside this one:
//   pgs.hpp              7.1.1: PGS, PSOR, symmetric Gauss-Seidel, projected Jacobi
//   pgs_block.hpp        block PGS (contact manifolds solved as blocks by Lemke)
//   pgs_matrix_free.hpp  7.1.1 without A (sequential impulses)
//   pgs_nesterov.hpp     PGS with Nesterov momentum and adaptive restart
//   apgd.hpp             accelerated projected gradient descent
//   nncg.hpp             nonsmooth nonlinear conjugate gradient on PGS sweeps
//   pgs_sm.hpp           PGS with subspace minimization
//   admm.hpp             ADMM on the box QP with one factor of A + rho E
//   rbgs.hpp             red-black (graph-coloured) PGS
//   shock.hpp            PGS in shock-propagation order: contact levels from the ground up
//   method_settings.hpp  the parameters of the methods that have their own
//   direct.hpp           the exact path: interior point in body space, crossover to the active set
//   active_set.hpp       the previous exact path: active set on CHOLMOD inside proximal points
//   lemke.hpp            Lemke's method, a dense pivoting reference
//   islands.hpp          independent blocks of A, solved apart
//   coulomb.hpp          friction bounds ±mu lambda_n (5.4) around any method: a fixed point
//   cone/nsgs.hpp        non-smooth Gauss-Seidel on Coulomb's friction cones
//   peers/peers.hpp      the field's own solvers as methods: Siconos numerics and Bullet
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cbps/solvers/method_settings.hpp"
#include "cbps/system/boxed_problem.hpp"

namespace cbps {

/// What the exact path keeps from one solve to the next (direct.hpp, make_exact_memory): the
/// body-space pattern of M + Jᵀ D⁻¹ J and CHOLMOD's analysis of it, reused while J's pattern
/// stays the same. Private to the library.
struct ExactMemory;

/// The methods, each one name on the command line, in scene files and in summaries
/// (to_string / method_from_string read the one table of methods, methods.hpp).
enum class Method {
  Pgs,          ///< "pgs": projected Gauss-Seidel (7.1.1), PSOR with relaxation ≠ 1
  BlockPgs,     ///< "block-pgs": contact manifolds solved as blocks (pgs_block.hpp)
  Sgs,          ///< "sgs": symmetric Gauss-Seidel, a forward and a backward sweep
  Jacobi,       ///< "jacobi": projected Jacobi
  MatrixFree,   ///< "matrix-free": 7.1.1 on J and Minv without A (pgs_matrix_free.hpp)
  Direct,       ///< "direct": the exact path (direct.hpp)
  ActiveSet,    ///< "active-set": the previous exact path (active_set.hpp), for comparison
  PgsNesterov,  ///< "pgs-nesterov": PGS with Nesterov momentum and restart (pgs_nesterov.hpp)
  Apgd,         ///< "apgd": accelerated projected gradient descent (apgd.hpp)
  Nncg,         ///< "nncg": nonsmooth nonlinear conjugate gradient on PGS sweeps (nncg.hpp)
  PgsSm,        ///< "pgs-sm": PGS with subspace minimization by CG (pgs_sm.hpp)
  Admm,         ///< "admm": ADMM with one factor of A + rho E (admm.hpp)
  Rbgs,         ///< "rbgs": red-black (graph-coloured) PGS (rbgs.hpp)
  Shock,        ///< "shock": PGS level by level from the ground up (shock.hpp)
  Lemke,        ///< "lemke": Lemke's complementary pivoting, dense, any square A (lemke.hpp)
  Nsgs,         ///< "nsgs": PGS with each contact projected onto its friction cone (nsgs.hpp)
  // The peers (peers/peers.hpp): the field's own solvers, judged by cbps's residual.
  SiconosLemke,  ///< "siconos:lemke": Siconos' lexicographic Lemke (LCP, relay, MLCP)
  SiconosPgs,    ///< "siconos:pgs": Siconos' projected Gauss-Seidel (LCP, relay, MLCP)
  SiconosEnum,   ///< "siconos:enum": Siconos' enumeration (small problems)
  SiconosAvi,    ///< "siconos:avi": Siconos' AVI solver of Cao & Ferris (LCP, relay)
  // Siconos' fc3d solvers: Coulomb's law on friction cones (cone_problem.hpp) only.
  SiconosFc3dNsgs,   ///< "siconos:fc3d-nsgs": non-smooth Gauss-Seidel
  SiconosFc3dNsnAc,  ///< "siconos:fc3d-nsn-ac": non-smooth Newton on Alart-Curnier's function
  SiconosFc3dProx,   ///< "siconos:fc3d-prox": proximal points around NSN-AC
  SiconosFc3dAdmm,   ///< "siconos:fc3d-admm": ADMM on the cones
  BulletDantzig,     ///< "bullet:dantzig": Bullet's Dantzig solver (ODE's)
  BulletLemke,       ///< "bullet:lemke": Bullet's Lemke solver
  BulletPgs          ///< "bullet:pgs": Bullet's projected Gauss-Seidel on the dense A
};

std::string_view to_string(Method method);

/// The exact path (exact/direct.hpp) in its role: the answer every study, check and exported
/// step is judged against or solved with, and the method of `cbps lcp` under mpirun. The
/// studies and commands name the role, not the method.
inline constexpr Method kExactMethod = Method::Direct;
/// The paper's method (7.1.1, projected Gauss-Seidel) in its role: what a scene, a library
/// solve and the solver grammar run when nothing else is named, the sweep a teaching page shows
/// beside a method that does not sweep, and the sweep the studies hold beside the exact path.
inline constexpr Method kPaperMethod = Method::Pgs;
/// The paper's sweep on friction cones (nsgs, docs/cones.md) in its role: a cone scene's default,
/// the sweep a teaching page shows on cones, the exact path's sweeps on cones.
inline constexpr Method kConeSweepMethod = Method::Nsgs;
/// Contact manifolds solved as blocks (compared/pgs_block.hpp) in its role: the stress study's
/// sweep beside the paper's and the exact path on the contact scenes.
inline constexpr Method kBlockMethod = Method::BlockPgs;
/// The pivoting method (exact/lemke.hpp) in its role: the exact answer of a dense problem that
/// is neither symmetric nor on cones (a Siconos LCP or relay file), `cbps lcp`'s default there.
inline constexpr Method kPivotingMethod = Method::Lemke;
/// The method of a name; false (method untouched) for a name that is none.
bool method_from_string(std::string_view name, Method& method);
/// The method of a name known to be one (code, tests); std::invalid_argument otherwise.
Method method_of(std::string_view name);
/// "pgs, block-pgs, sgs, jacobi, matrix-free, direct, active-set", for messages and help.
std::string method_names();
// The questions below read each method's entry in the one table (methods.hpp, MethodEntry).

/// True for the methods that sweep (all but the exact paths and the pivoting methods, cbps's and
/// the peers'): they run to a sweep limit.
bool is_iterative(Method method);
/// The largest problem Method::Lemke takes: its dense tableau is c × 2c (for 3000 rows 144 MB,
/// and a boxed problem doubles its rows); a larger one is an InputError.
inline constexpr long kMaxDenseLemkeRows = 3000;
/// True for the methods that read J (and Minv) rather than A alone: the matrix-free sweep
/// (7.1.1 on J, Minv) and the shock order (layers from J's body blocks). They need a problem
/// that carries J (a step's system, a `cbps matrices` folder; not a Siconos file) and run on the
/// whole of it (an island's problem carries no J).
bool needs_jacobian(Method method);

/// False for the methods that never read A's entries, so that a step solved by them need not
/// form A (issue 32): matrix-free (J and Minv alone, 7.1.1) and direct on the boxed problem
/// (body space; small islands get their A(F, F) formed by the path itself). solve() forms A
/// (formed_A) for every other method when a problem comes without it.
bool reads_A(Method method, bool cones);

/// True for the methods whose derivation needs a symmetric A: they minimise the QP
/// ½ λᵀAλ − bᵀλ of 6.2 over the box, whose optimality conditions are the boxed LCP only when
/// A = Aᵀ (the exact paths direct and active-set, apgd, nncg, pgs-sm, admm). solve() refuses a
/// non-symmetric A for them (InputError). The sweeps of 7.1.1 (pgs, psor, sgs, jacobi, rbgs,
/// block-pgs, shock, pgs-nesterov) take any A with a positive diagonal: they read A's rows
/// (BoxedProblem::A_rows). matrix-free sweeps J Minv Jᵀ, which solve() checks against A.
/// On friction cones (`cones`) direct takes any A: past the relaxation's interior point, which it
/// runs on A's symmetric part, its stages solve the law itself on A (cone/cone_direct.hpp).
bool needs_symmetric(Method method, bool cones = false);

/// True for Siconos' fc3d solvers (peers/peers.hpp): they take only problems whose every row is
/// in a contact under Coulomb's law.
bool is_siconos_fc3d(Method method);

/// True for the methods that solve a problem whose contacts live in friction cones
/// (BoxedProblem::cones, system/cone_problem.hpp) under either law: nsgs and direct
/// (cone/cone_direct.hpp). Siconos' fc3d solvers take Coulomb's law only; apgd, admm and
/// pgs-nesterov the relaxation only (the QP over the cones they minimise, pgs-nesterov's
/// momentum resting on nsgs's sweep descending it): takes_cone_law. solve() refuses the others
/// on such a problem (InputError): they solve the boxed problem of 6.2.
bool takes_cones(Method method);
/// The most rows a method takes (a dense copy of A), 0 for any.
long most_rows(Method method);
/// True for a pivoting method of cbps, whose iterations are its pivots (lemke).
bool counts_pivots(Method method);
/// True when a method that takes cones takes them under `law` (a cone law: CoulombCone or
/// Relaxation).
bool takes_cone_law(Method method, FrictionLaw law);
/// The methods takes_cones names, for messages.
inline constexpr const char* kConeMethodNames =
    "nsgs and direct (and siconos:fc3d-* for Coulomb's law, apgd, admm and pgs-nesterov for the "
    "relaxation)";

/// The relaxation factors omega a method takes: 0 < omega ≤ 1 for Jacobi (damping; above 1
/// it diverges on the simplest chains), 0 < omega < 2 for the rest (SOR's range). The one check
/// scene files and the --solver grammar share.
bool relaxation_in_range(Method method, double omega);
/// That range as text, "(0, 1]" or "(0, 2)".
const char* relaxation_range(Method method);

/// The order in which a Gauss-Seidel sweep visits the rows (7.1.1 uses the natural order).
enum class RowOrder {
  Natural,  ///< 0, 1, …, c−1
  Reverse,  ///< c−1, …, 0
  Random    ///< a fresh permutation every sweep, from SolverOptions::seed
};
std::string to_string(RowOrder order);

/// What a solve is asked, declared once with one set of defaults: a scene's solver block is
/// these (SolverSettings, scene.hpp, adds the warm start) and so is every solve's options
/// (SolverOptions adds what one solve needs at run time), so a library solve() and a scene's
/// step stop and split alike. Fields a method has no use for are ignored by it (the row order by
/// Jacobi, the sweeps by the exact paths).
struct SolveSettings {
  Method method = kPaperMethod;
  int max_iterations = 100;  ///< sweeps (iterative methods)
  /// Stop when the natural-map residual ≤ this, N, for every method; 0: iterative methods run
  /// every sweep, the direct path stops at its rounding floor (direct.hpp); below that floor
  /// it stops there once its steps no longer reduce the residual (may_stop).
  double tolerance = 1e-10;
  double delta_tolerance = 0.0;  ///< stop when max |Δlambda| in a sweep ≤ this (N); 0 = never
  double relaxation = 1.0;       ///< Jacobi damping / SOR factor omega (1 = the paper's 7.1.1)
  bool split_islands = true;     ///< iterative methods: solve independent blocks of A apart
  RowOrder order = RowOrder::Natural;  ///< Gauss-Seidel forms (pgs, matrix-free)
  /// pgs and matrix-free: every sweep visits the distance rows, then all contact normal rows,
  /// then all friction rows, each group in `order` (SweepOrder, pgs.hpp); needs the problem's
  /// row kinds. false: the rows as the system holds them (each contact's friction rows right
  /// after its normal row). Other methods ignore it.
  bool contacts_first = false;
  std::uint64_t seed = 0;  ///< RowOrder::Random: the first permutation's seed
  /// Constraint-force mixing eps, kg⁻¹: every method solves the boxed problem of A + eps E
  /// (with_cfm) instead of A; A itself stays J Minv Jᵀ. Residuals are those of A + eps E. 0: off.
  double cfm = 0.0;
  /// The parameters of the methods that have their own (method_settings.hpp).
  MethodSettings methods;
};

/// Everything one solve is told: the settings, and what the solve needs at run time.
struct SolverOptions : SolveSettings {
  bool describe = true;  ///< write SolverSummary::message (off for each island)
  /// Block PGS: delta / max_j A_jj of the block, added to the diagonal of each block of
  /// several rows before it is solved (see block_pgs_sweep).
  double block_regularization = 1e-7;
  /// The exact paths' own settings (direct.hpp and active_set.hpp describe the methods).
  struct Direct {
    int max_interior = 200;  ///< interior-point iterations (direct)
    /// direct: problems with fewer rows than this (or no bounded row) go to the active-set path
    /// whole, which is exact to round-off on them; 0: the interior point always.
    int interior_from_rows = 500;
    double interior_mu = 1e-13;  ///< stop the interior iterations at μ ≤ this · scale_of (direct)
    double proximal = 1e-12;     ///< the interior Newton systems' ρ, a fraction of max A_kk
    int max_outer_iterations = 500;  ///< proximal-point steps per island (active-set)
    double epsilon = 1e-4;  ///< proximal ε as a fraction of the island's max A_jj (active-set)
    double epsilon_floor = 1e-10;  ///< smallest ε (same units) once the active set settles
    int start_sweeps = 5;          ///< PGS sweeps (7.1.1) that choose the first active set
    bool split_islands =
        true;  ///< active-set: solve independent blocks of A apart (exact either way)
    /// direct: what it keeps between solves (make_exact_memory, direct.hpp); a running
    /// Simulation holds one for all its steps. Null: every solve analyses its pattern anew.
    std::shared_ptr<ExactMemory> memory;
  } direct;
  /// Iterative solvers call this after every sweep with the sweep count, lambda and the seconds
  /// spent in sweeps so far (the call itself is not timed); false ends the solve
  /// (Termination::Stopped). `cbps converge` records its samples here.
  std::function<bool(int, const VecX&, double)> after_sweep;
  /// Wall-clock bound on one solve, s; 0: none. The sweeping methods stop after the sweep that
  /// passes it (Termination::TimeLimit, their lambda the last sweep's); the exact paths
  /// (interior point, crossover, active set, Lemke's pivots, the cone stages, the Coulomb fixed
  /// point) at their next iteration, with their best lambda; a peer's child process is killed at
  /// it (lambda stays the guess: a peer reports no point before its end).
  double time_limit = 0.0;
  /// The sweeping methods read `tolerance` both ways, as the direct path always does: they stop
  /// where the residual is within it in N and the unit-free residual (unit_free.hpp) within it
  /// too. `cbps lcp` sets it for problems read from Siconos and FCLIB files, whose units are their
  /// simulator's (forces near 1e-10 N are within 1e-10 N at λ = 0); false for cbps's scenes and
  /// folders, in SI units, where a step's forces of 1e-13 N are done at 1e-10 N whatever their
  /// unit-free residual. The direct path, which reads `tolerance` both ways on those, reads it as
  /// a unit-free residual alone where this is set (UnitFreeTarget::read; on cones, through
  /// unit-free quantities alone: cone_direct.cpp's Aim): there a newton is not the problem's unit
  /// of force.
  bool tolerance_unit_free = false;
  /// time_limit as a point in time: set by solve() on entry, kept by the solves it makes
  /// inside (a Coulomb fixed point's rounds, an island's solve) so that one limit bounds them all.
  /// The default, time_point::max(): none.
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
};

/// True once options.deadline has passed (never when solve() set none).
bool past_deadline(const SolverOptions& options);

/// Why a solver stopped. NotConverged: the direct path stopped short of its own tolerance (an
/// inconsistent or infeasible system, or stagnation); its best lambda is returned, with the
/// residual that proves how far it is from a solution.
enum class Termination {
  ResidualTolerance,
  DeltaTolerance,
  MaxIterations,
  Direct,
  NotConverged,
  NonFinite,
  Stopped,     ///< SolverOptions::after_sweep returned false
  NoSolution,  ///< Lemke's ray termination: no solution found (none exists if A is copositive-plus)
  /// A peer (peers/peers.hpp) returned a lambda cbps's verdict does not call solved
  /// (system/unit_free.hpp), whatever it said of it
  PeerUnsolved,
  TimeLimit  ///< SolverOptions::time_limit passed before the method's own stop
};
std::string to_string(Termination t);

struct SolverSummary {
  int iterations = 0;  ///< sweeps done; direct: interior iterations; active-set: outer iterations
  double residual = 0.0;   ///< natural-map residual at the end, N
  double delta = 0.0;      ///< max |Δlambda| of the last sweep, N
  int factorizations = 0;  ///< sparse Cholesky factorizations (exact paths)
  int pivots = 0;          ///< active-set exchanges (exact paths)
  /// active-set: islands solved again from 0 after a guess stalled; pgs-nesterov, apgd, nncg:
  /// momentum or direction restarts; pgs-sm: products with A beyond one per iteration (one per CG
  /// start)
  int restarts = 0;
  int islands = 0;        ///< independent blocks of A solved apart (exact paths)
  bool singular = false;  ///< the active-set path found a singular block and regularised it
  int crossover = 0;      ///< direct: the crossover's proximal (outer) steps
  long factor_nnz = 0;    ///< direct: nonzeros of its Cholesky factor
  long updates = 0;       ///< direct: rows added to or removed from a factor by updates
  std::string space;      ///< direct: "body" (M + Jᵀ D⁻¹ J) or "row" (A + D) or "" (none)
  /// direct: how it reached its answer (direct.hpp's steps name them): "guess" (the guess already
  /// solved it), "warm" (the crossover from the guess's partition), "interior" (the interior
  /// point, then the crossover), "active-set" (few rows; also the active-set method's own),
  /// "linear" (no bounded row); "" for the other methods
  std::string route;
  /// A peer's own word on its answer ("info 0", "returned true"; peers.hpp), empty for cbps's
  /// methods; whether that word was success; and the seconds spent converting the problem to
  /// the peer's storage (in wall_time_s, reported apart: the dense peers' conversion).
  std::string peer_status;
  bool peer_said_ok = false;
  double convert_time_s = 0.0;
  double peer_solve_time_s = 0.0;  ///< the peer's own call, s
  int peer_iterations = -1;        ///< as the peer reports them; −1: not exposed
  double wall_time_s = 0.0;
  Termination termination = Termination::MaxIterations;
  std::string message;  ///< one line with the numbers
  bool ok() const { return termination != Termination::NonFinite; }
};

/// Constraint-force mixing, applied once for a whole solve: calls run(problem, options) with A
/// replaced by A + eps E (formed here, once) and options.cfm = 0, or with both as they are when
/// cfm = 0 or the method is matrix-free (its sweep puts eps on its own diagonal).
SolverSummary with_cfm_applied(
    const BoxedProblem& problem,
    const SolverOptions& options,
    const std::function<SolverSummary(const BoxedProblem&, const SolverOptions&)>& run);

/// Solves the problem by options.method from the guess in lambda (resized to zeros if its size
/// is wrong). With options.cfm > 0 every method works on A + eps E (the matrix-free sweep on its
/// own diagonal). With options.split_islands the iterative methods run on each island of A
/// apart, each until its own tolerance; the summary then has the largest sweep count and
/// residual of any island and the worst termination. options.tolerance reaches every method.
/// Method::MatrixFree needs problem.J and problem.Minv, Method::Shock problem.J
/// (std::invalid_argument otherwise); both run on the whole problem even with split_islands.
/// Method::Lemke solves the dense A (any square A, the guess unused, tolerance unused) and
/// throws InputError above kMaxDenseLemkeRows rows; its pivots count as iterations.
/// Checked once per solve (InputError): A symmetric to kSymmetryTolerance for the methods that
/// need it (needs_symmetric; the others then sweep A's rows, from an Aᵀ formed here), and for
/// matrix-free A = J Minv Jᵀ + cfm E on a test vector (factors_mismatch ≤ 1e-12).
SolverSummary solve(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options);

}  // namespace cbps
