// cbps: the command line (see docs/cli-contract.md). Exit codes: 0 success, 1 a failed
// computation, 2 bad input or usage. Errors go to stderr as "cbps: <what>: <why>".
#include <cstdlib>
#include <iostream>
#include <new>
#include <string>
#include <utility>

#include "cbps/base/error.hpp"
#include "cbps/distributed/tao.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/solvers/threads.hpp"
#include "common.hpp"

namespace {

/// The number of processes of the MPI job this process was started in by mpirun (Open MPI's
/// OMPI_COMM_WORLD_SIZE, MPICH's PMI_SIZE), 1 when none; and this process's rank in it.
std::pair<long, long> mpi_job() {
  for (const auto& [size_name, rank_name] :
       {std::pair{"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"},
        std::pair{"PMI_SIZE", "PMI_RANK"}}) {
    const char* size = std::getenv(size_name);
    const char* rank = std::getenv(rank_name);
    if (size != nullptr) return {std::atol(size), rank != nullptr ? std::atol(rank) : 0};
  }
  return {1, 0};
}

/// True when the parsed command runs distributed, one part on every rank of an MPI job:
/// `cbps lcp` with `--solver tao:TYPE`, `--solver direct` or `--generate` (docs/distributed.md).
bool runs_distributed(const CLI::App& app) {
  const CLI::App* lcp = app.get_subcommand("lcp");
  if (lcp == nullptr || !lcp->parsed()) return false;
  const CLI::Option* solver = lcp->get_option("--solver");
  const std::string name = solver->count() > 0 ? solver->as<std::string>() : std::string();
  return cbps::distributed::is_tao_solver(name) || name == cbps::to_string(cbps::kExactMethod) ||
         lcp->get_option("--generate")->count() > 0;
}

int run(int argc, char** argv) {
  cbps::set_command_line(argc, argv);
  CLI::App app{
      "cbps: the constraint-based rigid-body solver of Tamis & Maggiore (2015), built from the "
      "paper's matrices: J, Minv, A = J Minv J^T, b, solved by projected Gauss-Seidel."};
  app.footer(
      "\nExamples:\n"
      "  cbps scenes\n"
      "  cbps run pendulum-wave --out out/wave\n"
      "  cbps run chain --param n=100 --param mass_ratio=100 --check\n"
      "  cbps explain chain --param n=2\n"
      "  cbps matrices chain --step 10 --out out/m\n"
      "  cbps lcp out/m --solver pgs\n"
      "  cbps check out/m --lambda my_lambda.txt\n"
      "  cbps verify\n"
      "  cbps converge chain --param n=100 --param mass_ratio=100 --step 100 --out out/conv\n"
      "  cbps profile out/library --solvers pgs,apgd,direct --out out/profile\n"
      "Exit codes: 0 success, 1 failed computation, 2 bad input or usage.");
  app.require_subcommand(1);
  app.set_version_flag("--version", "cbps 0.1.0");
  cbps::cli::Action action;
  cbps::cli::register_scenes(app, action);
  cbps::cli::register_run(app, action);
  cbps::cli::register_explain(app, action);
  cbps::cli::register_matrices(app, action);
  cbps::cli::register_lcp(app, action);
  cbps::cli::register_check(app, action);
  cbps::cli::register_mujoco(app, action);
  cbps::cli::register_verify(app, action);
  cbps::cli::register_converge(app, action);
  cbps::cli::register_profile(app, action);
  cbps::cli::register_stress(app, action);
  // One thread unless asked (cbps/solvers/threads.hpp): every command takes --threads.
  int threads = 1;
  for (CLI::App* command : app.get_subcommands({})) {
    command
        ->add_option("--threads",
                     threads,
                     "threads of the BLAS and OpenMP under the exact path (CHOLMOD); 0: the "
                     "libraries' own default (OPENBLAS_NUM_THREADS, OMP_NUM_THREADS, else "
                     "every core) (default: 1)")
        ->check(CLI::Range(0, 1024));
  }
  cbps::cli::set_invocation(argc, argv);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "cbps: usage: " << e.what() << " (see cbps --help)\n";
    return 2;
  }
  // Under `mpirun -n N` with N > 1 every process would run a one-process command whole,
  // print it N times and write the same --out at once: refused on every rank, said once.
  if (const auto [size, rank] = mpi_job(); size > 1 && !runs_distributed(app)) {
    const CLI::App* command = app.get_subcommands().front();
    if (rank == 0)
      std::cerr << "cbps: " << command->get_name() << ": runs in one process, and this is one of "
                << size
                << " started by mpirun; run it without mpirun (only `cbps lcp "
                   "--solver tao:TYPE`, `cbps lcp --solver direct` and `cbps lcp --generate` "
                   "are distributed, docs/distributed.md)\n";
    return 2;
  }
  try {
    cbps::set_threads(threads);
    return action();
  } catch (const cbps::InputError& e) {
    std::cerr << "cbps: " << e.what() << "\n";
    return 2;
  } catch (const cbps::ComputationError& e) {
    std::cerr << "cbps: " << e.what() << "\n";
    return 1;
  } catch (const std::invalid_argument& e) {
    std::cerr << "cbps: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "cbps: out of memory: the scene or problem needs more memory than this machine "
                 "gave (try fewer bodies or rows; for large systems `cbps matrices` writes "
                 "sparse files where `explain` prints dense ones)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "cbps: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  cbps::install_interrupt_cleanup();  // Ctrl-C and SIGTERM leave nothing behind
  return cbps::wait_if_interrupted(run(argc, argv));
}
