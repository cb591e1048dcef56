// The peers as methods (peers.hpp): which problems each takes, and cbps's verdict on what it
// returns. The conversions and calls are siconos.cpp and bullet.cpp.
#include "cbps/solvers/peers/peers.hpp"

#include <chrono>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/system/cone_problem.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps {

namespace {

bool is_siconos(Method m) { return method_entry(m).library == Library::Siconos; }
bool is_bullet(Method m) { return method_entry(m).library == Library::Bullet; }

}  // namespace

bool is_peer(Method method) { return method_entry(method).library != Library::Cbps; }

bool peer_available(Method method) {
#ifdef CBPS_HAVE_SICONOS
  if (is_siconos(method)) return true;
#endif
#ifdef CBPS_HAVE_BULLET
  if (is_bullet(method)) return true;
#endif
  return false;
}

std::string peer_library(Method method) {
  return is_siconos(method) ? "Siconos numerics" : is_bullet(method) ? "Bullet" : "cbps";
}

PeerClass peer_class(const BoxedProblem& problem) {
  if (problem.cones != nullptr) return PeerClass::FrictionContact;
  if ((problem.cmin.array() == 0.0).all() && (problem.cmax.array() == kInf).all())
    return PeerClass::Lcp;
  if (problem.cmin.allFinite() && problem.cmax.allFinite()) return PeerClass::Relay;
  return PeerClass::Mlcp;
}

std::string to_string(PeerClass c) {
  switch (c) {
    case PeerClass::Lcp:
      return "LCP";
    case PeerClass::Relay:
      return "relay";
    case PeerClass::Mlcp:
      return "MLCP";
    case PeerClass::FrictionContact:
      return "frictional contact problem (fc3d)";
  }
  return "?";
}

long peer_max_rows(Method method) { return method_entry(method).max_rows; }

std::string peer_refusal(Method method, const BoxedProblem& problem) {
  const std::string name(to_string(method));
  if (!peer_available(method)) {
    return is_siconos(method)
               ? name +
                     ": this build has no Siconos numerics; install libsiconos-numerics-dev "
                     "(scripts/setup.sh installs it) and configure again (cmake --preset release)"
               : name +
                     ": this build has no Bullet; install libbullet-dev (scripts/setup.sh "
                     "installs it) and configure again (cmake --preset release)";
  }
  const long c = problem.rows();
  if (c > peer_max_rows(method))
    return name + ": the problem has " + std::to_string(c) + " rows; " + name +
           " is run on at most " + std::to_string(peer_max_rows(method)) + " (" +
           std::string(method_entry(method).rows_why) + ")";
  if (is_siconos_fc3d(method)) {
    // Siconos' FrictionContactProblem: every row a contact's (normal, t1, t2), Coulomb's law.
    if (problem.cones == nullptr)
      return name +
             ": Siconos' fc3d solvers take a problem whose contacts live in Coulomb's cone (an "
             "FCLIB file, a scene with friction=cone); this one is the boxed problem of 6.2 "
             "(siconos:lemke, siconos:pgs, siconos:enum and siconos:avi solve it)";
    if (problem.cones->law != FrictionLaw::CoulombCone)
      return name + ": Siconos' fc3d solvers solve Coulomb's law (De Saxce's form); this " +
             "problem's law is the convex relaxation (ccp), which nsgs and direct solve";
    const std::vector<char> in_cone = problem.cones->rows_in_cones(c);
    for (long k = 0; k < c; ++k)
      if (!in_cone[static_cast<std::size_t>(k)])
        return name + ": Siconos' frictional contact problem has only contacts' rows, and row " +
               std::to_string(k) + " is in no contact (bounds [" + number_text(problem.cmin[k]) +
               ", " + number_text(problem.cmax[k]) + "]); nsgs and direct solve such a problem";
  }
  if (const auto refuse = method_entry(method).refuse) return refuse(problem);
  return "";
}

SolverSummary solve_peer(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::string refusal = peer_refusal(options.method, problem);
  if (!refusal.empty()) throw InputError(refusal);
  if (lambda.size() != problem.rows()) lambda = VecX::Zero(problem.rows());
  const PeerRun run = is_siconos(options.method) ? run_siconos(problem, lambda, options)
                                                 : run_bullet(problem, lambda, options);
  SolverSummary s;
  s.iterations = run.iterations < 0 ? 0 : run.iterations;
  s.peer_status = run.status;
  s.peer_said_ok = run.said_ok;
  s.convert_time_s = run.convert_s;
  s.peer_solve_time_s = run.solve_s;
  s.peer_iterations = run.iterations;
  s.residual = natural_map_residual(problem, lambda);
  const UnitFreeResidual unit_free = unit_free_residual(problem, lambda);
  const bool solved = is_solved(unit_free, lambda);
  // An iterative peer stops by its own rule or its limit: ResidualTolerance only when cbps's
  // tolerance holds at its end.
  const bool at_tolerance = options.tolerance > 0.0 && s.residual <= options.tolerance;
  s.termination = !lambda.allFinite()             ? Termination::NonFinite
                  : run.timed_out                 ? Termination::TimeLimit
                  : !solved                       ? Termination::PeerUnsolved
                  : !is_iterative(options.method) ? Termination::Direct
                  : at_tolerance                  ? Termination::ResidualTolerance
                                                  : Termination::MaxIterations;
  std::ostringstream msg;
  msg << to_string(options.method) << " on the " << run.problem_class << ": peer "
      << (run.said_ok ? "said ok" : "said failed") << " (" << run.status << ")";
  if (run.iterations >= 0) msg << " after " << run.iterations << " iterations";
  msg << "; residual " << s.residual << " N, unit-free " << unit_free.relative << " "
      << (solved ? "<=" : ">") << " " << kSolvedTolerance << ": "
      << (solved        ? "solved"
          : run.said_ok ? "not solved, although the peer said ok"
                        : "not solved")
      << "; conversion " << run.convert_s << " s, solve " << run.solve_s << " s";
  if (options.describe) s.message = msg.str();
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

}  // namespace cbps
