// The exact path against PGS (issue: direct path): for the built-in chain of n links
// (n = 10², 10³, 10⁴, 10⁵, one distance row per link; A tridiagonal, positive definite) and for
// a 10⁶-row chain:
//
//   direct   wall time of solve_direct from λ = 0 (islands, CHOLMOD analysis, factorization,
//            solve, refinement, residual) and the natural-map residual it reaches (N);
//   pgs      wall time and sweeps for PGS (7.1.1) from λ = 0 to reach the natural-map residuals
//            1e-3, 1e-6 and 1e-10 N, within a budget of sweeps (reported as not reached, with
//            the residual at the end, when the budget runs out);
//   sweep    the time of one PGS sweep, so "direct < 100 sweeps" can be read off.
//
// and the stack of 1000 boxes (100 columns of 10, 12,000 contact and friction rows): the
// direct path and PGS from λ = 0 to the same residuals (budget 6× the chain's).
//
// Each timing is the median of --repeats runs (default 5; the PGS runs once, they are long).
// Prints a Markdown table and writes JSON with every number to --out.
// Usage: bench_direct [--out FILE] [--max-n N] [--budget-s SECONDS] [--repeats K]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cbps/cbps.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// The chain of n links, stepped 5 times with a cheap solver so every row has its general
/// pattern (the same state bench_system uses).
cbps::System chain_system(long n) {
  cbps::Scene scene = cbps::make_builtin_scene("chain", {{"n", std::to_string(n)}});
  scene.solver.max_iterations = 10;
  scene.solver.tolerance = 0.0;
  cbps::Simulation sim(scene);
  for (int s = 0; s < 5; ++s) sim.step();
  return sim.build_system();
}

/// The stack scene of the issue: 1000 boxes in 100 columns of 10 on a ground plane, four
/// contacts per face, the paper's friction rows (mu 0.5): 12,000 rows. Stepped 3 times with
/// the direct solver so the contacts are the resting ones.
cbps::System stack_system() {
  cbps::Scene scene = cbps::make_builtin_scene(
      "stack", {{"n", "10"}, {"columns", "100"}, {"margin", "0.001"}, {"push", "improved"}});
  scene.solver.method = cbps::Method::Direct;
  cbps::Simulation sim(scene);
  for (int s = 0; s < 3; ++s) sim.step();
  return sim.build_system();
}

struct PgsReach {
  double tolerance;
  bool reached = false;
  long sweeps = 0;
  double seconds = 0.0;
  double residual = 0.0;  ///< at the end
};

/// PGS from zero, checking the residual every `check` sweeps (its cost is excluded from the
/// time), until each tolerance is reached or the sweep budget is spent.
std::vector<PgsReach> pgs_reach(const cbps::System& sys, double budget_s) {
  std::vector<PgsReach> out{{1e-3}, {1e-6}, {1e-10}};
  cbps::VecX lambda = cbps::VecX::Zero(sys.rows());
  double solving = 0.0;
  long sweeps = 0;
  long check = 1;
  double residual = cbps::natural_map_residual(sys.problem(), lambda);
  while (solving < budget_s) {
    const auto start = Clock::now();
    for (long k = 0; k < check; ++k) cbps::pgs_sweep(sys.problem(), lambda);
    solving += seconds_since(start);
    sweeps += check;
    residual = cbps::natural_map_residual(sys.problem(), lambda);
    bool all = true;
    for (PgsReach& r : out) {
      if (!r.reached && residual <= r.tolerance) {
        r.reached = true;
        r.sweeps = sweeps;
        r.seconds = solving;
      }
      all = all && r.reached;
    }
    if (all || !std::isfinite(residual)) break;
    // Check often at first, then every ~1% of the sweeps done: the reported sweep counts are
    // exact to that granularity.
    check = std::max<long>(1, sweeps / 100);
  }
  for (PgsReach& r : out) {
    if (!r.reached) {
      r.sweeps = sweeps;
      r.seconds = solving;
    }
    r.residual = residual;
  }
  return out;
}

struct Options {
  std::string out_path;
  long max_n = 100000;
  double budget_s = 10.0;
  int repeats = 5;
};

/// The command line; false on a bad one.
bool parse_options(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--out" && has_value) {
      o.out_path = argv[++i];
    } else if (a == "--max-n" && has_value) {
      o.max_n = std::atol(argv[++i]);
    } else if (a == "--budget-s" && has_value) {
      o.budget_s = std::atof(argv[++i]);
    } else if (a == "--repeats" && has_value) {
      o.repeats = std::max(1, std::atoi(argv[++i]));
    } else {
      return false;
    }
  }
  return true;
}

/// The direct path from λ = 0, `repeats` times: the wall times and the last run's summary.
std::vector<double> time_direct(const cbps::System& sys, int repeats, cbps::SolverSummary& last) {
  std::vector<double> seconds;
  for (int r = 0; r < repeats; ++r) {
    cbps::VecX lambda = cbps::VecX::Zero(sys.rows());
    last = cbps::solve_direct(sys.problem(), lambda);
    seconds.push_back(last.wall_time_s);
  }
  return seconds;
}

/// One PGS sweep's time, `repeats` times, each the mean over 10⁶/n sweeps.
std::vector<double> time_sweep(const cbps::System& sys, long n, int repeats) {
  std::vector<double> sweep_s;
  cbps::VecX lambda = cbps::VecX::Zero(sys.rows());
  const int sweeps_timed = static_cast<int>(std::max<long>(1, 1000000 / n));
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    for (int k = 0; k < sweeps_timed; ++k) cbps::pgs_sweep(sys.problem(), lambda);
    sweep_s.push_back(seconds_since(start) / sweeps_timed);
  }
  return sweep_s;
}

nlohmann::json reach_json(const PgsReach& r) {
  return {{"tolerance", r.tolerance},
          {"reached", r.reached},
          {"sweeps", r.sweeps},
          {"seconds", r.seconds},
          {"final_residual", r.residual}};
}

/// The chain of n links: its row of the first table on stdout, and its JSON.
nlohmann::json bench_chain(long n, const Options& o) {
  std::fprintf(stderr, "chain n = %ld: building\n", n);
  const cbps::System sys = chain_system(n);
  cbps::SolverSummary summary;
  const std::vector<double> direct_s = time_direct(sys, o.repeats, summary);
  const std::vector<double> sweep_s = time_sweep(sys, n, o.repeats);
  const bool run_pgs = n <= o.max_n;  // the 10⁶ chain: direct and one sweep only
  std::fprintf(stderr,
               "chain n = %ld: direct %.3g s; PGS%s\n",
               n,
               median(direct_s),
               run_pgs ? " to tolerance" : " skipped");
  const std::vector<PgsReach> reach =
      run_pgs ? pgs_reach(sys, o.budget_s) : std::vector<PgsReach>{};

  nlohmann::json row{{"links", n},
                     {"rows", sys.rows()},
                     {"nnz_A", sys.A.nonZeros()},
                     {"direct_s", median(direct_s)},
                     {"direct_residual", summary.residual},
                     {"direct_factorizations", summary.factorizations},
                     {"direct_message", summary.message},
                     {"pgs_sweep_s", median(sweep_s)}};
  std::printf("| %ld | %.3g | %.2g | %d | %.3g | %.1f |",
              n,
              median(direct_s),
              summary.residual,
              summary.factorizations,
              median(sweep_s),
              median(direct_s) / median(sweep_s));
  for (const PgsReach& r : reach) {
    row["pgs"].push_back(reach_json(r));
    if (r.reached) {
      std::printf(" %.3g s (%ld sweeps) |", r.seconds, r.sweeps);
    } else {
      std::printf(" not in %.3g s (%ld sweeps; %.2g N) |", r.seconds, r.sweeps, r.residual);
    }
  }
  if (!run_pgs) std::printf(" — | — | — |");
  std::printf("\n");
  std::fflush(stdout);
  return row;
}

/// The stack: the direct path from zero against PGS from zero; its table on stdout, its JSON.
nlohmann::json bench_stack(const Options& o) {
  std::fprintf(stderr, "stack of 1000 boxes: building\n");
  const cbps::System stack = stack_system();
  cbps::SolverSummary stack_summary;
  const std::vector<double> stack_s = time_direct(stack, o.repeats, stack_summary);
  std::fprintf(stderr,
               "stack: direct %.3g s (%s); PGS to tolerance\n",
               median(stack_s),
               stack_summary.message.c_str());
  const std::vector<PgsReach> stack_reach = pgs_reach(stack, o.budget_s * 6);
  std::printf(
      "\n| stack (rows) | direct (s) | residual (N) | islands | factorizations | PGS to 1e-3 N "
      "| PGS to 1e-6 N | PGS to 1e-10 N |\n|---|---|---|---|---|---|---|---|\n");
  std::printf("| 1000 boxes (%d) | %.3g | %.2g | %d | %d |",
              stack.rows(),
              median(stack_s),
              stack_summary.residual,
              stack_summary.islands,
              stack_summary.factorizations);
  nlohmann::json stack_json{{"rows", stack.rows()},
                            {"nnz_A", stack.A.nonZeros()},
                            {"direct_s", median(stack_s)},
                            {"direct_residual", stack_summary.residual},
                            {"direct_message", stack_summary.message}};
  for (const PgsReach& r : stack_reach) {
    stack_json["pgs"].push_back(reach_json(r));
    if (r.reached) {
      std::printf(
          " %.3g s (%ld sweeps; %.0f× direct) |", r.seconds, r.sweeps, r.seconds / median(stack_s));
    } else {
      std::printf(" not in %.3g s (%ld sweeps; %.2g N) |", r.seconds, r.sweeps, r.residual);
    }
  }
  std::printf("\n");
  return stack_json;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse_options(argc, argv, o)) {
    std::cerr << "usage: bench_direct [--out FILE] [--max-n N] [--budget-s S] [--repeats K]\n";
    return 2;
  }
  nlohmann::json result = nlohmann::json::array();
  std::printf(
      "| links | direct (s) | residual (N) | factorizations | 1 PGS sweep (s) | direct / sweep "
      "| PGS to 1e-3 N | PGS to 1e-6 N | PGS to 1e-10 N "
      "|\n|---|---|---|---|---|---|---|---|---|\n");
  std::vector<long> sizes;
  for (long n = 100; n <= o.max_n; n *= 10) sizes.push_back(n);
  sizes.push_back(1000000);
  for (const long n : sizes) result.push_back(bench_chain(n, o));
  const nlohmann::json stack_json = bench_stack(o);

  if (!o.out_path.empty()) {
    // Whole or not at all (a temporary file beside it, renamed into place).
    try {
      cbps::write_output_file(
          o.out_path,
          "--out " + o.out_path,
          nlohmann::json{{"bench", "direct vs PGS on the chain and the 1000-box stack"},
                         {"budget_s", o.budget_s},
                         {"repeats", o.repeats},
                         {"chains", result},
                         {"stack", stack_json}}
                  .dump(2) +
              "\n");
    } catch (const std::exception& e) {
      std::cerr << "bench_direct: " << e.what() << "\n";
      return 1;
    }
  }
  return 0;
}
