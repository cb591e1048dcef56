// The exact solvers of the boxed problem (6.2) on contact and chain systems (issue: exact path):
//
//   direct      solve() with Method::Direct, the exact path (interior point in body space, then
//               a crossover to the exact active set), from λ = 0, to the relative natural-map
//               residual 1e-10 (options.tolerance = 1e-10 · scale_of): median wall time of
//               --repeats runs, the residual it reaches (N, and relative to scale_of), the
//               rounding floor at its answer (residual_floor: above the tolerance, a path stops
//               there once its steps no longer reduce the residual, so on large systems "direct
//               solve" may come above 1e-10), why it stopped,
//               interior iterations, crossover (proximal) steps, factorizations, the factor's
//               nonzeros and the space it factored in (body or row);
//   active-set  solve() with Method::ActiveSet, the previous exact path, once, to the same
//               tolerance, in a child process killed after --active-set-budget-s; not run where
//               it is known beforehand not to fit that budget (pyramids of base ≥ 40: more than
//               300 s), reported as "skipped: > budget";
//   v2          where both exact paths ran: max |v2_direct − v2_active| of compute_v2 (12.3.1),
//               the quantity both must agree on (λ itself is not unique where A is singular);
//   pgs         PGS (7.1.1) from λ = 0: sweeps and seconds to reach the relative residual 1e-10
//               within --budget-s (the residual is checked every ~1 % of the sweeps done,
//               outside the timing), or the residual reached when the budget runs out.
//
// The systems (each built like bench_direct's: the scene stepped with a cheap PGS, 50 sweeps a
// step, then Simulation::build_system()):
//   the pyramid of base 10, 20, 40, 60 after 30 steps (one island of 12 b² rows);
//   the stack of 100 columns of 10 boxes after 60 steps (100 islands);
//   the 1000-box stack exactly as bench_direct builds it (3 steps of the direct path);
//   the chain of 10⁴ and 10⁶ links as bench_direct builds it (5 steps of 10 sweeps).
//
// Prints two Markdown tables on stdout, progress on stderr, and writes JSON with every number to
// --out (rewritten after every system, so a long run that fails late keeps what it measured).
// Usage: bench_exact [--out FILE] [--repeats K] [--budget-s S] [--active-set-budget-s S]
//                    [--max-base B] [--quick]
// --quick: the pyramids of base 10 and 20, both stacks and the 10⁴ chain only.
// (`bench_exact --active-set-child IN OUT` is the child process of the active-set runs.)
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cbps/cbps.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kRelativeTolerance = 1e-10;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&t));
  return text;
}

/// The 1-minute load average (/proc/loadavg), -1 where there is none: the machine may be shared.
double load_average() {
  std::ifstream f("/proc/loadavg");
  double load = -1.0;
  f >> load;
  return f ? load : -1.0;
}

// ---- The systems --------------------------------------------------------------------------

enum class Kind { Pyramid, Stack, StackDirect, Chain };

struct Case {
  Kind kind;
  long size;  ///< pyramid base, links of the chain; unused for the stacks
  std::string name;
};

/// Steps a scene with a cheap PGS (50 sweeps a step), reporting progress on stderr, and returns
/// the system of the state it reaches.
cbps::System stepped_system(cbps::Scene scene, int steps, const std::string& name) {
  scene.solver.method = cbps::Method::Pgs;
  scene.solver.max_iterations = 50;
  cbps::Simulation sim(scene);
  const auto start = Clock::now();
  for (int s = 1; s <= steps; ++s) {
    sim.step();
    if (s % 5 == 0 || s == steps) {
      std::fprintf(stderr,
                   "%s: building, step %d of %d (%.1f s)\n",
                   name.c_str(),
                   s,
                   steps,
                   seconds_since(start));
    }
  }
  return sim.build_system();
}

/// The chain of n links, stepped 5 times with a cheap solver so every row has its general
/// pattern: bench_direct's chain_system.
cbps::System chain_system(long n) {
  cbps::Scene scene = cbps::make_builtin_scene("chain", {{"n", std::to_string(n)}});
  scene.solver.max_iterations = 10;
  scene.solver.tolerance = 0.0;
  cbps::Simulation sim(scene);
  for (int s = 0; s < 5; ++s) sim.step();
  return sim.build_system();
}

/// The stack of 1000 boxes (100 columns of 10, 12,000 contact and friction rows) stepped 3 times
/// with the direct solver: bench_direct's stack_system.
cbps::System stack_direct_system() {
  cbps::Scene scene = cbps::make_builtin_scene(
      "stack", {{"n", "10"}, {"columns", "100"}, {"margin", "0.001"}, {"push", "improved"}});
  scene.solver.method = cbps::Method::Direct;
  cbps::Simulation sim(scene);
  for (int s = 0; s < 3; ++s) sim.step();
  return sim.build_system();
}

cbps::System build(const Case& c) {
  switch (c.kind) {
    case Kind::Pyramid:
      return stepped_system(
          cbps::make_builtin_scene("pyramid", {{"base", std::to_string(c.size)}}), 30, c.name);
    case Kind::Stack:
      return stepped_system(
          cbps::make_builtin_scene("stack", {{"n", "10"}, {"columns", "100"}}), 60, c.name);
    case Kind::StackDirect:
      return stack_direct_system();
    case Kind::Chain:
      return chain_system(c.size);
  }
  return {};
}

/// How the system was made, for the JSON file.
nlohmann::json recipe(const Case& c) {
  switch (c.kind) {
    case Kind::Pyramid:
      return {{"scene", "pyramid"},
              {"parameters", {{"base", std::to_string(c.size)}}},
              {"steps", 30},
              {"step_solver", "pgs, 50 sweeps"}};
    case Kind::Stack:
      return {{"scene", "stack"},
              {"parameters", {{"n", "10"}, {"columns", "100"}}},
              {"steps", 60},
              {"step_solver", "pgs, 50 sweeps"}};
    case Kind::StackDirect:
      return {{"scene", "stack"},
              {"parameters",
               {{"n", "10"}, {"columns", "100"}, {"margin", "0.001"}, {"push", "improved"}}},
              {"steps", 3},
              {"step_solver", "direct (bench_direct's stack_system)"}};
    case Kind::Chain:
      return {{"scene", "chain"},
              {"parameters", {{"n", std::to_string(c.size)}}},
              {"steps", 5},
              {"step_solver", "pgs, 10 sweeps, tolerance 0 (bench_direct's chain_system)"}};
  }
  return {};
}

// ---- The solves ---------------------------------------------------------------------------

cbps::SolverOptions exact_options(cbps::Method method, double scale) {
  cbps::SolverOptions o;
  o.method = method;
  o.tolerance = kRelativeTolerance * scale;
  return o;
}

/// A summary with the residual recomputed here at the answer λ, and the rounding floor there
/// (residual_floor: above the tolerance, an exact path stops there once its steps no longer reduce
/// the residual, so "direct solve" may come with a relative residual above 1e-10).
nlohmann::json summary_json(const cbps::SolverSummary& s,
                            const cbps::BoxedProblem& problem,
                            double scale,
                            const cbps::VecX& lambda) {
  const double rounding = cbps::residual_floor(problem, lambda);
  return {{"residual", s.residual},
          {"relative_residual", s.residual / scale},
          {"residual_recomputed", cbps::natural_map_residual(problem, lambda)},
          {"residual_floor", rounding},
          {"relative_residual_floor", rounding / scale},
          {"tolerance_met", s.residual <= kRelativeTolerance * scale},
          {"termination", cbps::to_string(s.termination)},
          {"iterations", s.iterations},
          {"crossover", s.crossover},
          {"factorizations", s.factorizations},
          {"pivots", s.pivots},
          {"restarts", s.restarts},
          {"islands", s.islands},
          {"singular", s.singular},
          {"factor_nnz", s.factor_nnz},
          {"updates", s.updates},
          {"space", s.space},
          {"wall_time_s", s.wall_time_s},
          {"message", s.message}};
}

// ---- The active-set path in a child process ------------------------------------------------
//
// The active-set path cannot be stopped from outside a solve, so it runs in a child process
// (this program again, `--active-set-child IN OUT`), which is killed when the budget runs out.
// It is a fresh process rather than a fork: after CHOLMOD has run, this process has OpenMP's
// threads, which a forked child would lack. The child gets A, b, cmin and cmax (the active-set
// path reads nothing else of the problem) and the tolerance in IN, and writes its summary and λ
// to OUT, both raw binary files in /tmp.

/// The fixed-size part of OUT; then the message, then λ.
struct ChildRecord {
  int iterations, factorizations, pivots, restarts, islands, crossover, termination, singular;
  long factor_nnz, message_size, rows;
  double residual, wall_time_s, seconds;
};

template <class T>
void put(std::ostream& out, const T* data, size_t count) {
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(sizeof(T) * count));
}

template <class T>
bool get(std::istream& in, T* data, size_t count) {
  in.read(reinterpret_cast<char*>(data), static_cast<std::streamsize>(sizeof(T) * count));
  return static_cast<bool>(in);
}

/// IN: rows, nnz, tolerance, then A's compressed columns (outer, inner, values), b, cmin, cmax.
bool write_problem(const std::string& path, const cbps::BoxedProblem& p, double tolerance) {
  cbps::SpMat A = p.A;
  A.makeCompressed();
  const long rows = static_cast<long>(p.rows());
  const long nnz = static_cast<long>(A.nonZeros());
  std::ofstream out(path, std::ios::binary);
  put(out, &rows, 1);
  put(out, &nnz, 1);
  put(out, &tolerance, 1);
  put(out, A.outerIndexPtr(), static_cast<size_t>(A.outerSize() + 1));
  put(out, A.innerIndexPtr(), static_cast<size_t>(nnz));
  put(out, A.valuePtr(), static_cast<size_t>(nnz));
  for (const cbps::VecX* v : {&p.b, &p.cmin, &p.cmax})
    put(out, v->data(), static_cast<size_t>(rows));
  return static_cast<bool>(out);
}

/// The child: reads IN, solves with the active-set path from λ = 0, writes OUT. Exit status 0
/// when OUT is written.
int active_set_child(const std::string& in_path, const std::string& out_path) {
  std::ifstream in(in_path, std::ios::binary);
  long rows = 0;
  long nnz = 0;
  double tolerance = 0.0;
  if (!get(in, &rows, 1) || !get(in, &nnz, 1) || !get(in, &tolerance, 1) || rows < 0 || nnz < 0) {
    return 3;
  }
  using Index = cbps::SpMat::StorageIndex;
  std::vector<Index> outer(static_cast<size_t>(rows + 1));
  std::vector<Index> inner(static_cast<size_t>(nnz));
  std::vector<double> values(static_cast<size_t>(nnz));
  cbps::VecX b(rows), cmin(rows), cmax(rows);
  if (!get(in, outer.data(), outer.size()) || !get(in, inner.data(), inner.size()) ||
      !get(in, values.data(), values.size()) || !get(in, b.data(), static_cast<size_t>(rows)) ||
      !get(in, cmin.data(), static_cast<size_t>(rows)) ||
      !get(in, cmax.data(), static_cast<size_t>(rows))) {
    return 3;
  }
  const cbps::SpMat A =
      Eigen::Map<const cbps::SpMat>(rows, rows, nnz, outer.data(), inner.data(), values.data());
  cbps::SolverOptions o;
  o.method = cbps::Method::ActiveSet;
  o.tolerance = tolerance;
  cbps::VecX lambda = cbps::VecX::Zero(rows);
  const auto start = Clock::now();
  const cbps::SolverSummary s = cbps::solve(cbps::BoxedProblem{A, b, cmin, cmax}, lambda, o);
  const double seconds = seconds_since(start);
  const ChildRecord r{s.iterations,
                      s.factorizations,
                      s.pivots,
                      s.restarts,
                      s.islands,
                      s.crossover,
                      static_cast<int>(s.termination),
                      s.singular ? 1 : 0,
                      s.factor_nnz,
                      static_cast<long>(s.message.size()),
                      rows,
                      s.residual,
                      s.wall_time_s,
                      seconds};
  std::ofstream out(out_path, std::ios::binary);
  put(out, &r, 1);
  put(out, s.message.data(), s.message.size());
  put(out, lambda.data(), static_cast<size_t>(rows));
  out.close();
  return out ? 0 : 4;
}

/// The active-set run's outcome.
struct ActiveRun {
  enum class Status { Done, OverBudget, Failed } status = Status::Failed;
  double seconds = 0.0;  ///< the solve's (child's clock), or the budget spent when killed
  cbps::SolverSummary summary;
  cbps::VecX lambda;
  std::string error;
};

/// A temporary file name in /tmp (the file exists, empty, until removed).
std::string temporary_file() {
  char path[] = "/tmp/bench_exact_XXXXXX";
  const int fd = ::mkstemp(path);
  if (fd < 0) return {};
  ::close(fd);
  return path;
}

/// The active-set path from λ = 0 to `tolerance`, in a child process killed after budget_s.
ActiveRun run_active_set(const cbps::BoxedProblem& problem, double tolerance, double budget_s) {
  ActiveRun run;
  const std::string in_path = temporary_file();
  const std::string out_path = temporary_file();
  const auto finish = [&](const std::string& error) {
    run.error = error;
    if (!in_path.empty()) std::remove(in_path.c_str());
    if (!out_path.empty()) std::remove(out_path.c_str());
    return run;
  };
  if (in_path.empty() || out_path.empty()) return finish("cannot create a temporary file");
  if (!write_problem(in_path, problem, tolerance)) return finish("cannot write " + in_path);
  // Everything the child's exec needs is made before the fork.
  std::string self = "/proc/self/exe";
  std::string flag = "--active-set-child";
  std::vector<char*> args{self.data(),
                          flag.data(),
                          const_cast<char*>(in_path.c_str()),
                          const_cast<char*>(out_path.c_str()),
                          nullptr};
  std::fflush(stdout);
  std::fflush(stderr);
  const auto start = Clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) return finish("fork failed");
  if (pid == 0) {
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (seconds_since(start) > budget_s) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      run.seconds = seconds_since(start);
      run.status = ActiveRun::Status::OverBudget;
      return finish("");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return finish(WIFEXITED(status) ? "child exited with " + std::to_string(WEXITSTATUS(status))
                                    : "child killed by signal " + std::to_string(WTERMSIG(status)));
  }
  std::ifstream in(out_path, std::ios::binary);
  ChildRecord r{};
  bool ok = get(in, &r, 1) && r.rows == problem.rows() && r.message_size >= 0;
  std::string message(ok ? static_cast<size_t>(r.message_size) : 0, '\0');
  cbps::VecX lambda(ok ? r.rows : 0);
  ok = ok && get(in, message.data(), message.size()) &&
       get(in, lambda.data(), static_cast<size_t>(lambda.size()));
  if (!ok) return finish("cannot read the child's result");
  run.summary.iterations = r.iterations;
  run.summary.factorizations = r.factorizations;
  run.summary.pivots = r.pivots;
  run.summary.restarts = r.restarts;
  run.summary.islands = r.islands;
  run.summary.crossover = r.crossover;
  run.summary.termination = static_cast<cbps::Termination>(r.termination);
  run.summary.singular = r.singular != 0;
  run.summary.factor_nnz = r.factor_nnz;
  run.summary.residual = r.residual;
  run.summary.wall_time_s = r.wall_time_s;
  run.summary.message = std::move(message);
  run.seconds = r.seconds;
  run.lambda = std::move(lambda);
  run.status = ActiveRun::Status::Done;
  return finish("");
}

struct PgsReach {
  bool reached = false;
  long sweeps = 0;
  double seconds = 0.0;
  double residual = 0.0;  ///< at the end (N)
};

/// PGS from zero, checking the residual every ~1 % of the sweeps done (outside the timing),
/// until it is ≤ tolerance or the budget is spent: bench_direct's pgs_reach for one tolerance.
PgsReach pgs_reach(const cbps::System& sys, double tolerance, double budget_s) {
  PgsReach out;
  cbps::VecX lambda = cbps::VecX::Zero(sys.rows());
  const cbps::BoxedProblem problem = sys.problem();
  long check = 1;
  out.residual = cbps::natural_map_residual(problem, lambda);
  while (out.seconds < budget_s && out.residual > tolerance && std::isfinite(out.residual)) {
    const auto start = Clock::now();
    for (long k = 0; k < check; ++k) cbps::pgs_sweep(problem, lambda);
    out.seconds += seconds_since(start);
    out.sweeps += check;
    out.residual = cbps::natural_map_residual(problem, lambda);
    check = std::max<long>(1, out.sweeps / 100);
  }
  out.reached = out.residual <= tolerance;
  return out;
}

double max_abs_difference(const cbps::VecX& a, const cbps::VecX& b) {
  return a.size() == 0 ? 0.0 : (a - b).cwiseAbs().maxCoeff();
}

double max_abs(const cbps::VecX& a) { return a.size() == 0 ? 0.0 : a.cwiseAbs().maxCoeff(); }

/// "1.23 s", "45.6 ms" or "789 µs".
std::string format_seconds(double s) {
  char text[32];
  if (s >= 1.0) {
    std::snprintf(text, sizeof text, "%.3g s", s);
  } else if (s >= 1e-3) {
    std::snprintf(text, sizeof text, "%.3g ms", s * 1e3);
  } else {
    std::snprintf(text, sizeof text, "%.3g µs", s * 1e6);
  }
  return text;
}

std::string format(const char* spec, double value) {
  char text[64];
  std::snprintf(text, sizeof text, spec, value);
  return text;
}

/// Where the active-set path is known beforehand to take longer than this, s (0: nothing known):
/// on one pyramid island it grows steeply with the base, and needs more than 300 s at base 40.
double active_set_known_min_s(const Case& c) {
  return c.kind == Kind::Pyramid && c.size >= 40 ? 300.0 : 0.0;
}

struct Options {
  std::string out_path;
  int repeats = 3;
  double budget_s = 10.0;
  double active_budget_s = 60.0;
  long max_base = 60;
  bool quick = false;
};

/// The command line (`--name value` or `--name=value`); false on a bad one.
bool parse_options(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    std::optional<std::string> value;
    if (const size_t eq = a.find('='); a.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = a.substr(eq + 1);  // --name=value as well as --name value
      a.resize(eq);
    }
    const auto take = [&]() -> std::optional<std::string> {
      if (value) return value;
      if (i + 1 < argc) return std::string(argv[++i]);
      return std::nullopt;
    };
    std::optional<std::string> v;
    if (a == "--quick" && !value) {
      o.quick = true;
    } else if (a == "--out" && (v = take())) {
      o.out_path = *v;
    } else if (a == "--repeats" && (v = take())) {
      o.repeats = std::max(1, std::atoi(v->c_str()));
    } else if (a == "--budget-s" && (v = take())) {
      o.budget_s = std::atof(v->c_str());
    } else if (a == "--active-set-budget-s" && (v = take())) {
      o.active_budget_s = std::atof(v->c_str());
    } else if (a == "--max-base" && (v = take())) {
      o.max_base = std::atol(v->c_str());
    } else {
      return false;
    }
  }
  return true;
}

/// The systems measured, in order (--quick: the pyramids of base 10 and 20, both stacks and
/// the 10⁴ chain).
std::vector<Case> cases_of(const Options& o) {
  std::vector<Case> cases;
  for (const long base : {10L, 20L, 40L, 60L}) {
    if (base <= o.max_base && (!o.quick || base <= 20)) {
      cases.push_back({Kind::Pyramid, base, "pyramid " + std::to_string(base)});
    }
  }
  cases.push_back({Kind::Stack, 0, "stack 100×10, 60 steps"});
  cases.push_back({Kind::StackDirect, 0, "stack 100×10, bench_direct"});
  cases.push_back({Kind::Chain, 10000, "chain 10⁴"});
  if (!o.quick) cases.push_back({Kind::Chain, 1000000, "chain 10⁶"});
  return cases;
}

/// One system being measured: the problem, its JSON row, and its lines of the two tables.
struct Measured {
  Measured(const Case& of, const cbps::System& system)
      : c(of), sys(system), problem(system.problem()), scale(cbps::scale_of(problem)) {}
  const Case& c;
  const cbps::System& sys;
  cbps::BoxedProblem problem;
  double scale;
  nlohmann::json row;
  cbps::SolverSummary direct;
  cbps::VecX direct_lambda;
  cbps::VecX v2_direct;
  double direct_median = 0.0;
  double direct_floor = 0.0;
  std::string active_cell, v2_cell = "—", pgs_cell;
};

/// The direct path: the median of the repeats, the last run's answer.
void measure_direct(Measured& m, const Options& o) {
  std::vector<double> direct_s;
  for (int r = 0; r < o.repeats; ++r) {
    std::fprintf(stderr, "%s: direct, run %d of %d\n", m.c.name.c_str(), r + 1, o.repeats);
    cbps::VecX lambda = cbps::VecX::Zero(m.sys.rows());
    const auto start = Clock::now();
    m.direct = cbps::solve(m.problem, lambda, exact_options(cbps::Method::Direct, m.scale));
    direct_s.push_back(seconds_since(start));
    m.direct_lambda = std::move(lambda);
  }
  m.direct_median = median(direct_s);
  m.direct_floor = cbps::residual_floor(m.problem, m.direct_lambda);
  std::fprintf(stderr,
               "%s: direct %.3g s, %s, relative residual %.2g\n",
               m.c.name.c_str(),
               m.direct_median,
               cbps::to_string(m.direct.termination).c_str(),
               m.direct.residual / m.scale);
  m.row["direct"] = summary_json(m.direct, m.problem, m.scale, m.direct_lambda);
  m.row["direct"]["seconds"] = m.direct_median;
  m.row["direct"]["seconds_runs"] = direct_s;
  m.v2_direct = cbps::compute_v2(m.sys, m.direct_lambda);
  m.row["direct"]["max_abs_v2"] = max_abs(m.v2_direct);
}

/// A finished active-set run against the direct path's answer.
void record_active_done(Measured& m, const ActiveRun& run, nlohmann::json& active) {
  active["status"] = "done";
  active.update(summary_json(run.summary, m.problem, m.scale, run.lambda));
  const cbps::VecX v2_active = cbps::compute_v2(m.sys, run.lambda);
  const double dv2 = max_abs_difference(m.v2_direct, v2_active);
  m.row["v2_agreement"] = {
      {"max_abs_difference", dv2},
      {"max_abs_v2_direct", max_abs(m.v2_direct)},
      {"max_abs_lambda_difference", max_abs_difference(m.direct_lambda, run.lambda)}};
  m.v2_cell = format("%.2g", dv2);
  m.active_cell =
      format_seconds(run.seconds) + " | " + format("%.2g", run.summary.residual / m.scale) + " | " +
      cbps::to_string(run.summary.termination) + " | " + std::to_string(run.summary.iterations) +
      " | " + std::to_string(run.summary.factorizations);
}

/// The active-set path, once, where it can fit the budget. `pyramid_over_budget`: a smaller
/// pyramid already did not fit it (set here when this one does not).
void measure_active_set(Measured& m, const Options& o, bool& pyramid_over_budget) {
  nlohmann::json active{{"budget_s", o.active_budget_s}};
  const double known_min_s = active_set_known_min_s(m.c);
  if (known_min_s > o.active_budget_s || (m.c.kind == Kind::Pyramid && pyramid_over_budget)) {
    active["status"] = "skipped";
    active["reason"] = known_min_s > o.active_budget_s
                           ? "known to need more than " + format("%.0f", known_min_s) + " s"
                           : std::string("a smaller pyramid did not finish within the budget");
    m.active_cell = "skipped: > budget | — | — | — | —";
    std::fprintf(stderr, "%s: active set skipped (> budget)\n", m.c.name.c_str());
    m.row["active_set"] = active;
    return;
  }
  std::fprintf(stderr, "%s: active set (budget %.0f s)\n", m.c.name.c_str(), o.active_budget_s);
  const ActiveRun run = run_active_set(m.problem, kRelativeTolerance * m.scale, o.active_budget_s);
  active["seconds"] = run.seconds;
  switch (run.status) {
    case ActiveRun::Status::Failed:
      active["status"] = "failed";
      active["error"] = run.error;
      m.active_cell = "failed: " + run.error + " | — | — | — | —";
      break;
    case ActiveRun::Status::OverBudget:
      active["status"] = "over budget";
      if (m.c.kind == Kind::Pyramid) pyramid_over_budget = true;
      m.active_cell = "not in " + format("%.0f", o.active_budget_s) + " s | — | — | — | —";
      break;
    case ActiveRun::Status::Done:
      record_active_done(m, run, active);
      break;
  }
  std::fprintf(stderr,
               "%s: active set %s after %.3g s\n",
               m.c.name.c_str(),
               active["status"].get<std::string>().c_str(),
               run.seconds);
  m.row["active_set"] = active;
}

/// PGS to the same relative tolerance.
void measure_pgs(Measured& m, const Options& o) {
  std::fprintf(stderr,
               "%s: PGS to relative %.0e (budget %.0f s)\n",
               m.c.name.c_str(),
               kRelativeTolerance,
               o.budget_s);
  const PgsReach pgs = pgs_reach(m.sys, kRelativeTolerance * m.scale, o.budget_s);
  m.row["pgs"] = {{"reached", pgs.reached},
                  {"sweeps", pgs.sweeps},
                  {"seconds", pgs.seconds},
                  {"residual", pgs.residual},
                  {"relative_residual", pgs.residual / m.scale},
                  {"budget_s", o.budget_s}};
  m.pgs_cell = pgs.reached
                   ? format_seconds(pgs.seconds) + " (" + std::to_string(pgs.sweeps) + " sweeps)"
                   : "not in " + format_seconds(pgs.seconds) + " (" + std::to_string(pgs.sweeps) +
                         " sweeps; " + format("%.2g", pgs.residual / m.scale) + ")";
}

/// The two tables' lines of a measured system.
std::string direct_line(const Measured& m) {
  const cbps::SolverSummary& d = m.direct;
  return "| " + m.c.name + " | " + std::to_string(m.sys.rows()) + " | " +
         std::to_string(m.sys.A.nonZeros()) + " | " + std::to_string(m.sys.J.nonZeros()) + " | " +
         format_seconds(m.direct_median) + " | " + format("%.2g", d.residual) + " | " +
         format("%.2g", d.residual / m.scale) + " | " + format("%.2g", m.direct_floor / m.scale) +
         " | " + cbps::to_string(d.termination) + " | " + std::to_string(d.iterations) + " | " +
         std::to_string(d.crossover) + " | " + std::to_string(d.factorizations) + " | " +
         std::to_string(d.factor_nnz) + " | " + (d.space.empty() ? "—" : d.space) + " |";
}

std::string compare_line(const Measured& m) {
  return "| " + m.c.name + " | " + format_seconds(m.direct_median) + " | " + m.active_cell + " | " +
         m.v2_cell + " | " + m.pgs_cell + " |";
}

/// Builds the system of `c` and measures the three paths on it; its JSON row and table lines.
void bench_case(const Case& c,
                const Options& o,
                bool& pyramid_over_budget,
                nlohmann::json& systems,
                std::vector<std::string>& direct_table,
                std::vector<std::string>& compare_table) {
  std::fprintf(stderr, "%s: building\n", c.name.c_str());
  const auto build_start = Clock::now();
  const cbps::System sys = build(c);
  const double build_s = seconds_since(build_start);
  Measured m(c, sys);
  std::fprintf(stderr,
               "%s: %d rows, nnz(A) %ld, built in %.1f s\n",
               c.name.c_str(),
               sys.rows(),
               static_cast<long>(sys.A.nonZeros()),
               build_s);
  m.row = recipe(c);
  m.row["name"] = c.name;
  m.row["build_s"] = build_s;
  m.row["rows"] = sys.rows();
  m.row["bodies_moving"] = sys.J.cols() / 6;
  m.row["nnz_A"] = sys.A.nonZeros();
  m.row["nnz_J"] = sys.J.nonZeros();
  m.row["scale"] = m.scale;
  m.row["tolerance"] = kRelativeTolerance * m.scale;
  measure_direct(m, o);
  measure_active_set(m, o, pyramid_over_budget);
  measure_pgs(m, o);
  direct_table.push_back(direct_line(m));
  compare_table.push_back(compare_line(m));
  systems.push_back(m.row);
}

void print_tables(const std::vector<std::string>& direct_table,
                  const std::vector<std::string>& compare_table) {
  std::printf(
      "| system | rows | nnz(A) | nnz(J) | direct | residual (N) | relative | floor (relative) "
      "| termination "
      "| interior it. | crossover | factorizations | factor nnz | space |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---|\n");
  for (const std::string& line : direct_table) std::printf("%s\n", line.c_str());
  std::printf(
      "\n| system | direct | active-set | relative | termination | outer it. | factorizations "
      "| max Δv2 (m/s) | PGS to relative 1e-10 |\n"
      "|---|---:|---:|---:|---|---:|---:|---:|---:|\n");
  for (const std::string& line : compare_table) std::printf("%s\n", line.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "--active-set-child") {
    return active_set_child(argv[2], argv[3]);
  }
  Options o;
  if (!parse_options(argc, argv, o)) {
    std::cerr << "usage: bench_exact [--out FILE] [--repeats K] [--budget-s S] "
                 "[--active-set-budget-s S] [--max-base B] [--quick]\n";
    return 2;
  }
  const auto bench_start = Clock::now();
  nlohmann::json doc{{"bench", "exact paths (direct, active-set) and PGS to relative 1e-10"},
                     {"started", utc_now()},
                     {"load_average_start", load_average()},
                     {"relative_tolerance", kRelativeTolerance},
                     {"repeats", o.repeats},
                     {"budget_s", o.budget_s},
                     {"active_set_budget_s", o.active_budget_s},
                     {"max_base", o.max_base},
                     {"quick", o.quick},
                     {"systems", nlohmann::json::array()}};
  // Rewritten after every system, so a long run that fails late keeps what it measured.
  const auto save = [&]() {
    if (o.out_path.empty()) return true;
    doc["total_s"] = seconds_since(bench_start);
    doc["load_average_end"] = load_average();
    try {  // whole or not at all: a temporary file beside it, renamed into place
      cbps::write_output_file(o.out_path, "--out " + o.out_path, doc.dump(2) + "\n");
      return true;
    } catch (const std::exception& e) {
      std::cerr << "bench_exact: " << e.what() << "\n";
      return false;
    }
  };
  bool saved = true;
  std::vector<std::string> direct_table, compare_table;
  bool pyramid_over_budget = false;  // a smaller pyramid already did not fit the budget
  for (const Case& c : cases_of(o)) {
    bench_case(c, o, pyramid_over_budget, doc["systems"], direct_table, compare_table);
    saved = save() && saved;  // on failure, go on: the tables on stdout still come
  }
  print_tables(direct_table, compare_table);
  std::fprintf(stderr, "bench_exact: %.0f s in all\n", seconds_since(bench_start));
  return save() && saved ? 0 : 1;
}
