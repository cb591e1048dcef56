// The solver variants people compare PGS (7.1.1) with: relaxation (PSOR), symmetric sweeps,
// row orders, damped Jacobi, and the matrix-free form (sequential impulses), which must give
// the explicit-A iterates to round-off: the two formulations are one method.
#include <catch2/catch.hpp>
#include <random>
#include <string>
#include <vector>

#include "cbps/cbps.hpp"
#include "cbps/error.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/studies/solver_spec.hpp"

using namespace cbps;

namespace {

/// The system of a built-in scene after `steps` steps (contacts formed, chains loaded).
System system_of(const std::string& name,
                 const std::map<std::string, std::string>& values,
                 int steps) {
  Simulation sim(make_builtin_scene(name, values));
  for (int s = 0; s < steps; ++s) sim.step();
  return sim.build_system();
}

/// The direct path's lambda (6.2) and its v2, the unique reference.
VecX exact_lambda(const System& sys) {
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = solve_direct(sys.problem(), lambda);
  // Verified, as `cbps lcp` verifies (its own 64 u stop may be out of reach on singular A).
  REQUIRE(s.residual <= 1e-9 * std::max(1.0, sys.b.lpNorm<Eigen::Infinity>()));
  return lambda;
}

}  // namespace

TEST_CASE("matrix-free PGS gives explicit-A PGS's iterates to round-off (7.1.1)",
          "[solver][variants][eq7.1.1]") {
  // Contacts with friction (paper bounds and Coulomb), a chain with an end-mass ratio, each in
  // natural and reverse order and with over-relaxation: 40 sweeps from lambda = 0, compared
  // after every sweep.
  struct Case {
    std::string name;
    std::map<std::string, std::string> values;
    int steps;
  };
  const Case c = GENERATE(values<Case>({
      {"chain", {{"n", "40"}, {"mass_ratio", "100"}}, 5},
      {"stack", {{"n", "4"}}, 3},
      {"pyramid", {{"base", "4"}}, 2},
      {"v-corner", {{"mu", "0.5"}}, 2},
  }));
  const RowOrder order = GENERATE(RowOrder::Natural, RowOrder::Reverse);
  const double omega = GENERATE(1.0, 1.3);
  CAPTURE(c.name, to_string(order), omega);
  const System sys = system_of(c.name, c.values, c.steps);
  REQUIRE(sys.rows() > 0);
  std::mt19937_64 rng(0);
  std::vector<int> rows;
  sweep_order(order, sys.rows(), rng, rows);
  const MatrixFreePgs matrix_free(sys.J, sys.Minv);
  VecX explicit_lambda = VecX::Zero(sys.rows()), free_lambda = explicit_lambda;
  VecX u = matrix_free.impulse(free_lambda);
  double worst = 0.0;
  for (int sweep = 0; sweep < 40; ++sweep) {
    pgs_sweep(sys.problem(), explicit_lambda, omega, rows);
    matrix_free.sweep(sys.b, sys.cmin, sys.cmax, free_lambda, u, omega, rows);
    const double scale = std::max(1.0, explicit_lambda.lpNorm<Eigen::Infinity>());
    worst = std::max(worst, (explicit_lambda - free_lambda).lpNorm<Eigen::Infinity>() / scale);
  }
  INFO("largest difference over 40 sweeps, relative to max |lambda|: " << worst);
  // Each sweep rounds A lambda two ways: a few ulps per row, carried through 40 sweeps.
  CHECK(worst < 1e-12);
  CHECK((u - matrix_free.impulse(free_lambda)).lpNorm<Eigen::Infinity>() <
        1e-9 * std::max(1.0, u.lpNorm<Eigen::Infinity>()));  // u = W lambda kept
  // The same residual with or without A.
  CHECK(matrix_free.residual(sys.b, sys.cmin, sys.cmax, free_lambda, u) ==
        Approx(natural_map_residual(sys.problem(), free_lambda)).epsilon(1e-8).margin(1e-12));
}

TEST_CASE("every variant converges to the direct path's answer (7.1.1, 6.2)",
          "[solver][variants]") {
  // A hanging chain of 20 links (A definite: lambda unique) and a resting 3-box stack with
  // contacts (4 per face, A singular: v2 unique; frictionless: with the paper's friction rows PGS
  // stalls near 1e-4 N on this system, docs/convergence.md).
  const std::string spec = GENERATE(as<std::string>{},
                                    "pgs",
                                    "psor:1.5",
                                    "psor:0.7",
                                    "sgs",
                                    "sgs:1.2",
                                    "jacobi:0.5",
                                    "pgs:order=reverse",
                                    "pgs:order=random",
                                    "matrix-free",
                                    "matrix-free:order=random",
                                    "block-pgs");
  CAPTURE(spec);
  const SolverSpec s = parse_solver_spec(spec);
  SolverOptions options;
  options.method = s.method;
  options.relaxation = s.relaxation;
  options.order = s.order;
  options.seed = 7;
  options.max_iterations = 20000;
  options.tolerance = 1e-9;
  for (const bool contact : {false, true}) {
    CAPTURE(contact);
    const System sys = contact ? system_of("stack", {{"n", "3"}, {"mu", "0"}}, 3)
                               : system_of("chain", {{"n", "20"}, {"mass_ratio", "5"}}, 10);
    const VecX exact = exact_lambda(sys);
    VecX lambda = VecX::Zero(sys.rows());
    const SolverSummary summary = solve(sys.problem(), lambda, options);
    CAPTURE(summary.message);
    if (s.method == Method::BlockPgs && contact) {
      // Its blocks carry delta = 1e-7 max A_jj: a floor of O(delta lambda) ~ 1e-6 N, not 1e-9.
      CHECK(summary.residual < 1e-5);
    } else {
      CHECK(summary.termination == Termination::ResidualTolerance);
    }
    const VecX v2 = compute_v2(sys.v1, sys.Minv, sys.J, lambda, sys.fext, sys.dt);
    const VecX v2_exact = compute_v2(sys.v1, sys.Minv, sys.J, exact, sys.fext, sys.dt);
    CHECK((v2 - v2_exact).lpNorm<Eigen::Infinity>() < 1e-6);
    if (!contact) CHECK((lambda - exact).lpNorm<Eigen::Infinity>() < 1e-6);
  }
}

TEST_CASE("symmetric Gauss-Seidel is a forward sweep then a backward sweep", "[solver][variants]") {
  const System sys = system_of("pyramid", {{"base", "3"}}, 2);
  std::vector<int> backward(static_cast<std::size_t>(sys.rows()));
  for (int k = 0; k < sys.rows(); ++k) backward[std::size_t(k)] = sys.rows() - 1 - k;
  VecX by_hand = VecX::Zero(sys.rows()), sgs = by_hand;
  SolverOptions options;
  options.max_iterations = 5;
  options.relaxation = 1.2;
  solve_sgs(sys.problem(), sgs, options);
  for (int k = 0; k < 5; ++k) {
    pgs_sweep(sys.problem(), by_hand, 1.2);
    pgs_sweep(sys.problem(), by_hand, 1.2, backward);
  }
  CHECK((sgs - by_hand).lpNorm<Eigen::Infinity>() == 0.0);  // the same operations
}

TEST_CASE("random row order: the seed fixes the iterates, another seed changes them",
          "[solver][variants]") {
  const System sys = system_of("stack", {{"n", "3"}}, 3);
  const auto run = [&](std::uint64_t seed) {
    SolverOptions options;
    options.order = RowOrder::Random;
    options.seed = seed;
    options.max_iterations = 7;
    VecX lambda = VecX::Zero(sys.rows());
    solve_pgs(sys.problem(), lambda, options);
    return lambda;
  };
  CHECK((run(1) - run(1)).lpNorm<Eigen::Infinity>() == 0.0);
  CHECK((run(1) - run(2)).lpNorm<Eigen::Infinity>() > 1e-6);
}

TEST_CASE("damping makes projected Jacobi converge where plain Jacobi diverges",
          "[solver][variants]") {
  // A = (1 − a) I + a 11ᵀ with a = 0.9 (3×3, definite): Jacobi's iteration matrix −a (11ᵀ − I)
  // has the eigenvalue −2a = −1.8, so plain Jacobi diverges; damped by omega its eigenvalues
  // are 1 − omega (1 + 2a) and 1 − omega (1 − a): omega = 0.3 gives 0.16 and 0.97, < 1.
  MatX dense = MatX::Constant(3, 3, 0.9);
  dense.diagonal().setOnes();
  const SpMat A = dense.sparseView();
  const VecX b = VecX::Ones(3);
  const VecX lo = VecX::Constant(3, -kInf), hi = VecX::Constant(3, kInf);
  SolverOptions options;
  options.max_iterations = 2000;
  options.tolerance = 1e-12;
  VecX plain = VecX::Zero(3), damped = VecX::Zero(3);
  options.relaxation = 1.0;
  const SolverSummary p = solve_jacobi(BoxedProblem{A, b, lo, hi}, plain, options);
  options.relaxation = 0.3;
  const SolverSummary d = solve_jacobi(BoxedProblem{A, b, lo, hi}, damped, options);
  CHECK(p.termination != Termination::ResidualTolerance);
  CHECK(d.termination == Termination::ResidualTolerance);
  const VecX exact = dense.ldlt().solve(b);  // 1 / (1 + 2a) each
  CHECK((damped - exact).lpNorm<Eigen::Infinity>() < 1e-11);
}

TEST_CASE("solver specs: names, relaxation factors, orders and warm starts", "[solver][cli]") {
  const SolverSpec psor = parse_solver_spec("psor:1.3");
  CHECK(psor.method == Method::Pgs);
  CHECK(psor.relaxation == 1.3);
  const SolverSpec random = parse_solver_spec("pgs:order=random:warm=off");
  CHECK(random.order == RowOrder::Random);
  CHECK_FALSE(random.warm_start);
  CHECK(parse_solver_spec("jacobi:1").relaxation == 1.0);
  CHECK(parse_solver_spec("matrix-free:order=reverse").order == RowOrder::Reverse);
  const auto list = parse_solver_list("pgs,psor:1.3,direct");
  REQUIRE(list.size() == 3);
  CHECK(list[2].method == Method::Direct);
  const auto error_of = [](const std::string& text) {
    try {
      parse_solver_spec(text, "--solver");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error_of("cg").find("--solver 'cg': unknown solver") != std::string::npos);
  CHECK(error_of("psor").find("psor needs its factor") != std::string::npos);
  CHECK(error_of("psor:2").find("in (0, 2)") != std::string::npos);
  CHECK(error_of("jacobi:1.5").find("in (0, 1]") != std::string::npos);
  CHECK(error_of("pgs:1.3").find("takes no relaxation factor") != std::string::npos);
  CHECK(error_of("sgs:order=random").find("order= applies to") != std::string::npos);
  CHECK(error_of("pgs:order=spiral").find("valid: natural, reverse, random") != std::string::npos);
  CHECK(error_of("pgs:warm=maybe").find("valid: on, off") != std::string::npos);
  CHECK(error_of("pgs:colour=red").find("unknown option 'colour'") != std::string::npos);
  CHECK_THROWS_AS(parse_solver_list("pgs,,direct"), InputError);
}
