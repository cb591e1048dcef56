// SolverOptions::time_limit bounds every method (issue 50, item 5): the exact paths (active set,
// interior point and crossover, Lemke's pivots, the cone stages) stop at their next iteration
// past it with Termination::TimeLimit and a finite lambda, and Bullet's solvers, which take no
// limit of their own, are run in a child process killed at it. Before, only the sweeps and the
// Siconos peers stopped: `direct` and `lemke` ran to their own end, whatever the limit.
#include <catch2/catch.hpp>
#include <chrono>
#include <functional>
#include <random>

#include "cbps/solvers/peers/peers.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/cone_problem.hpp"

using namespace cbps;

namespace {

/// A = B Bᵀ + I (c×c, symmetric positive definite, dense), b in [−1, 1]; rows alternately [0, ∞)
/// and the box [−0.1, 0.1]: many rows at their bounds, so every exact path has work to do.
struct RandomProblem {
  SpMat A;
  VecX b, cmin, cmax;
  explicit RandomProblem(int c, unsigned seed = 7) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    MatX B(c, c);
    for (int i = 0; i < c; ++i)
      for (int j = 0; j < c; ++j) B(i, j) = u(rng) / std::sqrt(static_cast<double>(c));
    const MatX dense = B * B.transpose() + MatX::Identity(c, c);
    A = dense.sparseView();
    b.resize(c);
    cmin.resize(c);
    cmax.resize(c);
    for (int k = 0; k < c; ++k) {
      b(k) = u(rng);
      cmin(k) = k % 2 == 0 ? 0.0 : -0.1;
      cmax(k) = k % 2 == 0 ? kInf : 0.1;
    }
  }
  BoxedProblem problem() const {
    BoxedProblem p{A, b, cmin, cmax};
    p.symmetric = true;
    return p;
  }
};

SolverOptions limited(Method method, double time_limit) {
  SolverOptions o;
  o.method = method;
  o.tolerance = 1e-12;
  o.time_limit = time_limit;
  return o;
}

double seconds_of(const std::function<void()>& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// `method` under a limit of 1 ns (passed at its first iteration) stops with TimeLimit, a
/// finite lambda and the limit in its message; under 600 s it solves the problem as without
/// one. The limited run's summary.
SolverSummary check_stops_at_limit(const RandomProblem& r, Method method) {
  VecX lambda;
  const SolverSummary s = solve(r.problem(), lambda, limited(method, 1e-9));
  INFO(s.message);
  CHECK(s.termination == Termination::TimeLimit);
  CHECK(s.message.find("time limit") != std::string::npos);
  CHECK(lambda.size() == r.b.size());
  CHECK(lambda.allFinite());
  VecX free_lambda;
  const SolverSummary free = solve(r.problem(), free_lambda, limited(method, 600.0));
  INFO(free.message);
  CHECK(free.termination == Termination::Direct);
  return s;
}

}  // namespace

TEST_CASE("direct stops at the time limit, on the active-set and on the interior-point route",
          "[time-limit][direct]") {
  // 120 rows: the active set's rounds; 600 rows (>= interior_from_rows): the interior point and
  // the crossover. A limit of 1 ns has passed at the first iteration of either.
  for (const int c : {120, 600}) {
    CAPTURE(c);
    check_stops_at_limit(RandomProblem(c), Method::Direct);
  }
}

TEST_CASE("Lemke's pivots stop at the time limit", "[time-limit][lemke]") {
  const SolverSummary s = check_stops_at_limit(RandomProblem(200), Method::Lemke);
  CHECK(s.pivots >= 1);
  CHECK(s.pivots < 10);  // one check per pivot: it stops within the pivot in hand
  // A non-symmetric A (Lemke takes any square A): A + S with S skew, positive definite still.
  RandomProblem skewed(200, 5);
  for (int k = 0; k + 1 < 200; ++k) {
    skewed.A.coeffRef(k, k + 1) += 0.3;
    skewed.A.coeffRef(k + 1, k) -= 0.3;
  }
  VecX lambda;
  BoxedProblem p = skewed.problem();
  p.symmetric = false;
  const SolverSummary n = solve(p, lambda, limited(Method::Lemke, 1e-9));
  INFO(n.message);
  CHECK(n.termination == Termination::TimeLimit);
  CHECK(lambda.allFinite());
  VecX free_lambda;
  const SolverSummary free = solve(p, free_lambda, limited(Method::Lemke, 600.0));
  INFO(free.message);
  CHECK(free.termination == Termination::Direct);
}

TEST_CASE("direct on cones stops at the time limit", "[time-limit][cone-direct]") {
  // 60 contacts in Coulomb's cones (mu 0.5) on a random W.
  const RandomProblem r(180, 11);
  VecX cmin = VecX::Constant(180, -kInf), cmax = VecX::Constant(180, kInf);
  FrictionContacts cones;
  cones.mu = VecX::Constant(60, 0.5);
  for (int i = 0; i < 60; ++i) {
    cones.normal.push_back(3 * i);
    cmin(3 * i) = 0.0;
  }
  for (const FrictionLaw law : {FrictionLaw::CoulombCone, FrictionLaw::Relaxation}) {
    cones.law = law;
    BoxedProblem p{r.A, r.b, cmin, cmax};
    p.symmetric = true;
    p.cones = &cones;
    VecX lambda;
    const SolverSummary s = solve(p, lambda, limited(Method::Direct, 1e-9));
    INFO(s.message);
    CHECK(s.termination == Termination::TimeLimit);
    CHECK(lambda.allFinite());
  }
}

TEST_CASE("Bullet's solvers run in a child process killed at the time limit",
          "[time-limit][peers]") {
  if (!peer_available(Method::BulletDantzig)) {
    WARN("this build has no Bullet: not tested");
    return;
  }
  // Bullet's Lemke on the bounded path inverts A and pivots on 2c unknowns: far more than the
  // limit of 1 ms at 600 rows (the fork and the dense copy alone take longer).
  const RandomProblem r(600);
  VecX lambda = VecX::Zero(600);
  SolverSummary s;
  const double took =
      seconds_of([&] { s = solve(r.problem(), lambda, limited(Method::BulletLemke, 1e-3)); });
  INFO(s.message << "; took " << took << " s");
  CHECK(s.termination == Termination::TimeLimit);
  CHECK(s.peer_status.rfind("time limit", 0) == 0);
  CHECK(took < 5.0);
  CHECK(lambda.isZero(0.0));  // the guess: the child sent nothing
  // Without a limit it runs in this process, as before, and answers (its own word aside).
  const RandomProblem small(40);
  VecX answer = VecX::Zero(40);
  const SolverSummary in_process =
      solve(small.problem(), answer, limited(Method::BulletDantzig, 0));
  INFO(in_process.message);
  CHECK(in_process.termination != Termination::TimeLimit);
  CHECK(in_process.peer_status.rfind("time limit", 0) != 0);
}
