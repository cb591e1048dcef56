// cbps lcp PROBLEM [--solver NAME] [--json] [--out DIR]: solves a stored boxed LCP, either a
// folder written by `cbps matrices` (A, b, cmin, cmax) or a Siconos .dat file (LCP or relay).
//
// Both are held in the paper's convention (6.2): w = A lambda − b, cmin ≤ lambda ≤ cmax, which
// is Siconos' w = M z + q, lb ≤ z ≤ ub with M = A, q = −b, lb = cmin, ub = cmax. The command
// measures the natural-map residual of the returned lambda itself, and prints "solved" only if
// it is ≤ kLcpSolvedTolerance · max(1, ‖q‖∞, max |M_ij|), whatever the solver claims.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cbps/error.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/direct.hpp"
#include "cbps/solvers/lemke.hpp"
#include "cbps/solvers/solver.hpp"
#include "common.hpp"

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

int lcp_command(const LcpOptions& o) {
  std::error_code ec;
  const bool folder = fs::is_directory(o.problem, ec);
  if (!o.out.empty() && fs::exists(o.out, ec) && fs::equivalent(o.out, o.problem, ec))
    throw InputError("--out " + o.out + ": is the problem itself; choose another folder");
  // A folder with cfm.txt: the step solved the boxed problem of A + eps E, and so does this.
  StoredProblem p = read_problem(o.problem, parse_siconos_kind(o.siconos, "--siconos"));
  p.A = with_cfm(p.A, p.cfm);

  // The default: the exact path for the symmetric A of a `cbps matrices` folder (and for a
  // Siconos file too large for dense Lemke), Lemke for Siconos files.
  std::string solver = o.solver;
  if (solver.empty()) solver = (!folder && p.rows() <= kMaxLemkeRows) ? "lemke" : "direct";
  if (solver != "lemke" && solver != "pgs" && solver != "jacobi" && solver != "direct" &&
      solver != "active-set")
    throw InputError("--solver " + solver +
                     ": unknown; use lemke, pgs, jacobi, direct or active-set");
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

  // The command's own check of the returned lambda (6.2), independent of the solver's claim.
  const bool sized = r.lambda.size() == p.rows();
  const double residual = sized ? natural_map_residual(p.problem(), r.lambda) : kInf;
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
                  "symmetric positive semidefinite A; the default for cbps matrices folders) or "
                  "active-set (the previous exact path: active set on CHOLMOD)");
  cmd->add_option("--iterations", o->iterations, "pgs/jacobi: sweeps (default 10000)")
      ->check(positive());
  cmd->add_option(
         "--tolerance",
         o->tolerance,
         "pgs/jacobi/direct/active-set: stop at this natural-map residual, N (default 1e-10; "
         "below their rounding floor the exact paths stop there once their steps no longer "
         "reduce the residual; not used by lemke)")
      ->check(non_negative());
  cmd->add_option("--siconos",
                  o->siconos,
                  "what a .dat file holds: auto (from the count of numbers: n^2 + n an LCP, "
                  "n^2 + 3n a relay problem), lcp or relay (default auto)");
  cmd->add_flag("--json", o->json, "print the result as JSON");
  cmd->add_option("--out", o->out, "write result.json and lambda.mtx here (only if solved)");
  cmd->callback([&run, o] { run = [o] { return lcp_command(*o); }; });
}

}  // namespace cbps::cli
