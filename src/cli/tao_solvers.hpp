// `tao:TYPE` in the solver lists of `cbps converge` and `cbps profile` (docs/distributed.md,
// "TAO beside PGS: converge and profile"): PETSc/TAO's bound-constrained minimisers run in this
// one process, a job of one MPI rank, beside the cbps solvers. The core library knows nothing of
// PETSc: the tao specs are parsed here, in the CLI, which alone is built with CBPS_HAVE_PETSC.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cbps/distributed/tao.hpp"
#include "cbps/studies/convergence.hpp"
#include "cbps/studies/profile.hpp"
#include "cbps/studies/solver_spec.hpp"

namespace cbps::cli {

using distributed::is_tao_solver;

/// The message of a build without PETSc for `OPTION SPEC` (e.g. "--solver tao:tron"), the same
/// for `cbps lcp --solver` and the --solvers lists: how to get PETSc.
std::string without_petsc_message(const std::string& option_and_spec);

/// Every name a command that takes tao:TYPE accepts: solver_names() (solver_spec.hpp), then
/// tao:TYPE. The list of --help and of every "unknown solver" message of lcp, converge, profile.
std::string cli_solver_names();

/// parse_solver_spec (solver_spec.hpp) with `tao:TYPE` too (SolverSpec::tao = TYPE): an unknown
/// name lists cli_solver_names(); an unknown TAO type, options after it, or (exit 2) a build
/// without PETSc (without_petsc_message) are InputErrors naming `what`.
SolverSpec parse_cli_solver_spec(const std::string& text, const std::string& what);

/// parse_solver_list (solver_spec.hpp) with `tao:TYPE` entries too: those get SolverSpec::tao =
/// TYPE. InputError naming `what` for an unknown TAO type or options after it, and (exit 2)
/// without_petsc_message in a build without PETSc.
std::vector<SolverSpec> parse_cli_solver_list(const std::string& text, const std::string& what);

/// One line per TAO entry for a --solvers list's --help: "tao:TYPE ..." with the types, or that
/// the build has none.
std::string tao_spec_help();

/// PETSc and MPI for a whole command (converge, profile), made once before its first TAO solve:
/// PetscInitialize when made, PetscFinalize when destroyed, however many solves run between. In
/// a build without PETSc, or for a list without tao specs, it starts nothing.
class TaoInProcess {
 public:
  /// Starts PETSc when `specs` holds a tao spec; InputError (exit 2) naming `what` when this
  /// process is one rank of several (these commands run TAO in one process, not under mpirun -n
  /// N with N > 1).
  TaoInProcess(const std::vector<SolverSpec>& specs, const std::string& what);
  ~TaoInProcess();
  TaoInProcess(const TaoInProcess&) = delete;
  TaoInProcess& operator=(const TaoInProcess&) = delete;

  /// How run_spec and profile_spec run a tao:TYPE spec here (distributed/tao_studies.hpp);
  /// empty without PETSc or a tao spec (parse_cli_solver_list refused any then).
  ConvergenceTao converge() const;
  ProfileTao profile() const;

 private:
  struct Session;
  std::unique_ptr<Session> session_;
};

}  // namespace cbps::cli
