// `tao:TYPE` in `cbps converge --solvers` and `cbps profile --solvers` (tao_solvers.hpp).
#include "tao_solvers.hpp"

#ifdef CBPS_HAVE_PETSC
#include "cbps/distributed/tao_studies.hpp"
#endif

#include "cbps/base/error.hpp"

namespace cbps::cli {

std::string without_petsc_message(const std::string& option_and_spec) {
  return option_and_spec +
         ": this cbps was built without PETSc; install PETSc (Debian: petsc-dev, or "
         "scripts/setup.sh --with-petsc) and build again: CMake finds it by "
         "pkg-config (option CBPS_PETSC, on by default; not under the sanitizers), "
         "see docs/distributed.md";
}

std::string cli_solver_names() { return solver_names() + ", tao:TYPE"; }

SolverSpec parse_cli_solver_spec(const std::string& text, const std::string& what) {
  if (!is_tao_solver(text)) {
    if (!is_solver_name(text))
      throw InputError(what + " '" + text + "': unknown solver (valid: " + cli_solver_names() +
                       ")");
    return parse_solver_spec(text, what);
  }
#ifndef CBPS_HAVE_PETSC
  throw InputError(without_petsc_message(what + " " + text));
#endif
  const std::string type = text.size() > 4 ? text.substr(4) : "";
  if (!distributed::is_tao_type(type))
    throw InputError(what + " '" + text +
                     "': " + (type.empty() ? "no TAO type" : "unknown TAO type \"" + type + "\"") +
                     "; use tao:TYPE with TYPE one of " + distributed::tao_type_list() +
                     " (no options after it)");
  SolverSpec spec;
  spec.text = text;
  spec.tao = type;
  return spec;
}

std::vector<SolverSpec> parse_cli_solver_list(const std::string& text, const std::string& what) {
  std::vector<SolverSpec> specs;
  std::string::size_type from = 0;
  while (true) {
    const auto comma = text.find(',', from);
    const std::string item =
        text.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    if (item.empty()) throw InputError(what + " '" + text + "': an empty entry");
    specs.push_back(parse_cli_solver_spec(item, what));
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  return specs;
}

std::string tao_spec_help() {
#ifdef CBPS_HAVE_PETSC
  return "  tao:TYPE      PETSc/TAO's bound-constrained minimiser TYPE (" +
         distributed::tao_type_list() +
         ") in this process, from lambda = 0; its iterations count as sweeps "
         "(docs/distributed.md)\n";
#else
  return "  tao:TYPE      PETSc/TAO (docs/distributed.md): not in this build (no PETSc)\n";
#endif
}

#ifdef CBPS_HAVE_PETSC

struct TaoInProcess::Session {
  distributed::MpiSession mpi;
};

TaoInProcess::TaoInProcess(const std::vector<SolverSpec>& specs, const std::string& what) {
  bool any = false;
  for (const SolverSpec& s : specs) any = any || !s.tao.empty();
  if (!any) return;
  session_ = std::make_unique<Session>();
  if (session_->mpi.size() != 1)
    throw InputError(what +
                     ": tao:TYPE runs in this one process; start the command without "
                     "mpirun (this is one of " +
                     std::to_string(session_->mpi.size()) + " ranks)");
}

ConvergenceTao TaoInProcess::converge() const {
  if (!session_) return {};
  return [this](const ConvergenceSystem& s, const SolverSpec& spec, const ConvergenceLimits& l) {
    return distributed::converge_tao(session_->mpi, s, spec, l);
  };
}

ProfileTao TaoInProcess::profile() const {
  if (!session_) return {};
  return [this](const ProfileProblem& p, const SolverSpec& spec, const ProfileLimits& l) {
    return distributed::profile_tao(session_->mpi, p, spec, l);
  };
}

#else

struct TaoInProcess::Session {};

TaoInProcess::TaoInProcess(const std::vector<SolverSpec>&, const std::string&) {}

ConvergenceTao TaoInProcess::converge() const { return {}; }

ProfileTao TaoInProcess::profile() const { return {}; }

#endif

TaoInProcess::~TaoInProcess() = default;

}  // namespace cbps::cli
