// cbps lcp PROBLEM [--solver NAME] [--json] [--out DIR]: solves a stored boxed LCP, either a
// folder written by `cbps matrices` (A, b, cmin, cmax) or a Siconos .dat file (LCP or relay).
//
// Both are held in the paper's convention (6.2): w = A lambda − b, cmin ≤ lambda ≤ cmax, which
// is Siconos' w = M z + q, lb ≤ z ≤ ub with M = A, q = −b, lb = cmin, ub = cmax. The command
// measures the natural-map residual of the returned lambda itself, and prints "solved" only if
// it is ≤ kLcpSolvedTolerance · max(1, ‖q‖∞, max |M_ij|), whatever the solver claims.
//
// `--solver tao:TYPE` (a build with PETSc, docs/distributed.md) solves the same problem by TAO
// under MPI, alone or as `mpirun -n N cbps lcp ...`: every rank reads the problem, rank 0 alone
// prints and writes --out, through the same report as every other solver, and every rank exits
// with the same code.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>

#include "cbps/distributed/tao.hpp"
#include "cbps/error.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/direct.hpp"
#include "cbps/solvers/lemke.hpp"
#include "cbps/solvers/solver.hpp"
#include "common.hpp"
#include "tao_solvers.hpp"

namespace cbps::cli {

namespace {

namespace fs = std::filesystem;

/// The largest problem handed to the dense Lemke solver (its tableau is n × 2n).
constexpr long kMaxLemkeRows = 3000;

struct LcpOptions {
  std::string problem;
  std::string solver;
  int iterations = 10000;
  double tolerance = 1e-10;
  bool json = false;
  std::string out;
  std::string siconos = "auto";
};

bool is_standard_lcp(const StoredProblem& p) {
  return (p.cmin.array() == 0.0).all() && (p.cmax.array() == kInf).all();
}

/// What the solver returned, before the command's own check.
struct Outcome {
  VecX lambda;
  int iterations = 0;
  bool no_solution = false;  ///< Lemke's ray termination
  std::string message;
};

/// What the distributed path adds to its Outcome: it measures the residual itself and says
/// more in the JSON object.
struct OutcomeExtras {
  /// The natural-map residual as the solver measured it (TAO: on its distributed vectors);
  /// empty: the command measures it on lambda.
  std::optional<double> residual;
  /// Fields added to the JSON object (TAO: ranks, tao).
  nlohmann::json fields = nlohmann::json::object();
};

Outcome run_lemke(const StoredProblem& p) {
  if (p.rows() > kMaxLemkeRows)
    throw InputError("--solver lemke: the problem has " + std::to_string(p.rows()) +
                     " rows; the dense Lemke solver takes at most " +
                     std::to_string(kMaxLemkeRows) + " (use --solver pgs)");
  const MatX M = MatX(p.A);
  const VecX q = -p.b;
  const LcpResult r =
      is_standard_lcp(p) ? solve_lemke(M, q) : solve_boxed_lemke(M, q, p.cmin, p.cmax);
  return {r.z, r.pivots, r.status == LcpResult::Status::NoSolution, r.message};
}

Outcome run_iterative(const StoredProblem& p, const LcpOptions& o) {
  for (long k = 0; k < p.rows(); ++k) {
    const double a_kk = p.A.coeff(k, k);
    if (!(a_kk > 0.0)) {
      return {VecX::Zero(p.rows()),
              0,
              false,
              o.solver + ": not run, it needs a positive diagonal; A[" + std::to_string(k) + "," +
                  std::to_string(k) + "] = " + std::to_string(a_kk)};
    }
  }
  SolverOptions options;
  method_from_string(o.solver, options.method);  // pgs or jacobi, checked by lcp_command
  options.max_iterations = o.iterations;
  options.tolerance = o.tolerance;
  VecX lambda = VecX::Zero(p.rows());
  const SolverSummary s = solve(p.problem(), lambda, options);
  return {lambda, s.iterations, false, s.message};
}

std::string format_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

Outcome run_direct(const StoredProblem& p, Method method, double tolerance) {
  // The exact paths are for the paper's A = J Minv Jᵀ: symmetric positive semidefinite.
  require_symmetric(p, "--solver " + std::string(to_string(method)));
  VecX lambda = VecX::Zero(p.rows());
  SolverOptions options;
  options.method = method;
  options.tolerance = tolerance;
  BoxedProblem problem = p.problem();
  problem.cfm = p.cfm;  // lcp_command put it into A
  const SolverSummary s = solve(problem, lambda, options);
  std::ostringstream msg;
  msg << s.message << "; " << s.wall_time_s << " s";
  return {lambda, s.iterations, false, msg.str()};
}

/// The command's verdict on what a solver returned and its report: the residual check (6.2),
/// the JSON object, the text on stdout, --out (result.json, lambda.mtx, only when solved).
/// Every solver's result goes through here, TAO's included (on rank 0 alone). Returns the exit
/// code: 0 solved, 1 not.
int report(const LcpOptions& o,
           const StoredProblem& p,
           bool folder,
           const std::string& solver,
           const Outcome& r,
           double wall,
           OutputDir* dir,
           const OutcomeExtras& extras = {}) {
  // The command's own check of the returned lambda (6.2), independent of the solver's claim.
  const bool sized = r.lambda.size() == p.rows();
  const double residual = !sized            ? kInf
                          : extras.residual ? *extras.residual
                                            : natural_map_residual(p.problem(), r.lambda);
  const double scale = scale_of(p.problem());
  const bool solved = sized && r.lambda.allFinite() && std::isfinite(residual) &&
                      residual <= kLcpSolvedTolerance * scale;
  const std::string status = solved ? "solved" : r.no_solution ? "no_solution" : "failed";

  nlohmann::json j;
  j["problem"] = o.problem;
  j["rows"] = p.rows();
  j["cfm"] = p.cfm;
  j["solver"] = solver;
  j["status"] = status;
  j["iterations"] = r.iterations;
  j["wall_time_s"] = wall;
  j["residual"] = std::isfinite(residual) ? nlohmann::json(residual) : nlohmann::json(nullptr);
  j["scale"] = scale;
  j["message"] = r.message;
  j["lambda"] = sized ? vector_json(r.lambda) : nlohmann::json::array();
  j.update(extras.fields);

  if (solved && dir) {
    write_text(dir->file("result.json"), j.dump(2) + "\n");
    write_matrix_market(dir->file("lambda.mtx"),
                        r.lambda,
                        "lambda: solution of " + o.problem + " by " + solver + ", N");
    dir->commit();
  }
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%s: %ld rows (%s)\n",
                o.problem.c_str(),
                p.rows(),
                folder ? "cbps matrices folder" : "Siconos file");
    if (p.cfm > 0.0)
      std::printf("cfm %s kg^-1 (cfm.txt): solving the boxed problem of A + eps E\n",
                  number_text(p.cfm).c_str());
    std::printf("%s: %s, %d %s, %s s\n",
                solver.c_str(),
                status.c_str(),
                r.iterations,
                solver == "lemke" ? "pivots" : "iterations",
                format_number(wall).c_str());
    std::printf("residual %s (natural map, infinity norm; scale %s)\n",
                format_number(residual).c_str(),
                format_number(scale).c_str());
    std::printf("%s\n", r.message.c_str());
    if (solved && !o.out.empty()) std::printf("wrote %s\n", o.out.c_str());
  }
  if (!solved && !o.out.empty())
    std::fprintf(
        stderr, "cbps: --out %s: not written, the problem was not solved\n", o.out.c_str());
  return solved ? 0 : 1;
}

/// --out must not be the problem's own folder.
void check_out_is_not_problem(const LcpOptions& o) {
  std::error_code ec;
  if (!o.out.empty() && fs::exists(o.out, ec) && fs::equivalent(o.out, o.problem, ec))
    throw InputError("--out " + o.out + ": is the problem itself; choose another folder");
}

/// The problem as every solver here solves it: a folder with cfm.txt is the boxed problem of
/// A + eps E, the one its step solved.
StoredProblem read_lcp_problem(const LcpOptions& o) {
  StoredProblem p = read_problem(o.problem, parse_siconos_kind(o.siconos, "--siconos"));
  p.A = with_cfm(p.A, p.cfm);
  return p;
}

#ifdef CBPS_HAVE_PETSC
/// The exit code main gives an exception (main.cpp): 2 for bad input or usage, else 1.
int exit_code_of(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const InputError&) {
    return 2;
  } catch (const std::invalid_argument&) {
    return 2;
  } catch (...) {
    return 1;
  }
}

/// `--solver tao:TYPE` on every rank of the MPI job (one without mpirun). Bad input on any rank
/// ends every rank with exit 2, reported once, by the lowest rank that found it: the problem is
/// read and checked (and rank 0 opens --out) before anything is distributed, and the ranks agree
/// on the outcome by one reduction, so none is left waiting in a collective call.
int lcp_tao_command(const LcpOptions& o) {
  distributed::MpiSession session;

  // Check the options and read the problem on every rank (for now every rank reads the whole
  // file).
  const std::string& solver = o.solver;
  const std::string type = solver.size() > 4 ? solver.substr(4) : "";
  std::optional<StoredProblem> p;
  std::unique_ptr<OutputDir> dir;
  bool folder = false;
  std::exception_ptr failure;
  try {
    if (!distributed::is_tao_type(type))
      throw InputError("--solver " + solver + ": " +
                       (type.empty() ? "no TAO type" : "unknown TAO type \"" + type + "\"") +
                       "; use tao:TYPE with TYPE one of " + distributed::tao_type_list());
    check_out_is_not_problem(o);
    std::error_code ec;
    folder = fs::is_directory(o.problem, ec);
    p = read_lcp_problem(o);
    // TAO minimises ½ lambdaᵀ A lambda − bᵀ lambda, whose gradient is A lambda − b only for a
    // symmetric A: the paper's A = J Minv Jᵀ.
    require_symmetric(*p, "--solver " + solver);
    if (session.rank() == 0 && !o.out.empty()) dir = std::make_unique<OutputDir>(o.out);
  } catch (...) {
    failure = std::current_exception();
  }
  const int first = session.first_failing_rank(failure != nullptr);
  if (first < session.size()) {
    const int code = session.broadcast(failure ? exit_code_of(failure) : 0, first);
    if (session.rank() == first) std::rethrow_exception(failure);  // main reports it
    return code;
  }

  distributed::TaoOptions options;
  options.type = type;
  options.max_iterations = o.iterations;
  options.tolerance = o.tolerance;
  const auto start = std::chrono::steady_clock::now();
  const distributed::TaoResult t = distributed::solve_tao(session, p->problem(), options);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Rank 0 reports and writes; every rank exits with its code.
  int code = 1;
  failure = nullptr;
  if (session.rank() == 0) {
    try {
      Outcome r;
      r.lambda = t.lambda;
      r.iterations = t.iterations;
      r.message = "TAO " + type + ": " + t.reason + " (" + t.stop + "), TAO's measure " +
                  format_number(t.tao_residual) + " (gatol " + format_number(o.tolerance) + "), " +
                  std::to_string(session.size()) + (session.size() == 1 ? " rank" : " ranks");
      OutcomeExtras extras;
      extras.residual = t.residual;
      extras.fields["ranks"] = session.size();
      extras.fields["tao"] = {
          {"type", type},
          {"reason", t.reason},
          {"converged", t.converged},
          {"stop", t.stop},
          {"measure", number_json(t.tao_residual)},
          {"gatol", o.tolerance},
          // The same residual from the gathered lambda by natural_map_residual, while rank 0
          // still holds the whole problem: the cross-check of the distributed one.
          {"residual_gathered",
           number_json(t.lambda.size() == p->rows() ? natural_map_residual(p->problem(), t.lambda)
                                                    : kInf)}};
      code = report(o, *p, folder, solver, r, wall, dir.get(), extras);
    } catch (...) {
      failure = std::current_exception();
      code = exit_code_of(failure);
    }
  }
  code = session.broadcast(code);
  if (failure) std::rethrow_exception(failure);
  return code;
}
#endif

/// `--solver tao:TYPE`, or without PETSc in the build exit 2 saying how to get it (before
/// anything starts MPI: every process of an mpirun job says it).
int lcp_tao(const LcpOptions& o) {
#ifdef CBPS_HAVE_PETSC
  return lcp_tao_command(o);
#else
  throw InputError(without_petsc_message("--solver " + o.solver));
#endif
}

int lcp_command(const LcpOptions& o) {
  if (is_tao_solver(o.solver)) return lcp_tao(o);
  std::error_code ec;
  const bool folder = fs::is_directory(o.problem, ec);
  check_out_is_not_problem(o);
  // A folder with cfm.txt: the step solved the boxed problem of A + eps E, and so does this.
  const StoredProblem p = read_lcp_problem(o);

  // The default: the exact path for the symmetric A of a `cbps matrices` folder (and for a
  // Siconos file too large for dense Lemke), Lemke for Siconos files.
  std::string solver = o.solver;
  if (solver.empty()) solver = (!folder && p.rows() <= kMaxLemkeRows) ? "lemke" : "direct";
  if (solver != "lemke" && solver != "pgs" && solver != "jacobi" && solver != "direct" &&
      solver != "active-set")
    throw InputError("--solver " + solver +
                     ": unknown; use lemke, pgs, jacobi, direct, active-set or tao:TYPE");
  std::unique_ptr<OutputDir> dir;
  if (!o.out.empty()) dir = std::make_unique<OutputDir>(o.out);

  LcpOptions run = o;
  run.solver = solver;
  const auto start = std::chrono::steady_clock::now();
  const Outcome r = solver == "lemke"        ? run_lemke(p)
                    : solver == "direct"     ? run_direct(p, Method::Direct, o.tolerance)
                    : solver == "active-set" ? run_direct(p, Method::ActiveSet, o.tolerance)
                                             : run_iterative(p, run);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report(o, p, folder, solver, r, wall, dir.get());
}

}  // namespace

void register_lcp(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "lcp", "solve a stored problem: a `cbps matrices` folder or a Siconos .dat file");
  auto o = std::make_shared<LcpOptions>();
  cmd->add_option("PROBLEM", o->problem, "folder from `cbps matrices`, or a Siconos .dat file")
      ->required();
  cmd->add_option("--solver",
                  o->solver,
                  "lemke (dense, any square A; the default for Siconos files up to 3000 rows), "
                  "pgs, jacobi, direct (interior point in body space with a crossover, "
                  "symmetric positive semidefinite A; the default for cbps matrices folders), "
                  "active-set (the previous exact path: active set on CHOLMOD) or tao:TYPE "
                  "(PETSc/TAO under MPI, alone or under `mpirun -n N`; symmetric A; TYPE one of " +
                      distributed::tao_type_list() +
                      "; only in a build with PETSc, docs/distributed.md)");
  cmd->add_option("--iterations",
                  o->iterations,
                  "pgs/jacobi: sweeps; tao:TYPE: TAO's iterations (default 10000)")
      ->check(positive());
  cmd->add_option(
         "--tolerance",
         o->tolerance,
         "pgs/jacobi/direct/active-set: stop at this natural-map residual, N (default 1e-10; "
         "below their rounding floor the exact paths stop there once their steps no longer "
         "reduce the residual; not used by lemke). tao:TYPE: TAO's absolute tolerance gatol "
         "on its own measure (a 2-norm of the gradient without the rows TAO holds at a bound; "
         "for bqpip its mean infeasibility), not the natural-map residual: the result is "
         "judged solved by that residual <= 1e-9 max(1, |b|inf, max |A_ij|) whatever TAO "
         "says")
      ->check(non_negative());
  cmd->add_option("--siconos",
                  o->siconos,
                  "what a .dat file holds: auto (from the count of numbers: n^2 + n an LCP, "
                  "n^2 + 3n a relay problem), lcp or relay (default auto)");
  cmd->add_flag("--json", o->json, "print the result as JSON");
  cmd->add_option("--out",
                  o->out,
                  "write result.json and lambda.mtx here (only if solved; under mpirun rank 0 "
                  "writes)");
  cmd->callback([&run, o] { run = [o] { return lcp_command(*o); }; });
}

}  // namespace cbps::cli
