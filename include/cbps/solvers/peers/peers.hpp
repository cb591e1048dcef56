// The field's own solvers on cbps's boxed problem (6.2): Siconos numerics (Acary, Brémond &
// Huber, INRIA; LCP, relay and MLCP solvers, C API) and Bullet's MLCP solvers (Coumans; Dantzig
// after ODE, Lemke, projected Gauss-Seidel). They are methods like cbps's own (`siconos:lemke`,
// `bullet:dantzig`, ...): solve() runs them, and what they return is judged by cbps's
// natural-map residual, never by their word (docs/peers.md).
//
// Each peer is handed the problem in its own class and its own storage, converted here and timed
// apart from its solve (SolverSummary::convert_time_s):
//   Siconos: an LCP (w = M z + q, 0 ≤ z ⊥ w ≥ 0) when every row is [0, ∞); a relay problem
//            (lb ≤ z ≤ ub, −w in the normal cone of the box) when every bound is finite; an MLCP
//            otherwise (free rows as equalities, one-sided rows shifted, boxed rows split in
//            two complementarity pairs, below). M = A dense, q = −b. Its fc3d solvers
//            (siconos:fc3d-*) take a problem whose every row is in a contact under Coulomb's
//            law (cone_problem.hpp) as its FrictionContactProblem: dimension 3, M = A dense,
//            q = −b, mu, rows per contact normal, t1, t2 (cbps's order, FCLIB's).
//   Bullet:  btMLCPSolverInterface::solveMLCP(A, b, x, lo, hi), which is the boxed problem of
//            6.2 itself (w = A x − b), with A dense (btMatrixXu).
// Both are optional: a build without them (CBPS_HAVE_SICONOS, CBPS_HAVE_BULLET unset) refuses a
// peer with an InputError saying how to get it.
#pragma once

#include <string>

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// True for the peers' methods (siconos:*, bullet:*).
bool is_peer(Method method);
/// True for a peer compiled into this build.
bool peer_available(Method method);
/// "Siconos numerics" or "Bullet", for messages.
std::string peer_library(Method method);

/// The problem class a peer receives (Siconos' four; Bullet takes every boxed problem).
enum class PeerClass { Lcp, Relay, Mlcp, FrictionContact };
/// The class of a problem: FrictionContact when its contacts live in cones, Lcp when every row
/// is [0, ∞), Relay when every bound is finite, Mlcp otherwise.
PeerClass peer_class(const BoxedProblem& problem);
std::string to_string(PeerClass c);

/// The peers' row limits (their entries' max_rows): they work on a dense copy of A.
inline constexpr long kPeerDenseRows = kMaxDenseLemkeRows;  ///< 72 MB, as cbps's own lemke
inline constexpr long kPeerEnumerationRows = 20;  ///< 2^c cases (2^(2c) for a boxed pair): 10^6
inline constexpr long kPeerTableauRows = 1000;  ///< a dense inverse of A, a 2c x 4c tableau: 64 MB
inline constexpr long kPeerDenseConeRows = 6000;  ///< a dense W of 288 MB: 1,600 contacts' rows

/// The largest problem each peer is handed (rows of the boxed problem): the dense peers' memory
/// and the enumeration's 2^c cases.
long peer_max_rows(Method method);

/// Why a peer cannot take this problem (its class, its size, its bounds, the build), or empty.
std::string peer_refusal(Method method, const BoxedProblem& problem);

/// A peer on the whole problem from lambda (its guess where the peer takes one), with
/// options.max_iterations and options.tolerance passed as the peer's own (docs/peers.md).
/// InputError when peer_refusal is not empty. The summary's termination is cbps's verdict
/// (Direct or ResidualTolerance when cbps's verdict holds, is_solved of system/unit_free.hpp;
/// PeerUnsolved otherwise; NonFinite), its peer_status the peer's own word, and its message
/// says "not solved, although the peer said ok" when the two disagree.
SolverSummary solve_peer(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options);

/// What a peer returned, before cbps's verdict (siconos.cpp, bullet.cpp).
struct PeerRun {
  bool said_ok = false;       ///< the peer's own claim of success
  std::string status;         ///< the peer's own word: "info 0", "returned true", ...
  int iterations = -1;        ///< as the peer reports them; −1: not exposed
  double convert_s = 0.0;     ///< converting the problem to the peer's storage, s
  double solve_s = 0.0;       ///< the peer's own call, s
  std::string problem_class;  ///< what it was handed: "LCP", "relay", "MLCP", "boxed MLCP"
  bool timed_out = false;     ///< killed at SolverOptions::time_limit (lambda: the guess)
};
PeerRun run_siconos(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options);
PeerRun run_bullet(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options);

}  // namespace cbps
