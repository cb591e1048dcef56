// cbps lcp PROBLEM [--solver NAME] [--json] [--out DIR]: solves a stored boxed LCP, either a
// folder written by `cbps matrices` (A, b, cmin, cmax) or a Siconos .dat file (LCP or relay).
//
// The solve and cbps's verdict on it are studies/lcp.hpp; here the options, the distributed path
// and the report.
//
// `--solver tao:TYPE` (a build with PETSc, docs/distributed.md) solves the same problem by TAO
// under MPI, alone or as `mpirun -n N cbps lcp ...`: every rank holds only its own rows (a
// folder read by rows, docs/distributed.md#reading-a-folder-by-rows), rank 0 alone prints and
// writes --out, through the same report as every other solver, and every rank exits with the
// same code.
//
// `mpirun -n N cbps lcp FOLDER --solver direct` runs the exact path under MPI
// (distributed/exact.hpp, docs/distributed.md#the-exact-path-under-mpi): every rank reads its rows
// of J, b, cmin, cmax and its bodies' rows of Minv, and reports as the TAO path does.
//
// `--generate chain --rows N --solver tao:TYPE` builds the problem instead of reading it, each
// rank only its own rows (distributed/generate.hpp, docs/distributed.md#generated-problems),
// and reports through the same report(); no rank holds the whole problem.
#include "cbps/studies/lcp.hpp"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/distributed/exact.hpp"
#include "cbps/distributed/generate.hpp"
#include "cbps/distributed/tao.hpp"
#include "cbps/io/fclib_file.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/exact/lemke.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "cbps/system/system.hpp"
#include "common.hpp"
#include "tao_solvers.hpp"

namespace cbps::cli {

namespace {

namespace fs = std::filesystem;

struct LcpOptions {
  std::string problem;
  std::string solver;
  int iterations = 10000;
  double tolerance = 1e-10;
  double time_limit = 0.0;  ///< --time-limit, s; 0: none
  bool json = false;
  bool quiet = false;  ///< --quiet: no line every 2 s of a long solve
  std::string out;
  std::string siconos = "auto";
  std::string cone;      ///< --cone coulomb|ccp: an FCLIB file's law (default: Coulomb's, FCLIB's)
  std::string generate;  ///< --generate SCENE: built per rank instead of read (chain, pyramid)
  std::string rows;      ///< --rows N (text: 1e6 accepted)
  std::string write_system;  ///< --write-system DIR: the generated A, b, cmin, cmax (small)
};

/// The largest generated problem --write-system gathers onto rank 0, and whose lambda the JSON
/// object carries.
constexpr long kMaxGatheredRows = 100000;

/// What the distributed path adds to its LcpOutcome: it measures the residual itself and says
/// more in the JSON object.
struct OutcomeExtras {
  /// The natural-map residual and the unit-free residual as the solver measured them on rows
  /// spread over ranks (TAO, direct under MPI); empty: the command measures them on lambda.
  std::optional<double> residual;
  std::optional<UnitFreeResidual> unit_free;
  /// Fields added to the JSON object (TAO: ranks, tao).
  nlohmann::json fields = nlohmann::json::object();
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
           const OutcomeExtras& extras = {}) {
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
    std::printf("%s: %ld rows (%s)\n", o.problem.c_str(), p.rows, p.kind.c_str());
    if (p.cfm > 0.0)
      std::printf("cfm %s kg^-1 (cfm.txt): solving the boxed problem of A + eps E\n",
                  number_text(p.cfm).c_str());
    std::printf("%s: %s, %d %s, %s s\n",
                solver.c_str(),
                v.status.c_str(),
                r.iterations,
                r.pivots ? "pivots" : "iterations",
                number_text(wall).c_str());
    if (v.unit_free)
      std::printf("unit-free residual %s (%s N over the force scale %s N; solved at <= %s)\n",
                  number_text(v.unit_free->relative).c_str(),
                  number_text(v.unit_free->residual).c_str(),
                  number_text(v.unit_free->scale).c_str(),
                  number_text(kSolvedTolerance).c_str());
    std::printf("residual %s (natural map, infinity norm; data scale %s)\n",
                number_text(v.residual).c_str(),
                number_text(v.scale).c_str());
    std::printf("%s\n", r.message.c_str());
    if (!v.peer_disagrees.empty()) std::printf("%s\n", v.peer_disagrees.c_str());
    if (v.cone)
      std::printf(
          "cone law %s, %ld contacts: Signorini gap %s, cone violation %s N, dissipation gap "
          "%s, FCLIB merit %s, Siconos error %s\n",
          std::string(to_string(p.stored->cones.law)).c_str(),
          p.stored->cones.contacts(),
          number_text(v.cone->signorini).c_str(),
          number_text(v.cone->violation).c_str(),
          number_text(v.cone->dissipation).c_str(),
          number_text(v.cone->fclib_merit).c_str(),
          number_text(v.cone->siconos_error).c_str());
    if (!r.space_reason.empty()) std::printf("space %s\n", r.space_reason.c_str());
    if (v.solved && !o.out.empty()) std::printf("wrote %s\n", o.out.c_str());
  }
  if (!v.solved && !o.out.empty())
    std::fprintf(
        stderr, "cbps: --out %s: not written, the problem was not solved\n", o.out.c_str());
  return v.solved ? 0 : 1;
}

/// PROBLEM read whole, with --cone's law for its contacts in friction cones.
StoredProblem read_lcp_problem(const LcpOptions& o) {
  const SiconosKind kind = parse_siconos_kind(o.siconos, "--siconos");
  std::error_code ec;
  if (kind != SiconosKind::Auto && (fs::is_directory(o.problem, ec) || is_hdf5_file(o.problem)))
    throw InputError(
        "--siconos " + o.siconos + ": says what a Siconos .dat file holds; " + o.problem + " is " +
        (fs::is_directory(o.problem, ec) ? "a cbps matrices folder" : "an HDF5 (FCLIB) file") +
        ", whose kind its files say");
  StoredProblem p = read_problem(o.problem, kind);
  apply_cone_option(p, o.cone, o.problem);
  return p;
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
  return o.solver == "direct" && (launched_by_mpirun() || !o.generate.empty());
}

/// --out must not be the problem's own folder.
void check_out_is_not_problem(const LcpOptions& o) {
  std::error_code ec;
  if (!o.out.empty() && fs::exists(o.out, ec) && fs::equivalent(o.out, o.problem, ec))
    throw InputError("--out " + o.out + ": is the problem itself; choose another folder");
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

/// --rows N as a whole number of rows: "1000", "1e6" (parse_number's forms), 1 … 1e7 (the
/// chain's largest n).
long parse_rows(const std::string& text) {
  double value = 0.0;
  if (!parse_number(text, value) || value != std::floor(value) || value < 1.0 || value > 1e7)
    throw InputError("--rows " + text + ": not a whole number of rows from 1 to 1e7 (e.g. 1e6)");
  return static_cast<long>(value);
}

/// This process's peak resident memory so far (getrusage ru_maxrss, KiB on Linux), MB.
double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

/// The base of the smallest pyramid with at least `rows` rows: 12 base² (base² box pairs in
/// contact, the ground's base and two under each of the other boxes, of 4 points with one
/// contact and two friction rows each, 5.3, 5.4), so base = ⌈√(rows / 12)⌉.
long pyramid_base_for(long rows) {
  auto base = static_cast<long>(std::ceil(std::sqrt(static_cast<double>(rows) / 12.0)));
  while (base > 1 && 12 * (base - 1) * (base - 1) >= rows) --base;
  while (12 * base * base < rows) ++base;
  return base;
}

/// The options of the distributed path checked before anything is distributed; the number of
/// rows of a generated problem (0 for a read one).
long check_distributed_options(const LcpOptions& o, const std::string& type) {
  const bool generated = !o.generate.empty();
  if (generated && !o.problem.empty())
    throw InputError("--generate " + o.generate + ": give either PROBLEM (" + o.problem +
                     ") or --generate, not both");
  if (generated && o.generate != "chain" && o.generate != "pyramid")
    throw InputError("--generate " + o.generate +
                     ": unknown; the generators are chain (solved by tao:TYPE) and pyramid "
                     "(solved by direct)");
  if (o.generate == "pyramid" && o.solver != "direct")
    throw InputError("--generate pyramid: --solver " + (o.solver.empty() ? "(none)" : o.solver) +
                     ": a generated pyramid is solved by the exact path, --solver direct (each "
                     "rank builds its rows of J and Minv; A, which TAO needs, is never formed)");
  if (o.generate == "chain" && !is_tao_solver(o.solver))
    throw InputError("--generate: --solver " + (o.solver.empty() ? "(none)" : o.solver) +
                     ": a generated chain (its rows of A alone) is solved by tao:TYPE with TYPE "
                     "one of " +
                     distributed::tao_type_list());
  if (!is_distributed_direct(o) && !distributed::is_tao_type(type))
    throw InputError("--solver " + o.solver + ": " +
                     (type.empty() ? "no TAO type" : "unknown TAO type \"" + type + "\"") +
                     "; use tao:TYPE with TYPE one of " + distributed::tao_type_list());
  if (!is_distributed_direct(o) && o.time_limit > 0.0)
    throw InputError("--time-limit: --solver " + o.solver +
                     " in cbps lcp runs TAO on every rank to --iterations, and a limit of time "
                     "would stop the ranks at different iterations; bound it by --iterations "
                     "(cbps converge and profile bound tao:TYPE by time, on one process)");
  if (!generated) {
    check_out_is_not_problem(o);
    return 0;
  }
  if (o.rows.empty()) throw InputError("--generate " + o.generate + ": --rows N is required");
  const long rows = parse_rows(o.rows);
  // The rows generated: a pyramid's 12 base² may exceed the N asked for.
  const long base = o.generate == "pyramid" ? pyramid_base_for(rows) : 0;
  const long generated_rows = o.generate == "pyramid" ? 12 * base * base : rows;
  if (!o.write_system.empty() && generated_rows > kMaxGatheredRows)
    throw InputError("--write-system: " + std::to_string(generated_rows) +
                     " rows; it gathers the whole problem onto rank 0 and takes at most " +
                     std::to_string(kMaxGatheredRows));
  if (!o.write_system.empty() && !o.out.empty() && o.write_system == o.out)
    throw InputError("--write-system " + o.write_system + ": the same folder as --out");
  return rows;
}

/// What the distributed path calls the method it runs, for its messages.
std::string distributed_solver_name(const LcpOptions& o) {
  return is_distributed_direct(o) ? "--solver direct under mpirun (the exact path under MPI)"
                                  : "--solver " + o.solver + " (PETSc/TAO)";
}

/// The distributed paths solve the boxed problem of 6.2 only: a folder whose contacts live in
/// friction cones (cones.json) is refused, naming the serial methods that solve it.
void refuse_cones(const LcpOptions& o, const std::string& solver) {
  const long contacts = folder_cone_contacts(o.problem);
  if (contacts == 0) return;
  throw InputError(solver + ": " + o.problem + ": its " + std::to_string(contacts) +
                   (contacts == 1 ? " contact lives" : " contacts live") +
                   " in friction cones (cones.json), and this path solves only the boxed "
                   "problem of 6.2. `cbps lcp " +
                   o.problem +
                   " --solver direct` (without mpirun: the exact path on cones) or --solver nsgs "
                   "solves it (docs/cones.md)");
}

/// This rank's rows: generated, read by rows from a `cbps matrices` folder, or cut from a
/// Siconos file every rank reads (small, dense); `kind` says which, for report().
distributed::LocalSystem local_rows(const LcpOptions& o,
                                    long rows,
                                    const distributed::MpiSession& session,
                                    std::string& kind) {
  std::error_code ec;
  if (o.generate == "chain") {
    kind = "generated";
    return distributed::generate_chain(
        {{"n", std::to_string(rows)}}, session.rank(), session.size());
  }
  if (o.generate == "pyramid") {
    kind = "generated, J and Minv built per rank";  // numbered by lcp_distributed_command
    return distributed::generate_pyramid(
        {{"base", std::to_string(pyramid_base_for(rows))}}, session.rank(), session.size());
  }
  if (!fs::exists(o.problem, ec)) throw InputError(o.problem + ": no such file or folder");
  if (fs::is_directory(o.problem, ec)) refuse_cones(o, distributed_solver_name(o));
  if (is_distributed_direct(o)) {
    if (!fs::is_directory(o.problem, ec))
      throw InputError("--solver direct under mpirun: " + o.problem +
                       ": not a cbps matrices folder; the exact path under MPI works in body "
                       "space and reads J and Minv by rows (a Siconos or FCLIB file has "
                       "neither); without mpirun, `cbps lcp " +
                       o.problem + " --solver direct` solves it on one process");
    kind = "cbps matrices folder, J and Minv read by rows";
    return distributed::read_folder_factors(o.problem, session.rank(), session.size());
  }
  if (fs::is_directory(o.problem, ec)) {
    kind = "cbps matrices folder, read by rows";
    return distributed::read_folder_rows(o.problem, session.rank(), session.size());
  }
  StoredProblem p = read_lcp_problem(o);
  if (!p.cones.empty())
    throw InputError("--solver " + o.solver + ": " + o.problem + ": its " +
                     std::to_string(p.cones.contacts()) +
                     " contacts live in friction cones; TAO solves the boxed problem of 6.2. Use "
                     "--solver nsgs (docs/cones.md)");
  kind = "Siconos file";
  return distributed::rows_of(p.problem(), p.cfm, o.problem, session.rank(), session.size());
}

/// --write-system: the gathered A, b, cmin, cmax of a generated problem (rank 0).
void write_gathered(distributed::GatheredSystem& g,
                    const std::string& description,
                    OutputDir& dir) {
  StoredProblem gathered;  // g is written once, then unused: moved
  // The exact path's problems come as J and Minv: A = J Minv Jᵀ (6.2.9) formed here (small).
  gathered.A = g.J.rows() > 0 ? compute_A(g.J, g.Minv) : std::move(g.A);
  gathered.J = std::move(g.J);
  gathered.Minv = std::move(g.Minv);
  gathered.b = std::move(g.b);
  gathered.cmin = std::move(g.cmin);
  gathered.cmax = std::move(g.cmax);
  write_problem(gathered,
                [&](const std::string& name, const auto& write) { write(dir.file(name)); },
                {"; " + description, ""});
  dir.commit();
}

/// What the distributed path knows when rank 0 reports.
struct TaoReport {
  std::string type;
  std::string kind;
  long rows = 0;
  double read_wall = 0.0;  ///< rank 0's time to build or read its rows, s
  double wall = 0.0;       ///< TAO's, s
  std::vector<double> memory;
};

/// "1 rank", "2 ranks".
std::string ranks_text(const distributed::MpiSession& session) {
  return std::to_string(session.size()) + (session.size() == 1 ? " rank" : " ranks");
}

/// What every distributed report adds (ranks, each rank's memory, the time to read or build the
/// rows) and its facts (rows, cfm, the scale measured on the distributed problem), then report().
int report_ranks(const LcpOptions& o,
                 const distributed::MpiSession& session,
                 const distributed::LocalSystem& local,
                 const TaoReport& at,
                 const LcpOutcome& r,
                 double scale,
                 OutcomeExtras& extras,
                 OutputDir* dir) {
  extras.fields["ranks"] = session.size();
  if (!o.generate.empty())
    extras.fields["generated"] = {{"scene", o.generate},
                                  {"description", local.description},
                                  {"step", 0},
                                  {"wall_time_s", at.read_wall}};
  else
    extras.fields["read_wall_time_s"] = at.read_wall;
  extras.fields["rank_memory_mb"] = at.memory;
  LcpFacts facts;
  facts.rows = at.rows;
  facts.cfm = local.cfm;
  facts.kind = at.kind + " on " + ranks_text(session);
  facts.scale = scale;
  facts.lambda_in_json = at.rows <= kMaxGatheredRows;
  LcpOptions named = o;
  named.problem = local.description;
  return report(named, facts, o.solver, r, at.wall, dir, extras);
}

/// Rank 0's report of TAO's answer, through the same report() as every solver (the residuals
/// and scale measured on the distributed vectors); the exit code.
int report_tao(const LcpOptions& o,
               const distributed::MpiSession& session,
               const distributed::LocalSystem& local,
               distributed::TaoResult& t,
               const TaoReport& at,
               OutputDir* dir,
               OutputDir* system_dir) {
  if (t.asymmetric)
    throw InputError("--solver " + o.solver +
                     ": needs a symmetric A (TAO minimises 1/2 lambda^T A lambda - b^T "
                     "lambda, whose gradient is A lambda - b only then); max |A - A^T| = " +
                     number_text(t.asymmetry) + "; `cbps lcp --solver lemke` solves any square A");
  if (system_dir != nullptr) write_gathered(t.gathered, local.description, *system_dir);
  const std::string ranks = ranks_text(session);
  LcpOutcome r;
  r.lambda = t.lambda;
  r.iterations = t.iterations;
  r.space_reason = "none: TAO " + at.type + " factors no Newton system";
  r.message = "TAO " + at.type + ": " + t.reason + " (" + t.stop + "), TAO's measure " +
              number_text(t.tao_residual) + " (gatol " + number_text(o.tolerance) + "), " + ranks;
  OutcomeExtras extras;
  extras.residual = t.residual;
  extras.unit_free = t.unit_free;
  extras.fields["tao"] = {{"type", at.type},
                          {"reason", t.reason},
                          {"converged", t.converged},
                          {"stop", t.stop},
                          {"measure", number_json(t.tao_residual)},
                          {"gatol", o.tolerance}};
  return report_ranks(o, session, local, at, r, t.scale, extras, dir);
}

/// Rank 0's report of the exact path under MPI, through the same report() as every solver.
int report_direct(const LcpOptions& o,
                  const distributed::MpiSession& session,
                  const distributed::LocalSystem& local,
                  distributed::DirectResult& d,
                  const TaoReport& at,
                  OutputDir* dir,
                  OutputDir* system_dir) {
  if (system_dir != nullptr) write_gathered(d.gathered, local.description, *system_dir);
  const std::string ranks = ranks_text(session);
  LcpOutcome r;
  r.lambda = d.lambda;
  r.iterations = d.iterations;
  r.space = "body";
  r.space_reason = std::string("body: J and Minv ") + (o.generate.empty() ? "read" : "built") +
                   " by rows, H = M + Jt D^-1 J factored by SuperLU_dist on " + ranks;
  r.message = d.message;
  // Stopped by --time-limit: the ranks agreed past the deadline (rank 0's clock says so too).
  r.time_limit = !d.solved && o.time_limit > 0.0 && at.wall >= o.time_limit;
  OutcomeExtras extras;
  extras.residual = d.residual;
  extras.unit_free = d.unit_free;
  extras.fields["direct"] = {{"solved", d.solved},
                             {"interior_iterations", d.iterations},
                             {"crossover_steps", d.crossover},
                             {"crossover_solves", d.solves},
                             {"rows_moved", d.moved},
                             {"factorizations", d.factorizations},
                             {"low_rank_rows", d.updates},
                             {"reductions", d.reductions}};
  return report_ranks(o, session, local, at, r, d.scale, extras, dir);
}

/// `report()` (rank 0's report, returning its exit code) run on rank 0 alone; every rank returns
/// that code. An exception on rank 0 is rethrown there (main reports it, exit 2 or 1) once every
/// rank has the code, so none waits for rank 0.
int reported_by_rank_0(const distributed::MpiSession& session, const std::function<int()>& report) {
  int code = 1;
  std::exception_ptr failure;
  if (session.rank() == 0) {
    try {
      code = report();
    } catch (...) {
      failure = std::current_exception();
      code = exit_code_of(failure);
    }
  }
  code = session.broadcast(code);
  if (failure) std::rethrow_exception(failure);
  return code;
}

/// `cbps lcp PROBLEM --solver tao:TYPE` and `cbps lcp --generate chain --rows N --solver
/// tao:TYPE` on every rank of the MPI job (one without mpirun). Each rank holds only its rows
/// (generate.hpp). TAO solves the distributed problem and rank 0 reports. Bad input on any rank
/// ends every rank with exit 2, reported once, by the lowest rank that found it: the options
/// are checked and the rows read (and rank 0 opens --out) before anything is distributed, and
/// the ranks agree on the outcome by one reduction, so none is left waiting in a collective
/// call.
int lcp_distributed_command(const LcpOptions& o) {
  distributed::MpiSession session;
  TaoReport at;
  at.type = o.solver.size() > 4 ? o.solver.substr(4) : "";
  std::optional<distributed::LocalSystem> local;
  std::unique_ptr<OutputDir> dir;
  std::unique_ptr<OutputDir> system_dir;
  std::exception_ptr failure;
  try {
    const long rows = check_distributed_options(o, at.type);
    // The output folders before the work: a refused one ends every rank at once.
    if (session.rank() == 0 && !o.out.empty()) dir = std::make_unique<OutputDir>(o.out);
    if (session.rank() == 0 && !o.write_system.empty())
      system_dir = std::make_unique<OutputDir>(o.write_system);
    const auto reading = std::chrono::steady_clock::now();
    local = local_rows(o, rows, session, at.kind);
    at.read_wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - reading).count();
  } catch (...) {
    failure = std::current_exception();
  }
  const int first = session.first_failing_rank(failure != nullptr);
  if (first < session.size()) {
    const int code = session.broadcast(failure ? exit_code_of(failure) : 0, first);
    if (session.rank() == first) std::rethrow_exception(failure);  // main reports it
    return code;
  }

  // A folder's A must be its J Minv Jᵀ (read_problem checks the same on one process): every
  // rank measures its rows, and all see the same gap, so all refuse together, rank 0 saying so.
  if (local->factors_read) {
    try {
      check_factors_agree(o.problem, distributed::factors_gap_across_ranks(*local));
    } catch (const InputError&) {
      if (session.rank() == 0) throw;
      return 2;
    }
  }

  if (o.generate == "pyramid")  // each rank's rows follow the previous rank's (generate.hpp)
    local->first_row = session.sum_before(local->rows(), local->total_rows);
  at.rows = local->total_rows;
  if (is_distributed_direct(o)) {
    SolverOptions options;
    options.method = Method::Direct;
    options.tolerance = o.tolerance;
    const auto start = std::chrono::steady_clock::now();
    if (o.time_limit > 0.0) {  // the ranks stop together: each test of it is a reduction
      options.time_limit = o.time_limit;
      options.deadline = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(o.time_limit));
    }
    distributed::DirectResult d =
        distributed::solve_direct_local(session, *local, options, !o.write_system.empty());
    at.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    at.memory = session.gather(peak_memory_mb());
    return reported_by_rank_0(session, [&] {
      return report_direct(o, session, *local, d, at, dir.get(), system_dir.get());
    });
  }
  distributed::TaoOptions options;
  options.type = at.type;
  options.max_iterations = o.iterations;
  options.tolerance = o.tolerance;
  const auto start = std::chrono::steady_clock::now();
  distributed::TaoResult t =
      distributed::solve_tao_local(session, *local, options, !o.write_system.empty());
  at.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  at.memory = session.gather(peak_memory_mb());
  return reported_by_rank_0(
      session, [&] { return report_tao(o, session, *local, t, at, dir.get(), system_dir.get()); });
}
#endif

/// `--solver tao:TYPE` or `--generate SCENE`, or without PETSc in the build exit 2 saying how
/// to get it (before anything starts MPI: every process of an mpirun job says it).
int lcp_distributed(const LcpOptions& o) {
#ifdef CBPS_HAVE_PETSC
  return lcp_distributed_command(o);
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
  check_out_is_not_problem(o);
  StoredProblem p = read_lcp_problem(o);
  // A folder with cfm.txt: the step solved the boxed problem of A + eps E, and so does every
  // solver here (options.cfm, applied by solve()); the residual is that problem's.

  // The default (lcp --help says it, once): the exact path for a `cbps matrices` folder, for a
  // problem on cones (whatever its A) and for a Siconos file too large for dense Lemke; Lemke
  // for the other Siconos files.
  const bool cones = !p.cones.empty();
  const char* fallback = cones                                         ? "direct"
                         : !p.folder && p.rows() <= kMaxDenseLemkeRows ? "lemke"
                                                                       : "direct";
  const SolverSpec spec = given ? *given : parse_solver_spec(fallback, "--solver");
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
                  "iterations (default 10000)")
      ->check(positive());
  cmd->add_option(
         "--tolerance",
         o->tolerance,
         "every method but lemke and tao:TYPE: stop at this natural-map residual, N (default "
         "1e-10; the direct path also reads it as a unit-free residual, docs/cones.md; below "
         "their rounding floor the exact paths stop there once their steps no longer reduce the "
         "residual; lemke pivots to the end). tao:TYPE: TAO's absolute tolerance gatol on its "
         "own measure (a 2-norm of the gradient without the rows TAO holds at a bound; for "
         "bqpip its mean infeasibility), not the natural-map residual. Whatever the method "
         "says, the result is judged solved when its unit-free residual is <= 1e-9 (under "
         "mpirun: the natural-map residual <= 1e-9 max(1, |b|inf, max |A_ij|))")
      ->check(non_negative());
  cmd->add_option("--time-limit",
                  o->time_limit,
                  "stop the solve after this many seconds of wall time (default 0: no limit): "
                  "the sweeping methods after the sweep that passes it, a Siconos peer's "
                  "child process killed at it; the status is then \"time limit\" (exit 1) "
                  "unless the answer reached is solved")
      ->check(non_negative());
  cmd->add_option("--siconos",
                  o->siconos,
                  "what a .dat file holds: auto (from its contents: a frictional-contact dump "
                  "begins d nc storage, an LCP n 0 n n; then n^2 + n numbers an LCP, n^2 + 3n a "
                  "relay problem), lcp, relay or fc3d (Siconos' frictional-contact dump, local "
                  "or global, docs/cones.md) (default auto)");
  add_cone_option(cmd, o->cone);
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
                      std::to_string(kMaxGatheredRows) + " rows)");
  add_json_flag(cmd, o->json, "the result");
  add_quiet_flag(cmd, o->quiet, "no progress line on stderr every 2 s of a long solve");
  add_out_option(
      cmd, o->out, "result.json and lambda.mtx, only if solved (under mpirun rank 0 writes)");
  cmd->footer(solver_spec_help() + tao_spec_help());
  cmd->callback([&run, o] { run = [o] { return lcp_command(*o); }; });
}

}  // namespace cbps::cli
