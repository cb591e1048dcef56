// `cbps lcp` across the ranks of an MPI job (docs/distributed.md): `--solver tao:TYPE` (PETSc/TAO
// on a folder read by rows, a Siconos file or a generated chain) and `--solver direct` under
// mpirun or on a generated pyramid (the exact path under MPI, distributed/exact.hpp). Every rank
// holds only its own rows; rank 0 alone reports, through the command's own report, and every
// rank returns the same exit code. Bad input on any rank ends every rank with exit 2, reported
// once, by the lowest rank that found it: the options are checked and the rows read (and rank 0
// opens --out) before anything is distributed, and the ranks agree on the outcome by one
// reduction, so none is left waiting in a collective call.
//
// Built only with PETSc (CBPS_HAVE_PETSC); the command line says how to get it otherwise.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cbps/io/output_dir.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/lcp.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps::distributed {

/// The largest generated problem --write-system gathers onto rank 0, and whose lambda the JSON
/// object carries.
inline constexpr long kMaxGatheredRows = 100000;

/// What `cbps lcp` asks of the distributed path: its options as given.
struct LcpJob {
  std::string problem;  ///< PROBLEM, empty with `generate`
  std::string solver;   ///< --solver: "tao:TYPE", or "direct" (the exact path under MPI)
  bool direct = false;  ///< the exact path under MPI (else TAO)
  int iterations = 10000;
  double tolerance = SolveSettings{}.tolerance;  ///< N (TAO: its gatol)
  double time_limit = 0.0;                       ///< s, 0: none (the exact path only)
  std::string generate;                          ///< "chain", "pyramid" or empty
  std::string rows;                              ///< --rows N as given (1e6 accepted)
  std::string write_system;                      ///< --write-system DIR, or empty
  std::string out;                               ///< --out DIR, or empty
  /// PROBLEM read whole on every rank (a Siconos file: small and dense), with the command's
  /// --siconos and --cone applied.
  std::function<StoredProblem()> read_whole;
};

/// What rank 0 reports: what report() of `cbps lcp` takes, with the residuals measured on the
/// distributed vectors and the fields the distributed path adds to the JSON object.
struct LcpJobReport {
  std::string problem;  ///< PROBLEM, or the generated problem's description
  LcpFacts facts;
  LcpOutcome outcome;
  double wall = 0.0;  ///< the solve's, s
  std::optional<double> residual;
  std::optional<UnitFreeResidual> unit_free;
  nlohmann::json fields = nlohmann::json::object();  ///< ranks, memory, tao or direct
  OutputDir* dir = nullptr;                          ///< --out on rank 0, or none
};

/// Runs `job` on every rank of this process's MPI job (one rank without mpirun); `report` runs
/// on rank 0 alone and returns the exit code every rank returns. InputError for bad options or
/// input (thrown on the lowest rank that found it; the other ranks return 2).
int run_lcp_job(const LcpJob& job, const std::function<int(const LcpJobReport&)>& report);

}  // namespace cbps::distributed
