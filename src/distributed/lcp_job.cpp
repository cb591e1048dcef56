// `cbps lcp` across the ranks of an MPI job (distributed/lcp_job.hpp): the options checked, each
// rank's rows generated or read, TAO or the exact path under MPI, and rank 0's report.
#include "cbps/distributed/lcp_job.hpp"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/distributed/exact.hpp"
#include "cbps/distributed/generate.hpp"
#include "cbps/distributed/tao.hpp"
#include "cbps/io/json_numbers.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/system.hpp"

namespace cbps::distributed {

namespace {

namespace fs = std::filesystem;

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
long check_distributed_options(const LcpJob& o, const std::string& type) {
  const bool generated = !o.generate.empty();
  if (generated && !o.problem.empty())
    throw InputError("--generate " + o.generate + ": give either PROBLEM (" + o.problem +
                     ") or --generate, not both");
  if (generated && o.generate != "chain" && o.generate != "pyramid")
    throw InputError("--generate " + o.generate +
                     ": unknown; the generators are chain (solved by tao:TYPE) and pyramid "
                     "(solved by direct)");
  if (o.generate == "pyramid" && !o.direct)
    throw InputError("--generate pyramid: --solver " + (o.solver.empty() ? "(none)" : o.solver) +
                     ": a generated pyramid is solved by the exact path, --solver direct (each "
                     "rank builds its rows of J and Minv; A, which TAO needs, is never formed)");
  if (o.generate == "chain" && !is_tao_solver(o.solver))
    throw InputError("--generate: --solver " + (o.solver.empty() ? "(none)" : o.solver) +
                     ": a generated chain (its rows of A alone) is solved by tao:TYPE with TYPE "
                     "one of " +
                     tao_type_list());
  if (!o.direct && !is_tao_type(type))
    throw InputError("--solver " + o.solver + ": " +
                     (type.empty() ? "no TAO type" : "unknown TAO type \"" + type + "\"") +
                     "; use tao:TYPE with TYPE one of " + tao_type_list());
  if (!o.direct && o.time_limit > 0.0)
    throw InputError("--time-limit: --solver " + o.solver +
                     " in cbps lcp runs TAO on every rank to --iterations, and a limit of time "
                     "would stop the ranks at different iterations; bound it by --iterations "
                     "(cbps converge and profile bound tao:TYPE by time, on one process)");
  if (!generated) {
    check_out_is_not_input(o.out, o.problem, "--out");
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
std::string distributed_solver_name(const LcpJob& o) {
  return o.direct ? "--solver direct under mpirun (the exact path under MPI)"
                  : "--solver " + o.solver + " (PETSc/TAO)";
}

/// The distributed paths solve the boxed problem of 6.2 only: a folder whose contacts live in
/// friction cones (cones.json) is refused, naming the serial methods that solve it.
void refuse_cones(const LcpJob& o, const std::string& solver) {
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
LocalSystem local_rows(const LcpJob& o, long rows, const MpiSession& session, std::string& kind) {
  std::error_code ec;
  if (o.generate == "chain") {
    kind = "generated";
    return generate_chain({{"n", std::to_string(rows)}}, session.rank(), session.size());
  }
  if (o.generate == "pyramid") {
    kind = "generated, J and Minv built per rank";  // numbered by lcp_distributed_command
    return generate_pyramid(
        {{"base", std::to_string(pyramid_base_for(rows))}}, session.rank(), session.size());
  }
  if (!fs::exists(o.problem, ec)) throw InputError(o.problem + ": no such file or folder");
  if (fs::is_directory(o.problem, ec)) refuse_cones(o, distributed_solver_name(o));
  if (o.direct) {
    if (!fs::is_directory(o.problem, ec))
      throw InputError("--solver direct under mpirun: " + o.problem +
                       ": not a cbps matrices folder; the exact path under MPI works in body "
                       "space and reads J and Minv by rows (a Siconos or FCLIB file has "
                       "neither); without mpirun, `cbps lcp " +
                       o.problem + " --solver direct` solves it on one process");
    kind = "cbps matrices folder, J and Minv read by rows";
    return read_folder_factors(o.problem, session.rank(), session.size());
  }
  if (fs::is_directory(o.problem, ec)) {
    kind = "cbps matrices folder, read by rows";
    return read_folder_rows(o.problem, session.rank(), session.size());
  }
  StoredProblem p = o.read_whole();
  if (!p.cones.empty())
    throw InputError("--solver " + o.solver + ": " + o.problem + ": its " +
                     std::to_string(p.cones.contacts()) +
                     " contacts live in friction cones; TAO solves the boxed problem of 6.2. Use "
                     "--solver nsgs (docs/cones.md)");
  kind = "Siconos file";
  return rows_of(p.problem(), p.cfm, o.problem, session.rank(), session.size());
}

/// --write-system: the gathered A, b, cmin, cmax of a generated problem (rank 0).
void write_gathered(GatheredSystem& g, const std::string& description, OutputDir& dir) {
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

using Reporter = std::function<int(const LcpJobReport&)>;

/// What the distributed path knows when rank 0 reports.
struct JobFacts {
  std::string type;
  std::string kind;
  long rows = 0;
  double read_wall = 0.0;  ///< rank 0's time to build or read its rows, s
  double wall = 0.0;       ///< the solve's, s
  std::vector<double> memory;
};

/// "1 rank", "2 ranks".
std::string ranks_text(const MpiSession& session) {
  return std::to_string(session.size()) + (session.size() == 1 ? " rank" : " ranks");
}

/// What every distributed report adds (ranks, each rank's memory, the time to read or build the
/// rows) and its facts (rows, cfm, the scale measured on the distributed problem), then the
/// command's report.
int report_ranks(const LcpJob& o,
                 const MpiSession& session,
                 const LocalSystem& local,
                 const JobFacts& at,
                 double scale,
                 LcpJobReport& extras,
                 OutputDir* dir,
                 const Reporter& report) {
  extras.fields["ranks"] = session.size();
  if (!o.generate.empty())
    extras.fields["generated"] = {{"scene", o.generate},
                                  {"description", local.description},
                                  {"step", 0},
                                  {"wall_time_s", at.read_wall}};
  else
    extras.fields["read_wall_time_s"] = at.read_wall;
  extras.fields["rank_memory_mb"] = at.memory;
  extras.facts.rows = at.rows;
  extras.facts.cfm = local.cfm;
  extras.facts.kind = at.kind + " on " + ranks_text(session);
  extras.facts.scale = scale;
  extras.facts.lambda_in_json = at.rows <= kMaxGatheredRows;
  extras.problem = local.description;
  extras.wall = at.wall;
  extras.dir = dir;
  return report(extras);
}

/// Rank 0's report of TAO's answer, through the command's report as every solver's (the
/// residuals and scale measured on the distributed vectors); the exit code.
int report_tao(const LcpJob& o,
               const MpiSession& session,
               const LocalSystem& local,
               TaoResult& t,
               const JobFacts& at,
               OutputDir* dir,
               OutputDir* system_dir,
               const Reporter& report) {
  if (t.asymmetric)
    throw InputError("--solver " + o.solver +
                     ": needs a symmetric A (TAO minimises 1/2 lambda^T A lambda - b^T "
                     "lambda, whose gradient is A lambda - b only then); max |A - A^T| = " +
                     number_text(t.asymmetry) + "; `cbps lcp --solver lemke` solves any square A");
  if (system_dir != nullptr) write_gathered(t.gathered, local.description, *system_dir);
  const std::string ranks = ranks_text(session);
  LcpJobReport extras;
  LcpOutcome& r = extras.outcome;
  r.lambda = t.lambda;
  r.iterations = t.iterations;
  r.space_reason = "none: TAO " + at.type + " factors no Newton system";
  r.message = "TAO " + at.type + ": " + t.reason + " (" + t.stop + "), TAO's measure " +
              number_text(t.tao_residual) + " (gatol " + number_text(o.tolerance) + "), " + ranks;
  extras.residual = t.residual;
  extras.unit_free = t.unit_free;
  extras.fields["tao"] = {{"type", at.type},
                          {"reason", t.reason},
                          {"converged", t.converged},
                          {"stop", t.stop},
                          {"measure", number_json(t.tao_residual)},
                          {"gatol", o.tolerance}};
  return report_ranks(o, session, local, at, t.scale, extras, dir, report);
}

/// Rank 0's report of the exact path under MPI, through the command's report as every solver's.
int report_direct(const LcpJob& o,
                  const MpiSession& session,
                  const LocalSystem& local,
                  DirectResult& d,
                  const JobFacts& at,
                  OutputDir* dir,
                  OutputDir* system_dir,
                  const Reporter& report) {
  if (system_dir != nullptr) write_gathered(d.gathered, local.description, *system_dir);
  const std::string ranks = ranks_text(session);
  LcpJobReport extras;
  LcpOutcome& r = extras.outcome;
  r.lambda = d.lambda;
  r.iterations = d.iterations;
  r.space = "body";
  r.space_reason = std::string("body: J and Minv ") + (o.generate.empty() ? "read" : "built") +
                   " by rows, H = M + Jt D^-1 J factored by SuperLU_dist on " + ranks;
  r.message = d.message;
  // Stopped by --time-limit: the ranks agreed past the deadline (rank 0's clock says so too).
  r.time_limit = !d.solved && o.time_limit > 0.0 && at.wall >= o.time_limit;
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
  return report_ranks(o, session, local, at, d.scale, extras, dir, report);
}

/// Every rank's exit code, told by rank `teller`, once it has said what it has to say: its
/// failure, as main says one ("cbps: MESSAGE"), and whatever it printed, flushed while every
/// rank's MPI is still up. The others wait for it (one broadcast from it), so no rank's exit
/// lets mpiexec end the job before the teller's words are out (a rank that returned at once
/// while the teller still unwound to main was seen to cut its message off under load).
int told_by(const MpiSession& session, int teller, const std::exception_ptr& failure, int code) {
  if (session.rank() == teller && failure) {
    try {
      std::rethrow_exception(failure);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "cbps: %s\n", e.what());
    }
  }
  std::fflush(stdout);
  std::fflush(stderr);
  return session.broadcast(code, teller);
}

/// `report()` (rank 0's report, returning its exit code) run on rank 0 alone; every rank returns
/// that code. A failure on rank 0 is said there (told_by: exit 2 or 1).
int reported_by_rank_0(const MpiSession& session, const std::function<int()>& report) {
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
  return told_by(session, 0, failure, code);
}

}  // namespace

int run_lcp_job(const LcpJob& o, const Reporter& report) {
  MpiSession session;
  JobFacts at;
  at.type = o.solver.size() > 4 ? o.solver.substr(4) : "";
  std::optional<LocalSystem> local;
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
  if (first < session.size())
    return told_by(session, first, failure, failure ? exit_code_of(failure) : 0);

  // A folder's A must be its J Minv Jᵀ (read_problem checks the same on one process): every
  // rank measures its rows, and all see the same gap, so all refuse together, rank 0 saying so.
  if (local->factors_read) {
    try {
      check_factors_agree(o.problem, factors_gap_across_ranks(*local));
    } catch (const InputError&) {
      return told_by(session, 0, std::current_exception(), 2);
    }
  }

  if (o.generate == "pyramid")  // each rank's rows follow the previous rank's (generate.hpp)
    local->first_row = session.sum_before(local->rows(), local->total_rows);
  at.rows = local->total_rows;
  if (o.direct) {
    SolverOptions options;
    options.method = kExactMethod;
    options.tolerance = o.tolerance;
    const auto start = std::chrono::steady_clock::now();
    if (o.time_limit > 0.0) {  // the ranks stop together: each test of it is a reduction
      options.time_limit = o.time_limit;
      options.deadline = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(o.time_limit));
    }
    DirectResult d = solve_direct_local(session, *local, options, !o.write_system.empty());
    at.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    at.memory = session.gather(peak_memory_mb());
    return reported_by_rank_0(session, [&] {
      return report_direct(o, session, *local, d, at, dir.get(), system_dir.get(), report);
    });
  }
  TaoOptions options;
  options.type = at.type;
  options.max_iterations = o.iterations;
  options.tolerance = o.tolerance;
  const auto start = std::chrono::steady_clock::now();
  TaoResult t = solve_tao_local(session, *local, options, !o.write_system.empty());
  at.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  at.memory = session.gather(peak_memory_mb());
  return reported_by_rank_0(session, [&] {
    return report_tao(o, session, *local, t, at, dir.get(), system_dir.get(), report);
  });
}

}  // namespace cbps::distributed
