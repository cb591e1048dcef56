// Siconos numerics (4.4, C API) on cbps's boxed problem: the LCP, relay and MLCP forms of
// peers.hpp, each built dense, handed to Siconos' driver, and read back into lambda; and on a
// problem with Coulomb's cones, its FrictionContactProblem for the fc3d solvers.
#include <cmath>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/peers/peers.hpp"

#ifdef CBPS_HAVE_SICONOS

#include <siconos/numerics/FrictionContactProblem.h>
#include <siconos/numerics/Friction_cst.h>
#include <siconos/numerics/LCP_Solvers.h>
#include <siconos/numerics/LinearComplementarityProblem.h>
#include <siconos/numerics/MLCP_Solvers.h>
#include <siconos/numerics/MixedLinearComplementarityProblem.h>
#include <siconos/numerics/NonSmoothDrivers.h>
#include <siconos/numerics/NumericsMatrix.h>
#include <siconos/numerics/NumericsVerbose.h>
#include <siconos/numerics/RelayProblem.h>
#include <siconos/numerics/Relay_Solvers.h>
#include <siconos/numerics/SolverOptions.h>
#include <siconos/numerics/lcp_cst.h>
#include <siconos/numerics/mlcp_cst.h>
#include <siconos/numerics/relay_cst.h>
#include <siconos/numerics/sn_error_handling.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csetjmp>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "child_process.hpp"

/// Siconos' options (its global SolverOptions), apart from cbps's own.
using SiconosOptions = ::SolverOptions;

namespace cbps {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Siconos' solver ids of each of its methods, per problem class it takes (0: it has none).
struct SiconosIds {
  Method method;
  int lcp, relay, mlcp, fc3d;
};
constexpr SiconosIds kSiconosIds[] = {
    {Method::SiconosLemke, SICONOS_LCP_LEMKE, SICONOS_RELAY_LEMKE, SICONOS_MLCP_LCP_LEMKE, 0},
    {Method::SiconosPgs, SICONOS_LCP_PGS, SICONOS_RELAY_PGS, SICONOS_MLCP_PGS, 0},
    {Method::SiconosEnum, SICONOS_LCP_ENUM, SICONOS_RELAY_ENUM, SICONOS_MLCP_ENUM, 0},
    {Method::SiconosAvi, SICONOS_LCP_AVI_CAOFERRIS, SICONOS_RELAY_AVI_CAOFERRIS, 0, 0},
    {Method::SiconosFc3dNsgs, 0, 0, 0, SICONOS_FRICTION_3D_NSGS},
    {Method::SiconosFc3dNsnAc, 0, 0, 0, SICONOS_FRICTION_3D_NSN_AC},
    {Method::SiconosFc3dProx, 0, 0, 0, SICONOS_FRICTION_3D_PROX},
    {Method::SiconosFc3dAdmm, 0, 0, 0, SICONOS_FRICTION_3D_ADMM},
};

/// Siconos' solver id for a peer on a problem class; 0 when it has none.
int solver_id(Method method, PeerClass c) {
  for (const SiconosIds& ids : kSiconosIds)
    if (ids.method == method)
      return c == PeerClass::Lcp     ? ids.lcp
             : c == PeerClass::Relay ? ids.relay
             : c == PeerClass::Mlcp  ? ids.mlcp
                                     : ids.fc3d;
  return 0;
}

/// The MLCP of a boxed problem (Cottle, Pang & Stone 1992, 1.5): z = [u; v], w = M z + q,
/// w_1 = 0 (the free rows, u = their lambda), 0 ≤ v ⊥ w_2 ≥ 0. With r = A lambda − b (6.2):
///   a row with cmin finite, cmax = ∞:  v = lambda − cmin,  w = r
///   a row with cmin = −∞, cmax finite: v = cmax − lambda,  w = −r
///   a row with both finite:            v1 = lambda − cmin, w = r + sigma
///                                      v2 = sigma,         w = cmax − lambda
/// (sigma ≥ 0 is r's negative part: at cmax, r = −sigma ≤ 0; between the bounds sigma = 0 and
/// r = 0; at cmin, sigma = 0 and r ≥ 0: the box's complementarity). Each unknown j moves
/// lambda's row moves[j] by sign[j] (moves −1: sigma); each equation i is sign_eq[i] times r's
/// row of_r[i] plus the extra terms.
struct MlcpForm {
  int n = 0, m = 0;
  std::vector<long> moves, of_r;
  std::vector<double> sign, sign_eq;
  VecX lambda0;  ///< lambda at z = 0
  MatX M;
  VecX q;
};

MlcpForm mlcp_form(const BoxedProblem& p) {
  const long c = p.rows();
  MlcpForm f;
  f.lambda0 = VecX::Zero(c);
  struct Extra {
    long eq, var;
    double value;
  };
  std::vector<Extra> extras;
  std::vector<std::pair<long, double>> constant;  // (equation, value) added to q
  const auto add = [&](long row, double s, double s_eq) {
    f.moves.push_back(row);
    f.sign.push_back(s);
    f.of_r.push_back(row);
    f.sign_eq.push_back(s_eq);
  };
  for (long k = 0; k < c; ++k)  // the equalities first
    if (!std::isfinite(p.cmin[k]) && !std::isfinite(p.cmax[k])) add(k, 1.0, 1.0);
  f.n = static_cast<int>(f.moves.size());
  for (long k = 0; k < c; ++k) {
    const bool lo = std::isfinite(p.cmin[k]), hi = std::isfinite(p.cmax[k]);
    if (lo && !hi) {
      f.lambda0[k] = p.cmin[k];
      add(k, 1.0, 1.0);
    } else if (!lo && hi) {
      f.lambda0[k] = p.cmax[k];
      add(k, -1.0, -1.0);
    } else if (lo && hi) {
      f.lambda0[k] = p.cmin[k];
      const long v1 = static_cast<long>(f.moves.size());
      add(k, 1.0, 1.0);       // v1, w = r + sigma
      f.moves.push_back(-1);  // v2 = sigma
      f.sign.push_back(0.0);
      f.of_r.push_back(-1);  // w = cmax − lambda
      f.sign_eq.push_back(0.0);
      const long v2 = v1 + 1;
      extras.push_back({v1, v2, 1.0});
      extras.push_back({v2, v1, -1.0});
      constant.emplace_back(v2, p.cmax[k] - p.cmin[k]);
    }
  }
  const long N = static_cast<long>(f.moves.size());
  f.m = static_cast<int>(N - f.n);
  const MatX A = MatX(p.A);
  const VecX r0 = A * f.lambda0 - p.b;
  f.M = MatX::Zero(N, N);
  f.q = VecX::Zero(N);
  for (long i = 0; i < N; ++i) {
    if (f.of_r[i] < 0) continue;
    f.q[i] = f.sign_eq[i] * r0[f.of_r[i]];
    for (long j = 0; j < N; ++j)
      if (f.moves[j] >= 0) f.M(i, j) = f.sign_eq[i] * f.sign[j] * A(f.of_r[i], f.moves[j]);
  }
  for (const Extra& e : extras) f.M(e.eq, e.var) += e.value;
  for (const auto& [eq, value] : constant) f.q[eq] += value;
  return f;
}

/// What one driver call returned.
struct DriverCall {
  int info = -1;
  bool fatal = false;  ///< Siconos' own fatal error (sn_fatal_error), caught by its longjmp
  std::string fatal_message;
};

/// Calls a Siconos driver with its error handler armed: a fatal error inside Siconos longjmps
/// here instead of aborting the process. Only C objects live in this frame across setjmp.
template <typename Problem>
DriverCall call_driver(int (*driver)(Problem*, double*, double*, SiconosOptions*),
                       Problem* problem,
                       double* z,
                       double* w,
                       SiconosOptions* options) {
  DriverCall call;
  if (SN_SETJMP_EXTERNAL_START == 0) {
    call.info = driver(problem, z, w, options);
    SN_SETJMP_EXTERNAL_STOP
  } else {
    SN_SETJMP_EXTERNAL_STOP
    call.fatal = true;
    const char* message = sn_fatal_error_msg();
    call.fatal_message = message != nullptr ? message : "";
  }
  return call;
}

/// Siconos' options for a peer: the iteration limit and tolerance from cbps's (peers.hpp).
SiconosOptions* peer_options(int id, Method method, long size, const SolverOptions& options) {
  SiconosOptions* o = solver_options_create(id);
  // filterOn stays on (Siconos' default): its word includes its own check of the answer.
  if (is_iterative(method)) {  // pgs and the fc3d solvers: cbps's sweep limit and tolerance
    o->iparam[SICONOS_IPARAM_MAX_ITER] = options.max_iterations;
    o->dparam[SICONOS_DPARAM_TOL] = options.tolerance;  // 0: every sweep
  } else {
    // Pivoting (Lemke, Cao-Ferris): a pivot limit, not a sweep limit; at least 10 per unknown.
    o->iparam[SICONOS_IPARAM_MAX_ITER] = std::max(o->iparam[SICONOS_IPARAM_MAX_ITER],
                                                  static_cast<int>(std::min(10 * size, 1L << 30)));
    if (options.tolerance > 0.0) o->dparam[SICONOS_DPARAM_TOL] = options.tolerance;
  }
  return o;
}

PeerRun finish(PeerRun run, const DriverCall& call, const SiconosOptions* o, Method method) {
  run.said_ok = !call.fatal && call.info == 0;
  run.status =
      call.fatal ? "fatal error: " + call.fatal_message : "info " + std::to_string(call.info);
  if (method != Method::SiconosEnum && !call.fatal)
    run.iterations = o->iparam[SICONOS_IPARAM_ITER_DONE];
  return run;
}

/// A Siconos dense matrix on M's storage (Eigen's column-major, as NM_DENSE), released
/// without freeing that storage.
struct DenseView {
  NumericsMatrix* nm;
  explicit DenseView(MatX& M)
      : nm(NM_create_from_data(
            NM_DENSE, static_cast<int>(M.rows()), static_cast<int>(M.cols()), M.data())) {}
  DenseView(const DenseView&) = delete;
  DenseView& operator=(const DenseView&) = delete;
  ~DenseView() {
    NM_clear_not_dense(nm);
    std::free(nm);
  }
};

/// Siconos' MLCP of f (both its storages: (M, q) and the blocks A, B, C, D, a, b) solved from
/// z = 0; its enumeration needs its own init and reset around the driver.
DriverCall mlcp_call(MlcpForm& f, VecX& z, SiconosOptions* o, bool enumeration) {
  const int N = f.n + f.m;
  MatX Ab = f.M.topLeftCorner(f.n, f.n), Cb = f.M.topRightCorner(f.n, f.m),
       Db = f.M.bottomLeftCorner(f.m, f.n), Bb = f.M.bottomRightCorner(f.m, f.m);
  VecX ab = f.q.head(f.n), bb = f.q.tail(f.m);
  std::vector<int> blocks_rows{0, f.n, N}, blocks_comp{0, 1};
  DenseView M(f.M);
  MixedLinearComplementarityProblem mlcp{};
  mlcp.isStorageType1 = 1;
  mlcp.isStorageType2 = 1;
  mlcp.n = f.n;
  mlcp.m = f.m;
  mlcp.blocksRows = blocks_rows.data();
  mlcp.blocksIsComp = blocks_comp.data();
  mlcp.M = M.nm;
  mlcp.q = f.q.data();
  mlcp.A = Ab.data();
  mlcp.B = Bb.data();
  mlcp.C = Cb.data();
  mlcp.D = Db.data();
  mlcp.a = ab.data();
  mlcp.b = bb.data();
  VecX w = VecX::Zero(N);
  if (enumeration) mlcp_driver_init(&mlcp, o);
  const DriverCall call = call_driver(&mlcp_driver, &mlcp, z.data(), w.data(), o);
  if (enumeration) mlcp_driver_reset(&mlcp, o);
  return call;
}

/// The peer in this process (run_siconos runs it in a child): the problem in Siconos' class
/// (peers.hpp), its options, the driver, lambda read back.
PeerRun run_here(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  numerics_set_verbose(0);
  const auto start = std::chrono::steady_clock::now();
  const PeerClass c = peer_class(problem);
  PeerRun run;
  run.problem_class = to_string(c);
  const Method method = options.method;
  std::chrono::steady_clock::time_point solve_start;
  const auto convert_done = [&] {
    run.convert_s = seconds_since(start);
    solve_start = std::chrono::steady_clock::now();
  };
  if (c == PeerClass::FrictionContact) {
    // Every row is a contact's, contact i's rows 3i (normal), 3i + 1, 3i + 2 (peer_refusal):
    // u = W r + q with W = A, q = −b, r = lambda, as FCLIB's local problem (cone_problem.hpp).
    MatX W = MatX(problem.A);
    VecX q = -problem.b, mu = problem.cones->mu, u = VecX::Zero(problem.rows());
    DenseView view(W);
    SiconosOptions* o =
        peer_options(solver_id(method, c), method, static_cast<long>(problem.rows()), options);
    FrictionContactProblem fc{};
    fc.dimension = 3;
    fc.numberOfContacts = static_cast<int>(problem.cones->contacts());
    fc.M = view.nm;
    fc.q = q.data();
    fc.mu = mu.data();
    convert_done();
    const DriverCall call = call_driver(&fc3d_driver, &fc, lambda.data(), u.data(), o);
    run.solve_s = seconds_since(solve_start);
    run = finish(run, call, o, method);
    solver_options_delete(o);
    return run;
  }
  if (c != PeerClass::Mlcp) {
    MatX M = MatX(problem.A);
    VecX q = -problem.b, lb = problem.cmin, ub = problem.cmax, w = VecX::Zero(problem.rows());
    const int size = static_cast<int>(problem.rows());
    DenseView view(M);
    SiconosOptions* o = peer_options(solver_id(method, c), method, size, options);
    LinearComplementarityProblem lcp{size, view.nm, q.data()};
    RelayProblem relay{size, view.nm, q.data(), lb.data(), ub.data()};
    convert_done();
    const DriverCall call =
        c == PeerClass::Lcp
            ? call_driver(&linearComplementarity_driver, &lcp, lambda.data(), w.data(), o)
            : call_driver(&relay_driver, &relay, lambda.data(), w.data(), o);
    run.solve_s = seconds_since(solve_start);
    run = finish(run, call, o, method);
    solver_options_delete(o);
    return run;
  }
  MlcpForm f = mlcp_form(problem);
  const int N = f.n + f.m;
  VecX z = VecX::Zero(N);
  DriverCall call;
  SiconosOptions* o = nullptr;
  if (f.n == 0) {
    // No free row: the MLCP is an LCP (Siconos' MLCP Lemke factors the empty equality block and
    // ends the process), handed to Siconos' LCP solver of the same name.
    run.problem_class = "LCP of the boxed rows split in two";
    o = peer_options(solver_id(method, PeerClass::Lcp), method, N, options);
    DenseView view(f.M);
    LinearComplementarityProblem lcp{N, view.nm, f.q.data()};
    VecX w = VecX::Zero(N);
    convert_done();
    call = call_driver(&linearComplementarity_driver, &lcp, z.data(), w.data(), o);
  } else {
    o = peer_options(solver_id(method, c), method, N, options);
    convert_done();
    call = mlcp_call(f, z, o, method == Method::SiconosEnum);
  }
  run.solve_s = seconds_since(solve_start);
  run = finish(run, call, o, method);
  solver_options_delete(o);
  lambda = f.lambda0;
  for (long j = 0; j < N; ++j)
    if (f.moves[j] >= 0) lambda[f.moves[j]] += f.sign[j] * z[j];
  return run;
}

}  // namespace

PeerRun run_siconos(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  // Siconos can end the process it runs in: an assert() in its matrix code, exit() after a
  // failed LAPACK call (measured: its MLCP Lemke on a chain, an LU of an empty block).
  return run_in_child(problem, lambda, options, run_here, "Siconos");
}

}  // namespace cbps

#else  // a build without Siconos: solve_peer refuses before it gets here

namespace cbps {
PeerRun run_siconos(const BoxedProblem&, VecX&, const SolverOptions&) { return {}; }
}  // namespace cbps

#endif

namespace cbps {

namespace {

/// Siconos' AVI solver (Cao & Ferris) takes an LCP or a relay problem: no free row. Without free
/// rows an MLCP is an LCP (its boxed rows split in two, above).
std::string avi_refusal(const BoxedProblem& problem) {
  for (long k = 0; k < problem.rows(); ++k)
    if (!std::isfinite(problem.cmin[k]) && !std::isfinite(problem.cmax[k]))
      return "siconos:avi: Siconos' AVI solver (Cao & Ferris) takes an LCP or a relay problem, "
             "and row " +
             std::to_string(k) +
             " is free (both bounds infinite: an equality of an MLCP, which it does not take)";
  return "";
}

}  // namespace

// This file's entries in the one table of methods (methods.hpp, gathered by methods.cpp); the
// entries are there in every build, the peers refuse where the build has no Siconos
// (peer_available).

extern const MethodEntry kSiconosLemkeEntry;
constexpr MethodEntry kSiconosLemkeEntry{
    .method = Method::SiconosLemke,
    .name = "siconos:lemke",
    .iterative = false,
    .library = Library::Siconos,
    .max_rows = kPeerDenseRows,
    .rows_why = "it works on a dense copy of A",
    .solve = solve_peer,
    .what =
        "Siconos numerics' lexicographic Lemke on the LCP, relay or MLCP (dense, <= 3000 "
        "rows)",
};

extern const MethodEntry kSiconosPgsEntry;
constexpr MethodEntry kSiconosPgsEntry{
    .method = Method::SiconosPgs,
    .name = "siconos:pgs",
    .library = Library::Siconos,
    .max_rows = kPeerDenseRows,
    .rows_why = "it works on a dense copy of A",
    .solve = solve_peer,
    .what = "Siconos numerics' projected Gauss-Seidel on the LCP, relay or MLCP (dense)",
};

extern const MethodEntry kSiconosEnumEntry;
constexpr MethodEntry kSiconosEnumEntry{
    .method = Method::SiconosEnum,
    .name = "siconos:enum",
    .iterative = false,
    .library = Library::Siconos,
    .max_rows = kPeerEnumerationRows,
    .rows_why = "it enumerates 2^rows cases",
    .solve = solve_peer,
    .what = "Siconos numerics' enumeration of the complementarity cases (<= 20 rows)",
};

extern const MethodEntry kSiconosAviEntry;
constexpr MethodEntry kSiconosAviEntry{
    .method = Method::SiconosAvi,
    .name = "siconos:avi",
    .iterative = false,
    .library = Library::Siconos,
    .max_rows = kPeerDenseRows,
    .rows_why = "it works on a dense copy of A",
    .solve = solve_peer,
    .refuse = avi_refusal,
    .what = "Siconos numerics' AVI solver of Cao & Ferris on the LCP or relay (dense)",
};

extern const MethodEntry kSiconosFc3dNsgsEntry;
constexpr MethodEntry kSiconosFc3dNsgsEntry{
    .method = Method::SiconosFc3dNsgs,
    .name = "siconos:fc3d-nsgs",
    .library = Library::Siconos,
    .laws = kCoulombLaw,
    .max_rows = kPeerDenseConeRows,
    .rows_why = "it works on a dense copy of A",
    .solve = solve_peer,
    .what =
        "Siconos numerics' non-smooth Gauss-Seidel on Coulomb's cones (fc3d; dense, <= 6000 "
        "rows)",
};

extern const MethodEntry kSiconosFc3dNsnAcEntry;
constexpr MethodEntry kSiconosFc3dNsnAcEntry{
    .method = Method::SiconosFc3dNsnAc,
    .name = "siconos:fc3d-nsn-ac",
    .library = Library::Siconos,
    .laws = kCoulombLaw,
    .max_rows = kPeerDenseConeRows,
    .rows_why = "it works on a dense copy of A",
    .solve = solve_peer,
    .what =
        "Siconos numerics' non-smooth Newton on Alart-Curnier's function (fc3d; Coulomb's "
        "cones)",
};

extern const MethodEntry kSiconosFc3dProxEntry;
constexpr MethodEntry kSiconosFc3dProxEntry{
    .method = Method::SiconosFc3dProx,
    .name = "siconos:fc3d-prox",
    .library = Library::Siconos,
    .laws = kCoulombLaw,
    .max_rows = kPeerDenseConeRows,
    .rows_why = "it works on a dense copy of A",
    .solve = solve_peer,
    .what = "Siconos numerics' proximal points around NSN-AC (fc3d; Coulomb's cones)",
};

extern const MethodEntry kSiconosFc3dAdmmEntry;
constexpr MethodEntry kSiconosFc3dAdmmEntry{
    .method = Method::SiconosFc3dAdmm,
    .name = "siconos:fc3d-admm",
    .library = Library::Siconos,
    .laws = kCoulombLaw,
    .max_rows = kPeerDenseConeRows,
    .rows_why = "it works on a dense copy of A",
    .solve = solve_peer,
    .what = "Siconos numerics' ADMM on Coulomb's cones (fc3d)",
};

}  // namespace cbps
