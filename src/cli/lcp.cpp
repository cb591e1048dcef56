// cbps lcp PROBLEM [--solver NAME] [--json] [--out DIR]: solves a stored problem, a folder
// written by `cbps matrices`, a Siconos .dat file or an FCLIB file.
//
// The solve and cbps's verdict on it are studies/lcp.hpp, the paths across the ranks of an MPI
// job (`--solver tao:TYPE`, `mpirun -n N cbps lcp FOLDER --solver direct`, `--generate SCENE`)
// distributed/lcp_job.hpp; here the options and the report, the same for every solver (rank 0
// alone reports under MPI).
#include "cbps/studies/lcp.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>

#include "cbps/base/error.hpp"
#include "cbps/distributed/lcp_job.hpp"
#include "cbps/distributed/tao.hpp"
#include "cbps/io/fclib_file.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/exact/lemke.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "common.hpp"
#include "tao_solvers.hpp"

namespace cbps::cli {

namespace {

namespace fs = std::filesystem;

struct LcpOptions {
  std::string problem;
  std::string solver;
  int iterations = kProblemIterations;
  double tolerance = SolveSettings{}.tolerance;  ///< N, the one default (solver.hpp)
  double time_limit = 0.0;                       ///< --time-limit, s; 0: none
  bool json = false;
  bool quiet = false;  ///< --quiet: no line every 2 s of a long solve
  std::string out;
  std::string siconos = "auto";
  std::string cone;      ///< --cone coulomb|ccp: an FCLIB file's law (default: Coulomb's, FCLIB's)
  std::string generate;  ///< --generate SCENE: built per rank instead of read (chain, pyramid)
  std::string rows;      ///< --rows N (text: 1e6 accepted)
  std::string write_system;  ///< --write-system DIR: the generated A, b, cmin, cmax (small)
};

/// The report of what a solver returned: cbps's verdict (judge), the JSON object, the text on
/// stdout, --out (result.json, lambda.mtx, only when solved). Every solver's result goes
/// through here, TAO's included (on rank 0 alone). Returns the exit code: 0 solved, 1 not.
int report(const LcpOptions& o,
           const LcpFacts& p,
           const std::string& solver,
           const LcpOutcome& r,
           double wall,
           OutputDir* dir,
           const distributed::LcpJobReport& extras = {}) {
  const LcpVerdict v = judge(p, r, extras.residual, extras.unit_free);
  nlohmann::json j = lcp_result_json(o.problem, p, solver, r, v, wall);
  j.update(extras.fields);

  if (v.solved && dir) {
    write_text(dir->file("result.json"), j.dump(2) + "\n");
    write_matrix_market(dir->file("lambda.mtx"),
                        r.lambda,
                        "lambda: solution of " + o.problem + " by " + solver + ", N");
    dir->commit();
  }
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%s", lcp_text(o.problem, p, solver, r, v, wall).c_str());
    if (v.solved && !o.out.empty()) std::printf("wrote %s\n", o.out.c_str());
  }
  if (!v.solved && !o.out.empty())
    std::fprintf(
        stderr, "cbps: --out %s: not written, the problem was not solved\n", o.out.c_str());
  return v.solved ? 0 : 1;
}

/// True when an MPI launcher started this process (mpirun, mpiexec: Open MPI's
/// OMPI_COMM_WORLD_SIZE or MPICH's PMI_SIZE, as main.cpp's mpi_job reads them): then `--solver
/// direct` is the exact path under MPI, at any number of ranks.
bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

/// --solver direct under an MPI launcher (launched_by_mpirun) or on a generated problem: the
/// exact path under MPI.
bool is_distributed_direct(const LcpOptions& o) {
  return o.solver == to_string(kExactMethod) && (launched_by_mpirun() || !o.generate.empty());
}

/// `--solver tao:TYPE`, `--solver direct` under mpirun or `--generate SCENE` on every rank of the
/// MPI job (distributed/lcp_job.hpp), rank 0 reporting through report(); or without PETSc in the
/// build exit 2 saying how to get it (before anything starts MPI: every process of an mpirun
/// job says it).
int lcp_distributed(const LcpOptions& o) {
#ifdef CBPS_HAVE_PETSC
  distributed::LcpJob job;
  job.problem = o.problem;
  job.solver = o.solver;
  job.direct = is_distributed_direct(o);
  job.iterations = o.iterations;
  job.tolerance = o.tolerance;
  job.time_limit = o.time_limit;
  job.generate = o.generate;
  job.rows = o.rows;
  job.write_system = o.write_system;
  job.out = o.out;
  job.read_whole = [&o] { return read_problem(o.problem, o.siconos, o.cone); };
  return distributed::run_lcp_job(job, [&o](const distributed::LcpJobReport& r) {
    LcpOptions named = o;
    named.problem = r.problem;
    return report(named, r.facts, o.solver, r.outcome, r.wall, r.dir, r);
  });
#else
  throw InputError(without_petsc_message(o.generate.empty() ? "--solver " + o.solver
                                                            : "--generate " + o.generate));
#endif
}

int lcp_command(const LcpOptions& o) {
  if (!o.generate.empty()) return lcp_distributed(o);
  if (!o.rows.empty() || !o.write_system.empty())
    throw InputError(std::string(!o.rows.empty() ? "--rows" : "--write-system") +
                     ": only with --generate SCENE");
  if (o.problem.empty())
    throw InputError(
        "PROBLEM: missing; give a cbps matrices folder or a Siconos .dat file "
        "(or --generate SCENE --rows N)");
  if (is_tao_solver(o.solver) || is_distributed_direct(o)) return lcp_distributed(o);
  // The spec first: a bad name is reported before the data are read.
  std::optional<SolverSpec> given;
  if (!o.solver.empty()) given = parse_cli_solver_spec(o.solver, "--solver");
  check_out_is_not_input(o.out, o.problem, "--out");
  StoredProblem p = read_problem(o.problem, o.siconos, o.cone);
  // A folder with cfm.txt: the step solved the boxed problem of A + eps E, and so does every
  // solver here (options.cfm, applied by solve()); the residual is that problem's.

  // The default (lcp --help says it, once): the exact path for a `cbps matrices` folder, for a
  // problem on cones (whatever its A) and for a Siconos file too large for dense Lemke; Lemke
  // for the other Siconos files.
  const bool cones = !p.cones.empty();
  const Method fallback =
      !cones && !p.folder && p.rows() <= kMaxDenseLemkeRows ? kPivotingMethod : kExactMethod;
  const SolverSpec spec =
      given ? *given : parse_solver_spec(std::string(to_string(fallback)), "--solver");
  check_applicable(spec, p, o.problem);
  std::unique_ptr<OutputDir> dir;
  if (!o.out.empty()) dir = std::make_unique<OutputDir>(o.out);

  const auto start = std::chrono::steady_clock::now();
  LcpOutcome r;
  {
    // A peer or an exact path shows nothing until it ends: a line every 2 s meanwhile.
    const Heartbeat beat("cbps lcp: " + spec.text + " on " + o.problem, o.time_limit, o.quiet);
    r = solve_stored(spec, p, o.iterations, o.tolerance, o.time_limit);
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report(o, lcp_facts(p), spec.text, r, wall, dir.get());
}

}  // namespace

void register_lcp(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "lcp",
      "solve a stored problem: a `cbps matrices` folder, a Siconos .dat file or an FCLIB file");
  auto o = std::make_shared<LcpOptions>();
  cmd->add_option("PROBLEM",
                  o->problem,
                  "folder from `cbps matrices`, a Siconos .dat file (LCP, relay, or a "
                  "frictional-contact dump, local or global), or an FCLIB problem (HDF5, "
                  "docs/cones.md) (required unless --generate)");
  cmd->add_option(
      "--solver",
      o->solver,
      "NAME[:OMEGA][:key=value]... of the list below (" + cli_solver_names() +
          "), with the parameters the list gives. Default: direct (the exact path: interior "
          "point with a crossover, in body space when the folder has J.mtx and Minv.mtx; on "
          "friction cones its second-order-cone form, any A), except lemke for a Siconos LCP or "
          "relay file of up to 3000 rows. Cones are solved by nsgs, direct and Siconos' "
          "siconos:fc3d-nsgs, -nsn-ac, -prox, -admm. "
          "direct (except on cones) and active-set need a symmetric A, lemke takes any square "
          "A; "
          "matrix-free and shock read J and Minv (a cbps matrices folder, not a "
          "Siconos file); tao:TYPE is PETSc/TAO under MPI, alone or under "
          "`mpirun -n N` (symmetric A; TYPE one of " +
          distributed::tao_type_list() +
          "; only in a build with PETSc, docs/distributed.md); "
          "direct under `mpirun -n N` (any N) is the exact path across the ranks, each reading "
          "its rows of a folder's J and Minv (docs/distributed.md#the-exact-path-under-mpi)");
  cmd->add_option("--iterations",
                  o->iterations,
                  "the iterative methods (all but direct, active-set and lemke): at most this "
                  "many sweeps (apgd, admm, nncg, pgs-sm: iterations); tao:TYPE: TAO's "
                  "iterations (default " +
                      std::to_string(kProblemIterations) + ")")
      ->check(positive());
  cmd->add_option(
         "--tolerance",
         o->tolerance,
         "every method but lemke and tao:TYPE: stop at this natural-map residual, N (default " +
             number_text(o->tolerance) +
             "; the direct path, and every method on a Siconos or FCLIB file, also read it as a "
             "unit-free residual, docs/cones.md; below their "
             "rounding floor the exact paths stop there once their steps no longer reduce the "
             "residual; lemke pivots to the end). tao:TYPE: TAO's absolute tolerance gatol on "
             "its own measure (a 2-norm of the gradient without the rows TAO holds at a bound; "
             "for bqpip its mean infeasibility), not the natural-map residual. Whatever the "
             "method says, the result is judged solved when its unit-free residual is <= 1e-9, "
             "under mpirun too (the ranks form it from their rows)")
      ->check(non_negative());
  cmd->add_option("--time-limit",
                  o->time_limit,
                  "stop the solve after this many seconds of wall time (default 0: no limit): "
                  "the sweeping methods after the sweep that passes it, a Siconos peer's "
                  "child process killed at it; the status is then \"time limit\" (exit 1) "
                  "unless the answer reached is solved")
      ->check(non_negative());
  add_problem_options(cmd, o->siconos, o->cone);
  cmd->add_option("--generate",
                  o->generate,
                  "instead of PROBLEM, build the problem per rank, no rank holding all of it "
                  "(the built-in scene at step 0, numbered as `cbps matrices SCENE --step 0`; "
                  "with --rows; only in a build with PETSc, docs/distributed.md): chain (one "
                  "row per link, A's rows; --solver tao:TYPE) or pyramid (contact and friction "
                  "rows, J's rows and the bodies' Minv; --solver direct)");
  cmd->add_option("--rows",
                  o->rows,
                  "--generate: the problem's rows, 1 to 1e7 (1e6 accepted; chain: its links; "
                  "pyramid: at least this many, the smallest base with 12 base^2 >= N)");
  cmd->add_option("--write-system",
                  o->write_system,
                  "--generate: also write the generated A, b, cmin, cmax (pyramid: and J, "
                  "Minv) here, gathered onto rank 0 (a debugging aid, at most " +
                      std::to_string(distributed::kMaxGatheredRows) + " rows)");
  add_json_flag(cmd, o->json, "the result");
  add_quiet_flag(cmd, o->quiet, "no progress line on stderr every 2 s of a long solve");
  add_out_option(
      cmd, o->out, "result.json and lambda.mtx, only if solved (under mpirun rank 0 writes)");
  cmd->footer(solver_spec_help() + tao_spec_help());
  cmd->callback([&run, o] { run = [o] { return lcp_command(*o); }; });
}

}  // namespace cbps::cli
