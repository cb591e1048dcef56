// The exact path's interior-point method (solve_direct with options.direct.interior_from_rows = 0,
// so that small problems take it too): its answers checked against the optimality conditions of
// the QP min ½ λᵀAλ − bᵀλ over the box (6.2) row by row, against Lemke's method and the
// active-set path (independent methods), body space (M + Jᵀ D⁻¹ J) against row space (A + D),
// with CFM, fixed rows, and bad input.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "../src/solvers/exact/newton_system.hpp"
#include "cbps/solvers/exact/active_set.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/exact/interior_point.hpp"
#include "cbps/solvers/exact/lemke.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::construct;
using test::Constructed;

namespace {

/// The natural-map residual the interior path must reach on these problems, relative to
/// scale_of(problem): 1e-10. It stops at its rounding floor 64 u (‖A‖∞ ‖λ‖∞ + ‖b‖∞)
/// (direct.hpp), which is 2.6e-12 to 9.8e-12 · scale on the pyramids and stacks here (measured:
/// 2.7e-11 N on the 5-column stack, 9.6e-11 N on the base-10 pyramid, scale ≈ 10), so 1e-10
/// leaves a factor of 10 above the largest floor while an answer visibly off fails. The same
/// number bounds the KKT conditions row by row (λ in N and w in m/s² weighed alike, as the
/// natural map weighs them).
constexpr double kResidual = 1e-10;

/// Two exact answers of a degenerate (A singular) problem: w = A λ − b, the force Jᵀ λ and v2 are
/// unique, λ is not. Two answers each with residual r agree in them only to about r / σ₊ (σ₊ the
/// smallest nonzero eigenvalue of A), and where the active set is degenerate (a contact with
/// λ = 0 and w = 0 at once) only to about √(r ‖A‖ ‖λ‖): from (λ₁ − λ₂)ᵀ A (λ₁ − λ₂) =
/// (λ₁ − λ₂)ᵀ (w₁ − w₂), which is 0 at exact answers and O(r ‖λ‖) at inexact ones. With r at the
/// rounding floor (≈ 1e-11 · scale) that is up to ≈ 3e-6 · scale in the worst case; the interior
/// and active-set paths were measured 1e-8 relative apart on the base-10 pyramid (the issue), and
/// here at most 8.2e-11 m/s² apart in w (body against row space on the base-6 pyramid) and
/// 1.8e-13 · scale from Lemke. 1e-7 · scale: ten times the largest seen on a real scene, far
/// below anything a step would show.
constexpr double kDegenerateAgreement = 1e-7;

double objective(const SpMat& A, const VecX& b, const VecX& x) {
  return 0.5 * x.dot(A * x) - b.dot(x);  // ½ λᵀ A λ − bᵀ λ (6.2)
}

/// The options that send every problem with a bounded row to the interior-point method.
SolverOptions interior() {
  SolverOptions options;
  options.method = Method::Direct;
  options.tolerance = 0.0;  // to the rounding floor
  options.direct.interior_from_rows = 0;
  return options;
}

/// The interior path on `problem`, which must end Direct in body space (body) or row space, its
/// residual within kResidual · scale.
VecX solve_interior_in(const BoxedProblem& problem, bool body, double scale) {
  VecX lambda;
  const SolverSummary s = solve_direct(problem, lambda, interior());
  CAPTURE(body, s.message);
  CHECK(s.termination == Termination::Direct);
  CHECK(s.space == (body ? "body" : "row"));
  CHECK(natural_map_residual(problem, lambda) <= kResidual * scale);
  return lambda;
}

/// A built-in contact scene stepped `steps` times by PGS (the scene's own settings), and the
/// system of the state reached. Kept for the whole run: several test cases take the same step,
/// and stepping the pyramids is most of this file's time.
const System& stepped(const std::string& name,
                      const std::map<std::string, std::string>& values,
                      int steps) {
  static std::map<std::string, System> cache;
  std::string key = name + " @" + std::to_string(steps);
  for (const auto& [parameter, value] : values) key += " " + parameter + "=" + value;
  auto it = cache.find(key);
  if (it == cache.end()) {
    Simulation sim(test::contact_scene(name, values, "pgs"));
    for (int s = 0; s < steps; ++s) sim.step();
    it = cache.emplace(key, sim.build_system()).first;
  }
  return it->second;
}

/// The worst violation of the optimality conditions of 6.2, row by row, with w = A λ − b
/// computed here: λ must lie in the box (exactly: the crossover puts bound rows on their
/// bounds); a row within `tol` (N) of cmin needs w ≥ −tol, within tol of cmax w ≤ tol, and a
/// row strictly inside |w| ≤ tol (m/s², the same number: the natural map weighs N and m/s²
/// alike). A row within tol of both bounds (fixed, or a narrow box) has w free.
struct Kkt {
  double outside_box = 0.0;  ///< max distance of λ outside [cmin, cmax], N
  double w_violation = 0.0;  ///< max violation of the sign or zero condition on w, m/s²
  Eigen::Index worst_row = -1;
};

Kkt kkt(const BoxedProblem& p, const VecX& lambda, double tol) {
  const VecX w = p.A * lambda - p.b;
  Kkt k;
  for (Eigen::Index i = 0; i < lambda.size(); ++i) {
    k.outside_box = std::max({k.outside_box, p.cmin(i) - lambda(i), lambda(i) - p.cmax(i), 0.0});
    const bool at_lower = lambda(i) - p.cmin(i) <= tol;
    const bool at_upper = p.cmax(i) - lambda(i) <= tol;
    double v = 0.0;
    if (at_lower && !at_upper) v = std::max(-w(i), 0.0);
    if (at_upper && !at_lower) v = std::max(w(i), 0.0);
    if (!at_lower && !at_upper) v = std::abs(w(i));
    if (v > k.w_violation) {
      k.w_violation = v;
      k.worst_row = i;
    }
  }
  return k;
}

/// No feasible point near or far has a lower objective (the QP is convex: local = global).
/// Returns the largest decrease found (≤ 0 at a minimiser, up to rounding).
double largest_decrease(const BoxedProblem& p, const VecX& lambda, std::mt19937& rng) {
  std::normal_distribution<double> n01;
  const double f = objective(p.A, p.b, lambda);
  double decrease = -std::numeric_limits<double>::infinity();
  for (const double step : {1e-6, 1e-4, 1e-2, 1.0}) {
    for (int sample = 0; sample < 20; ++sample) {
      VecX mu(lambda.size());
      for (Eigen::Index i = 0; i < lambda.size(); ++i)
        mu(i) = clamp(lambda(i) + step * n01(rng), p.cmin(i), p.cmax(i));
      decrease = std::max(decrease, f - objective(p.A, p.b, mu));
    }
  }
  return decrease;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// 1. Pyramids and stacks against the optimality conditions.

TEST_CASE("interior path: pyramids and a multi-column stack meet the QP optimality conditions",
          "[direct][interior]") {
  struct Case {
    std::string name;
    std::map<std::string, std::string> values;
    int steps;
    bool body_crossover;  ///< one island above 500 rows: the crossover runs in body space
  };
  const Case c = GENERATE(values<Case>({
      {"pyramid", {{"base", "6"}}, 30, false},
      {"pyramid", {{"base", "10"}}, 30, true},
      {"stack", {{"n", "10"}, {"columns", "5"}}, 1, false},
  }));
  const System& sys = stepped(c.name, c.values, c.steps);
  const BoxedProblem problem = sys.problem();
  const double scale = scale_of(problem);
  INFO(c.name << " after " << c.steps << " steps: " << sys.rows() << " rows, scale " << scale);
  REQUIRE(sys.rows() > 0);

  VecX lambda;
  const SolverSummary s = solve_direct(problem, lambda, interior());
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  CHECK(s.space == "body");
  CHECK(s.iterations > 0);  // the interior point ran, not the active-set path
  // The large island's crossover keeps one body-space factor and updates it as rows join or
  // leave the free set (newton_system.cpp); the small ones factor A(F, F).
  const bool in_body = s.message.find("crossover (in body space)") != std::string::npos;
  CHECK(in_body == c.body_crossover);
  if (c.body_crossover) CHECK(s.updates > 0);
  const double tol = kResidual * scale;
  INFO("residual " << s.residual << " N, rounding floor " << residual_floor(problem, lambda)
                   << " N, bound " << tol << " N");
  CHECK(natural_map_residual(problem, lambda) <= tol);
  CHECK(s.residual <= tol);

  const Kkt k = kkt(problem, lambda, tol);
  INFO("worst row " << k.worst_row << ": w violation " << k.w_violation << ", outside the box "
                    << k.outside_box);
  CHECK(k.outside_box == 0.0);
  CHECK(k.w_violation <= tol);

  // The objective: no random feasible point is lower. Slack, as in test_direct.cpp: 1e-9 of
  // |f| (1.0e3 to 2.8e3 here), far above what the residual allows a perturbation Δ to gain
  // (about kResidual · scale · ‖Δ‖₁, ≤ 1e-9 · ‖Δ‖∞ · rows) and far below what a wrong row costs.
  std::mt19937 rng(21);
  const double f = objective(sys.A, sys.b, lambda);
  const double decrease = largest_decrease(problem, lambda, rng);
  INFO("objective " << f << ", largest decrease found " << decrease);
  CHECK(decrease <= 1e-9 * std::max(1.0, std::abs(f)));
}

TEST_CASE(
    "bulk crossover (the distributed exact path's) from the interior point's partition meets the "
    "QP optimality conditions and the pivoting crossover's objective",
    "[direct][interior][bulk]") {
  struct Case {
    std::string name;
    std::map<std::string, std::string> values;
    int steps;
  };
  const Case c = GENERATE(values<Case>({
      {"pyramid", {{"base", "10"}}, 30},
      {"pyramid", {{"base", "14"}}, 20},
      {"stack", {{"n", "10"}, {"columns", "5"}}, 1},
  }));
  const System& sys = stepped(c.name, c.values, c.steps);
  const BoxedProblem problem = sys.problem();
  const double scale = scale_of(problem);
  INFO(c.name << " after " << c.steps << " steps: " << sys.rows() << " rows, scale " << scale);
  const std::shared_ptr<NewtonSystem> newton = make_body_space(problem);
  REQUIRE(newton != nullptr);
  const VecX diagonal = problem.A.diagonal();
  const InteriorRows rows{
      problem.b, problem.cmin, problem.cmax, diagonal, scale, max_abs_row_sum(problem.A)};
  const SolverOptions options = interior();
  VecX lambda;
  const InteriorOutcome start = run_interior_point(rows, *newton, RowReduction(), options, lambda);
  CHECK(start.iterations > 0);
  CHECK_FALSE(start.solved);  // the tolerance needs a crossover here
  const CrossoverOutcome x =
      bulk_crossover(rows, *newton, RowReduction(), options, start.place, lambda);
  INFO(x.rounds << " proximal steps, " << x.steps << " solves, " << x.moved
                << " rows moved, residual " << x.residual << " N");
  CHECK(x.solved);
  CHECK(x.steps >= x.rounds);
  const double tol = kResidual * scale;
  CHECK(natural_map_residual(problem, lambda) <= tol);
  CHECK(x.residual == Approx(natural_map_residual(problem, lambda)).margin(1e-3 * tol));
  const Kkt k = kkt(problem, lambda, tol);
  INFO("worst row " << k.worst_row << ": w violation " << k.w_violation << ", outside the box "
                    << k.outside_box);
  CHECK(k.outside_box == 0.0);
  CHECK(k.w_violation <= tol);
  // The same minimum as the serial path (its pivoting crossover, an independent finish): λ may
  // differ where A is singular, the objective may not (slack as in the test above).
  VecX serial;
  REQUIRE(solve_direct(problem, serial, options).termination == Termination::Direct);
  const double f = objective(sys.A, sys.b, lambda);
  const double f_serial = objective(sys.A, sys.b, serial);
  INFO("objective " << f << ", serial " << f_serial);
  CHECK(std::abs(f - f_serial) <= 1e-9 * std::max(1.0, std::abs(f)));
  std::mt19937 rng(22);
  CHECK(largest_decrease(problem, lambda, rng) <= 1e-9 * std::max(1.0, std::abs(f)));
}

// ---------------------------------------------------------------------------------------------
// 2. Against Lemke's method on small problems.

namespace {

/// max |x|, 0 for an empty vector.
double inf_norm(const VecX& x) { return x.size() > 0 ? x.lpNorm<Eigen::Infinity>() : 0.0; }

/// A constructed problem (fixture.hpp) with its J padded to whole bodies (6 columns each) and
/// Minv = I, so that A = J Minv Jᵀ and the problem can be solved in body space.
struct WithFactors {
  SpMatRow J;
  SpMat Minv;
  explicit WithFactors(const Constructed& p) {
    const Eigen::Index d = p.J.cols();
    const Eigen::Index columns = 6 * ((d + 5) / 6);
    MatX padded = MatX::Zero(p.J.rows(), columns);
    padded.leftCols(d) = p.J;
    J = padded.sparseView();
    Minv = MatX::Identity(columns, columns).sparseView();
  }
  BoxedProblem problem(const Constructed& p) const {
    BoxedProblem boxed{p.A, p.b, p.lo, p.hi};
    boxed.J = &J;
    boxed.Minv = &Minv;
    return boxed;
  }
};

/// The rounding of w = A λ − b, N: 32 ε (‖A‖∞ ‖λ‖∞ + ‖b‖∞), the floor below which no residual
/// can be told from 0 (direct.hpp's residual_floor is 64 u = 32 ε of the same).
double rounding(const SpMat& A, const VecX& b, const VecX& lambda) {
  double row_sum = 0.0;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    double sum = 0.0;
    for (SpMat::InnerIterator it(A, j); it; ++it) sum += std::abs(it.value());
    row_sum = std::max(row_sum, sum);
  }
  return 32.0 * std::numeric_limits<double>::epsilon() * (row_sum * inf_norm(lambda) + inf_norm(b));
}

/// How far apart two answers λ₁, λ₂ of a problem with A positive definite can be, given their
/// natural-map residuals r₁, r₂ (∞-norm): the natural map's error bound ‖λ − λ*‖₂ ≤ (L + 1)/μ ‖r‖₂,
/// L and μ the largest and smallest eigenvalues of A (from the projection's variational
/// inequality and A's monotonicity, μ ‖λ − λ*‖² ≤ (L + 1) ‖r‖ ‖λ − λ*‖), with ‖r‖₂ ≤ √c ‖r‖∞
/// and each residual at least the rounding of w. Computed from A's spectrum, not chosen.
double definite_bound(const SpMat& A, double r1, double r2) {
  const VecX ev =
      Eigen::SelfAdjointEigenSolver<MatX>(MatX(A), Eigen::EigenvaluesOnly).eigenvalues();
  const double mu = ev.minCoeff();
  const double L = ev.maxCoeff();
  REQUIRE(mu > 0.0);
  return (L + 1.0) / mu * std::sqrt(double(A.rows())) * (r1 + r2);
}

/// True when some row is bounded and not fixed: the interior path takes the problem.
bool has_bounded_row(const VecX& lo, const VecX& hi) {
  for (Eigen::Index k = 0; k < lo.size(); ++k)
    if (lo(k) != hi(k) && (std::isfinite(lo(k)) || std::isfinite(hi(k)))) return true;
  return false;
}

}  // namespace

TEST_CASE("interior path: constructed problems agree with boxed Lemke in row and body space",
          "[direct][interior][lcp]") {
  std::mt19937 rng(22);
  int interior_solves = 0;
  for (int trial = 0; trial < 80; ++trial) {
    const int k = 1 + trial % 16;
    const bool definite = trial % 2 == 0;
    const int d = definite ? k + 3 : std::max(1, k / 2);  // d < k: A singular, rank d
    const Constructed p = construct(k, d, rng);
    const WithFactors factors(p);
    const double scale = test::scale_of(p.A, p.b);
    const LcpResult lemke = solve_boxed_lemke(MatX(p.A), -p.b, p.lo, p.hi);
    CAPTURE(trial, k, d, lemke.message);
    REQUIRE(lemke.solved());
    const VecX w_lemke = p.A * lemke.z - p.b;
    // The interior point runs when some row is bounded and λ = 0 clamped into the box does not
    // already solve the problem (direct.hpp, 1.: no bounded row goes to the active-set path, a
    // guess that solves it is returned as it is).
    VecX guess(k);
    for (int i = 0; i < k; ++i) guess(i) = clamp(0.0, p.lo(i), p.hi(i));
    const bool interior_runs = has_bounded_row(p.lo, p.hi) &&
                               natural_map_residual(BoxedProblem{p.A, p.b, p.lo, p.hi}, guess) > 0;
    for (const bool body : {false, true}) {
      const BoxedProblem problem = body ? factors.problem(p) : BoxedProblem{p.A, p.b, p.lo, p.hi};
      VecX lambda;
      const SolverSummary s = solve_direct(problem, lambda, interior());
      CAPTURE(body, s.message);
      REQUIRE(s.termination == Termination::Direct);
      CHECK(s.space == (interior_runs ? (body ? "body" : "row") : ""));
      interior_solves += interior_runs ? 1 : 0;
      CHECK(natural_map_residual(problem, lambda) <= kResidual * scale);
      // w is unique (6.2); on singular A to kDegenerateAgreement (two answers of a degenerate
      // problem), on definite A through λ below.
      const VecX w = p.A * lambda - p.b;
      CHECK(inf_norm(w - w_lemke) <= kDegenerateAgreement * scale);
      if (definite) {
        const double r_direct =
            std::max(natural_map_residual(problem, lambda), rounding(p.A, p.b, lambda));
        const double r_lemke = std::max(lemke.residual, rounding(p.A, p.b, lemke.z));
        const double bound = definite_bound(p.A, r_direct, r_lemke);
        CAPTURE(bound);
        CHECK(inf_norm(lambda - lemke.z) <= bound);
      }
    }
  }
  CHECK(interior_solves > 100);  // most of them reached the interior-point method
}

TEST_CASE("interior path: small contact scenes agree with boxed Lemke in row and body space",
          "[direct][interior][lcp]") {
  struct Case {
    std::string name;
    std::map<std::string, std::string> values;
    int steps;
    bool definite;
  };
  // One box on the ground (12 rows on 6 degrees of freedom: singular), two boxes (24 rows), and
  // the v-corner's sphere in a V (2 contact rows: definite).
  const Case c = GENERATE(values<Case>({
      {"stack", {{"n", "1"}}, 10, false},
      {"stack", {{"n", "2"}}, 10, false},
      {"v-corner", {}, 5, true},
  }));
  const System& sys = stepped(c.name, c.values, c.steps);
  const double scale = scale_of(sys.problem());
  INFO(c.name << " after " << c.steps << " steps: " << sys.rows() << " rows");
  REQUIRE(sys.rows() > 0);
  const LcpResult lemke = solve_boxed_lemke(MatX(sys.A), -sys.b, sys.cmin, sys.cmax);
  INFO(lemke.message);
  REQUIRE(lemke.solved());
  const VecX w_lemke = sys.A * lemke.z - sys.b;
  for (const bool body : {false, true}) {
    const BoxedProblem problem =
        body ? sys.problem() : BoxedProblem{sys.A, sys.b, sys.cmin, sys.cmax};
    const VecX lambda = solve_interior_in(problem, body, scale);
    CHECK(inf_norm(sys.A * lambda - sys.b - w_lemke) <= kDegenerateAgreement * scale);
    if (c.definite) {
      const double bound = definite_bound(
          sys.A,
          std::max(natural_map_residual(problem, lambda), rounding(sys.A, sys.b, lambda)),
          std::max(lemke.residual, rounding(sys.A, sys.b, lemke.z)));
      CAPTURE(bound);
      CHECK(inf_norm(lambda - lemke.z) <= bound);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 3. Against the active-set path (solve_active_set), where that succeeds.

namespace {

/// The 20-link chain of test_every_solver_agrees (A definite, 20 distance rows) with every row
/// boxed to [−c, c], c half the largest unbounded |λ|: joints that give when pulled harder than c.
/// Some rows sit at a bound, so the interior path takes it, and λ is unique.
struct BoundedChain {
  System sys = test::system_of("chain", {{"n", "20"}, {"mass_ratio", "10"}}, 10);
  VecX lo, hi;
  BoundedChain() {
    VecX free;
    solve_cholesky(sys.A, sys.b, free);
    const double c = 0.5 * inf_norm(free);
    lo = VecX::Constant(sys.rows(), -c);
    hi = VecX::Constant(sys.rows(), c);
  }
  BoxedProblem problem() const {  // body space: J and Minv come along
    BoxedProblem p{sys.A, sys.b, lo, hi};
    p.J = &sys.J;
    p.Minv = &sys.Minv;
    return p;
  }
  BoxedProblem rows() const { return BoxedProblem{sys.A, sys.b, lo, hi}; }
};

/// A built-in scene after some steps.
struct SceneStep {
  std::string name;
  std::map<std::string, std::string> values;
  int steps;
};
/// The 10-box stack and the base-6 pyramid after 30 steps: small enough for the active-set path.
/// Stepped with contact persistence off (rows matched by feature id), the states the numbers
/// below were measured on.
const std::initializer_list<SceneStep> kSmallContactSteps = {
    {"stack", {{"n", "10"}, {"persistence", "0"}}, 30},
    {"pyramid", {{"base", "6"}, {"persistence", "0"}}, 30},
};

/// The force Jᵀ λ on the bodies, N and N m: unique where λ is not (A = J Minv Jᵀ, Minv definite).
VecX force(const System& sys, const VecX& lambda) { return sys.J.transpose() * lambda; }

}  // namespace

TEST_CASE("interior path: contact scenes agree with the active-set path on w, Jᵀλ and v2",
          "[direct][interior]") {
  const SceneStep c = GENERATE(values<SceneStep>(kSmallContactSteps));
  const System& sys = stepped(c.name, c.values, c.steps);
  const BoxedProblem problem = sys.problem();
  const double scale = scale_of(problem);
  INFO(c.name << " after " << c.steps << " steps: " << sys.rows() << " rows, scale " << scale);

  VecX active;
  const SolverSummary sa = solve_active_set(problem, active);
  INFO("active set: " << sa.message);
  REQUIRE(sa.termination == Termination::Direct);
  VecX lambda;
  const SolverSummary s = solve_direct(problem, lambda, interior());
  INFO("interior: " << s.message);
  CHECK(s.termination == Termination::Direct);
  CHECK(s.space == "body");

  const double dw = inf_norm((sys.A * lambda - sys.b) - (sys.A * active - sys.b));
  const VecX f = force(sys, active);
  const double df = inf_norm(force(sys, lambda) - f);
  const double dv = inf_norm(compute_v2(sys, lambda) - compute_v2(sys, active));
  INFO("|Δw| " << dw << " m/s², |ΔJᵀλ| " << df << " N (|Jᵀλ| " << inf_norm(f) << "), |Δv2| " << dv
               << " m/s");
  CHECK(dw <= kDegenerateAgreement * scale);
  // Jᵀλ is as unique as w (A Δλ = 0 ⇔ Jᵀ Δλ = 0, Minv definite): the same relative bound on
  // its own size (measured: at most 1.4e-10 N of |Jᵀλ| ≈ 10 N in this file).
  CHECK(df <= kDegenerateAgreement * std::max(1.0, inf_norm(f)));
  // v2 = v1 + Δt Minv (Jᵀλ + fext) (12.3.1): Δv2 = Δt Minv ΔJᵀλ.
  const double minv = MatX(sys.Minv).cwiseAbs().rowwise().sum().maxCoeff();  // ‖Minv‖∞
  CHECK(dv <= sys.dt * minv * kDegenerateAgreement * std::max(1.0, inf_norm(f)));
}

namespace {

/// Both exact paths on `problem` (the interior path in body space), both required to succeed;
/// returns {interior λ, active-set λ}.
std::pair<VecX, VecX> solve_both(const BoxedProblem& problem) {
  VecX active, lambda;
  const SolverSummary sa = solve_active_set(problem, active);
  const SolverSummary s = solve_direct(problem, lambda, interior());
  INFO("active set: " << sa.message << "\ninterior: " << s.message);
  REQUIRE(sa.termination == Termination::Direct);
  CHECK(s.termination == Termination::Direct);
  CHECK(s.space == "body");
  return {lambda, active};
}

/// |λ₁ − λ₂| within definite_bound of A's spectrum, each residual at least its rounding.
void check_definite_agreement(const BoxedProblem& problem, const VecX& l1, const VecX& l2) {
  const auto r = [&](const VecX& l) {
    return std::max(natural_map_residual(problem, l), rounding(problem.A, problem.b, l));
  };
  const double bound = definite_bound(problem.A, r(l1), r(l2));
  INFO("|Δλ| " << inf_norm(l1 - l2) << " N, bound " << bound << " N");
  CHECK(inf_norm(l1 - l2) <= bound);
}

}  // namespace

TEST_CASE("interior path: where A is definite lambda equals the active-set path's",
          "[direct][interior]") {
  SECTION("the 20-link chain with boxed joints") {
    const BoundedChain chain;
    const BoxedProblem problem = chain.problem();
    const auto [lambda, active] = solve_both(problem);
    int at_bound = 0;
    for (Eigen::Index k = 0; k < lambda.size(); ++k)
      at_bound += lambda(k) == chain.lo(k) || lambda(k) == chain.hi(k);
    CHECK(at_bound > 0);  // the boxes bind: not the unbounded solve
    check_definite_agreement(problem, lambda, active);
  }
  SECTION("the v-corner's sphere") {
    const System& sys = stepped("v-corner", {}, 5);
    const BoxedProblem problem = sys.problem();
    const auto [lambda, active] = solve_both(problem);
    check_definite_agreement(problem, lambda, active);
  }
}

// ---------------------------------------------------------------------------------------------
// 4. Body space and row space: the same answer.

TEST_CASE("interior path: body space and row space give the same answer on the same step",
          "[direct][interior]") {
  SECTION("a pyramid and a stack: w, Jᵀλ and v2") {
    const SceneStep c = GENERATE(values<SceneStep>(kSmallContactSteps));
    const System& sys = stepped(c.name, c.values, c.steps);
    const double scale = scale_of(sys.problem());
    INFO(c.name << " after " << c.steps << " steps: " << sys.rows() << " rows");
    VecX body, row;
    const SolverSummary sb = solve_direct(sys.problem(), body, interior());
    const SolverSummary sr =
        solve_direct(BoxedProblem{sys.A, sys.b, sys.cmin, sys.cmax}, row, interior());
    INFO("body: " << sb.message << "\nrow: " << sr.message);
    CHECK(sb.termination == Termination::Direct);
    CHECK(sr.termination == Termination::Direct);
    CHECK(sb.space == "body");
    CHECK(sr.space == "row");
    const VecX f = force(sys, row);
    const double dw = inf_norm(sys.A * (body - row));
    const double df = inf_norm(force(sys, body) - f);
    const double dv = inf_norm(compute_v2(sys, body) - compute_v2(sys, row));
    INFO("|Δw| " << dw << " m/s², |ΔJᵀλ| " << df << " N, |Δv2| " << dv << " m/s");
    // Two exact answers of a degenerate problem: kDegenerateAgreement, as against the active set.
    CHECK(dw <= kDegenerateAgreement * scale);
    CHECK(df <= kDegenerateAgreement * std::max(1.0, inf_norm(f)));
    const double minv = MatX(sys.Minv).cwiseAbs().rowwise().sum().maxCoeff();
    CHECK(dv <= sys.dt * minv * kDegenerateAgreement * std::max(1.0, inf_norm(f)));
  }
  SECTION("the chain with boxed joints: lambda (A definite)") {
    const BoundedChain chain;
    VecX body, row;
    const SolverSummary sb = solve_direct(chain.problem(), body, interior());
    const SolverSummary sr = solve_direct(chain.rows(), row, interior());
    INFO("body: " << sb.message << "\nrow: " << sr.message);
    CHECK(sb.termination == Termination::Direct);
    CHECK(sr.termination == Termination::Direct);
    CHECK(sb.space == "body");
    CHECK(sr.space == "row");
    const SpMat& A = chain.sys.A;
    const VecX& b = chain.sys.b;
    const double bound =
        definite_bound(A,
                       std::max(natural_map_residual(chain.rows(), body), rounding(A, b, body)),
                       std::max(natural_map_residual(chain.rows(), row), rounding(A, b, row)));
    INFO("|Δλ| " << inf_norm(body - row) << " N, bound " << bound << " N");
    CHECK(inf_norm(body - row) <= bound);
  }
}

TEST_CASE("interior path: a warm start near the answer finishes by the crossover alone",
          "[direct][interior]") {
  // A running scene's guess: the exact answer of the step before, row by row through the row
  // ids (as Simulation's warm start of 7 maps it; rows new this step start from 0), the scene
  // stepped by the direct path (the warm path's use: a PGS-stepped state, settling with PGS's
  // errors, may need more than its 100 pivoting rounds; then the interior point runs). The
  // crossover from it must end Direct without the interior point and give the cold answer's
  // w and Jᵀλ (unique where λ is not).
  const SceneStep c = GENERATE(values<SceneStep>(kSmallContactSteps));
  Simulation sim(test::contact_scene(c.name, c.values, "direct"));
  for (int s = 1; s < c.steps; ++s) sim.step();
  const System before = sim.build_system();
  sim.step();
  const System sys = sim.build_system();
  const BoxedProblem problem = sys.problem();
  const double scale = scale_of(problem);
  VecX last;
  REQUIRE(solve_direct(before.problem(), last, interior()).termination == Termination::Direct);
  std::map<std::uint64_t, double> last_by_id;
  for (std::size_t k = 0; k < before.ids.size(); ++k)
    last_by_id[before.ids[k]] = last(Eigen::Index(k));
  VecX warm = VecX::Zero(sys.rows());
  long continued = 0;
  for (std::size_t k = 0; k < sys.ids.size(); ++k) {
    const auto it = last_by_id.find(sys.ids[k]);
    if (it == last_by_id.end()) continue;
    warm(Eigen::Index(k)) = it->second;
    ++continued;
  }
  REQUIRE(continued > sys.rows() / 2);
  VecX cold;
  const SolverSummary sc = solve_direct(problem, cold, interior());
  REQUIRE(sc.termination == Termination::Direct);
  const SolverSummary sw = solve_direct(problem, warm, interior());
  INFO(c.name << ": cold " << sc.message << "\nwarm " << sw.message);
  CHECK(sw.termination == Termination::Direct);
  CHECK(sw.message.rfind("direct (warm", 0) == 0);
  CHECK(sw.iterations == 0);  // no interior iteration
  CHECK(sw.space == "body");
  CHECK(natural_map_residual(problem, warm) <= kResidual * scale);
  CHECK(inf_norm(sys.A * (warm - cold)) <= kDegenerateAgreement * scale);
  const VecX f = force(sys, cold);
  CHECK(inf_norm(force(sys, warm) - f) <= kDegenerateAgreement * std::max(1.0, inf_norm(f)));
}

// ---------------------------------------------------------------------------------------------
// 5. Constraint-force mixing.

TEST_CASE("interior path with CFM: the answer solves the problem of A + eps E, in body space",
          "[direct][interior][cfm]") {
  const System& sys = stepped("pyramid", {{"base", "6"}}, 30);
  const BoxedProblem problem = sys.problem();
  const double scale = scale_of(problem);
  SolverOptions options = interior();
  options.cfm = 1e-6;  // kg⁻¹
  VecX lambda;
  const SolverSummary s = solve(problem, lambda, options);
  INFO(sys.rows() << " rows: " << s.message);
  CHECK(s.termination == Termination::Direct);
  CHECK(s.space == "body");
  CHECK(s.iterations > 0);
  const double with = natural_map_residual(problem, lambda, options.cfm);
  const double without = natural_map_residual(problem, lambda);
  INFO("residual of A + eps E " << with << " N, of A " << without << " N");
  CHECK(with <= kResidual * scale);
}

// ---------------------------------------------------------------------------------------------
// 6. Bad input: the solve ends, and says so.

namespace {

/// Six degrees of freedom, Minv = I, and rows of unit vectors of it: A = J Jᵀ.
struct UnitRows {
  SpMatRow J;
  SpMat A, Minv;
  VecX b, lo, hi;
  /// rows[k] is the degree of freedom row k pulls on.
  UnitRows(const std::vector<int>& rows, const VecX& b_, const VecX& lo_, const VecX& hi_)
      : b(b_), lo(lo_), hi(hi_) {
    MatX dense = MatX::Zero(Eigen::Index(rows.size()), 6);
    for (std::size_t k = 0; k < rows.size(); ++k) dense(Eigen::Index(k), rows[k]) = 1.0;
    J = dense.sparseView();
    const MatX a = dense * dense.transpose();
    A = a.sparseView();
    Minv = MatX::Identity(6, 6).sparseView();
  }
  BoxedProblem problem(bool body) const {
    BoxedProblem p{A, b, lo, hi};
    if (body) {
      p.J = &J;
      p.Minv = &Minv;
    }
    return p;
  }
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

TEST_CASE("interior path: NaN in b ends the solve with NonFinite", "[direct][interior]") {
  const bool body = GENERATE(false, true);
  const VecX b = (VecX(3) << 1.0, std::nan(""), 0.5).finished();
  const UnitRows u({0, 1, 2}, b, VecX::Zero(3), VecX::Constant(3, kInf));
  VecX lambda;
  const SolverSummary s = solve_direct(u.problem(body), lambda, interior());
  INFO(s.message);
  CHECK(s.termination == Termination::NonFinite);
  CHECK_FALSE(s.ok());
}

TEST_CASE("interior path: inconsistent equality rows end NotConverged within a second",
          "[direct][interior]") {
  const bool body = GENERATE(false, true);
  // Rows 0 and 1 are the same constraint (degree of freedom 0) asking for w = 0 at λ₀ + λ₁ = 1
  // and at λ₀ + λ₁ = 2: no λ solves both, and the smallest natural-map residual is 0.5 (w₀ = −w₁
  // = ±0.5). Rows 2 to 4 are bounded: a contact pushing (λ = 0.5), a friction row at its bound
  // (λ = 1, w = −2) and a contact separating (λ = 0, w = 1).
  const VecX b = (VecX(5) << 1.0, 2.0, 0.5, 3.0, -1.0).finished();
  const VecX lo = (VecX(5) << -kInf, -kInf, 0.0, -1.0, 0.0).finished();
  const VecX hi = (VecX(5) << kInf, kInf, kInf, 1.0, kInf).finished();
  const UnitRows u({0, 0, 1, 2, 3}, b, lo, hi);
  VecX lambda;
  const auto start = std::chrono::steady_clock::now();
  const SolverSummary s = solve_direct(u.problem(body), lambda, interior());
  const double elapsed = seconds_since(start);
  INFO(s.message << " in " << elapsed << " s");
  CHECK(s.termination == Termination::NotConverged);
  CHECK(std::isfinite(s.residual));
  CHECK(s.residual >= 0.49);
  CHECK(lambda.allFinite());
  CHECK(elapsed < 1.0);
  // The consistent rows are still solved.
  CHECK(lambda(2) == Approx(0.5).margin(1e-9));
  CHECK(lambda(3) == Approx(1.0).margin(1e-9));
  CHECK(lambda(4) == Approx(0.0).margin(1e-9));
}

TEST_CASE("an infeasible box (cmin > cmax) is not reported solved by the direct path",
          "[direct][interior]") {
  const bool body = GENERATE(false, true);
  // The interior point, and the default (500 rows: this problem goes to the active-set path).
  const int interior_from_rows = GENERATE(0, SolverOptions{}.direct.interior_from_rows);
  // b ≠ 0: the interior point runs; b = 0: λ = 0 clamped into the box is tried first as a guess.
  const bool zero_b = GENERATE(false, true);
  // Row 1 asks for 1 ≤ λ₁ ≤ −1: no λ is feasible. Rows 0 and 2 are contacts (λ = b).
  const VecX b = zero_b ? VecX::Zero(3) : (VecX(3) << 1.0, 0.5, 0.5).finished();
  const VecX lo = (VecX(3) << 0.0, 1.0, 0.0).finished();
  const VecX hi = (VecX(3) << kInf, -1.0, kInf).finished();
  const UnitRows u({0, 1, 2}, b, lo, hi);
  SolverOptions options = interior();
  options.direct.interior_from_rows = interior_from_rows;
  VecX lambda;
  const auto start = std::chrono::steady_clock::now();
  SolverSummary s;
  std::string error;  // an exception naming the row is a clear answer too
  try {
    s = solve_direct(u.problem(body), lambda, options);
  } catch (const std::exception& e) {
    error = e.what();
  }
  const double elapsed = seconds_since(start);
  INFO("body " << body << ", interior_from_rows " << interior_from_rows << ", b = 0 " << zero_b);
  INFO(s.message << " in " << elapsed << " s, termination " << to_string(s.termination)
                 << ", lambda " << lambda.transpose() << ", exception: " << error);
  CHECK(elapsed < 1.0);
  if (error.empty()) {
    // clamp(x, lo, hi) = min(max(x, lo), hi) is hi whenever lo > hi, so λ₁ = cmax would have a
    // natural-map residual of 0: both exact paths must check the box first (check_box).
    CHECK(s.termination == Termination::NotConverged);
    CHECK(std::isfinite(s.residual));
    CHECK(lambda.allFinite());
  }
}

// ---------------------------------------------------------------------------------------------
// 7. Fixed rows.

TEST_CASE("interior path: fixed rows (cmin = cmax) keep exactly their value",
          "[direct][interior]") {
  SECTION("friction rows fixed at 0 and a contact row fixed at a load, on a pyramid step") {
    const System& sys = stepped("pyramid", {{"base", "6"}}, 30);
    VecX lo = sys.cmin, hi = sys.cmax;
    std::vector<Eigen::Index> fixed;
    int frictions = 0;
    for (Eigen::Index k = 0; k < sys.rows(); ++k) {
      const std::string& label = sys.labels[std::size_t(k)];
      if (label.rfind("friction ", 0) == 0 && frictions++ % 3 == 0) {
        lo(k) = hi(k) = 0.0;  // every third friction row: no friction
        fixed.push_back(k);
      }
    }
    for (Eigen::Index k = 0; k < sys.rows(); ++k) {
      if (sys.labels[std::size_t(k)].rfind("contact ", 0) == 0) {
        lo(k) = hi(k) = 2.5;  // the first contact row: a given load, N
        fixed.push_back(k);
        break;
      }
    }
    REQUIRE(fixed.size() > 5);
    BoxedProblem problem{sys.A, sys.b, lo, hi};
    problem.J = &sys.J;
    problem.Minv = &sys.Minv;
    const double scale = scale_of(problem);
    for (const bool body : {false, true}) {
      const BoxedProblem p = body ? problem : BoxedProblem{sys.A, sys.b, lo, hi};
      const VecX lambda = solve_interior_in(p, body, scale);
      for (const Eigen::Index k : fixed) {
        CAPTURE(k, sys.labels[std::size_t(k)]);
        CHECK(lambda(k) == lo(k));
      }
      const Kkt kk = kkt(p, lambda, kResidual * scale);
      CHECK(kk.outside_box == 0.0);
      CHECK(kk.w_violation <= kResidual * scale);
    }
  }
  SECTION("constructed problems with fixed rows, in row and body space") {
    std::mt19937 rng(23);
    int fixed_rows = 0;
    for (int trial = 0; trial < 40; ++trial) {
      const int k = 4 + trial % 12;
      const Constructed p = construct(k, trial % 2 == 0 ? k + 3 : k / 2, rng);
      const WithFactors factors(p);
      for (const bool body : {false, true}) {
        const BoxedProblem problem = body ? factors.problem(p) : BoxedProblem{p.A, p.b, p.lo, p.hi};
        VecX lambda;
        const SolverSummary s = solve_direct(problem, lambda, interior());
        CAPTURE(trial, k, body, s.message);
        CHECK(s.termination == Termination::Direct);
        for (int i = 0; i < k; ++i) {
          if (p.lo(i) != p.hi(i)) continue;
          ++fixed_rows;
          CAPTURE(i);
          CHECK(lambda(i) == p.lo(i));
        }
      }
    }
    CHECK(fixed_rows > 20);
  }
}

TEST_CASE(
    "a tolerance below the rounding floor is aimed at while the steps still reduce the "
    "residual",
    "[direct][interior][tolerance]") {
  // may_stop's rule: at the tolerance; above the floor never; at or below the floor at once when
  // the tolerance is 0, else once a step no longer reduces the residual.
  CHECK(may_stop(1e-12, 1.0, 1e-11, 1e-10));
  CHECK_FALSE(may_stop(2e-10, 3e-10, 1e-11, 1e-10));
  CHECK_FALSE(may_stop(2e-10, 3e-10, 0.0, 1e-10));
  CHECK(may_stop(5e-11, std::numeric_limits<double>::infinity(), 0.0, 1e-10));
  CHECK_FALSE(may_stop(5e-11, 8e-11, 1e-11, 1e-10));
  CHECK(may_stop(5e-11, 5e-11, 1e-11, 1e-10));
  CHECK(may_stop(5e-11, 4e-11, 1e-11, 1e-10));

  // Asked for far less than rounding allows (1e-30 N), the path ends Direct at its floor, further
  // down than where tolerance 0 (the floor itself) lets it stop: measured 5.1e-11 against
  // 9.4e-11 N on the base-10 pyramid (body space), 2.3e-11 against 4.1e-11 N on the base-6
  // pyramid (A(F, F)). The stack's first stop below its floor is already as far as it gets.
  struct Case {
    std::string name;
    std::map<std::string, std::string> values;
    int steps;
    bool further;  ///< the tolerance-0 stop is not yet where the steps stop reducing it
  };
  const Case c = GENERATE(values<Case>({
      {"pyramid", {{"base", "6"}, {"persistence", "0"}}, 30, true},  // as measured: feature ids
      {"pyramid", {{"base", "10"}, {"persistence", "0"}}, 30, true},
      {"stack", {{"n", "10"}, {"columns", "5"}}, 1, false},
  }));
  const BoxedProblem problem = stepped(c.name, c.values, c.steps).problem();
  SolverOptions at_floor = interior();
  at_floor.tolerance = 0.0;
  SolverOptions below = interior();
  below.tolerance = 1e-30;
  VecX lambda_floor, lambda_below;
  const SolverSummary f = solve_direct(problem, lambda_floor, at_floor);
  const SolverSummary s = solve_direct(problem, lambda_below, below);
  INFO(c.name << ": tolerance 0: " << f.message << "; tolerance 1e-30: " << s.message);
  CHECK(f.termination == Termination::Direct);
  CHECK(s.termination == Termination::Direct);
  CHECK(f.residual <= residual_floor(problem, lambda_floor));
  CHECK(s.residual <= residual_floor(problem, lambda_below));
  CHECK(s.crossover >= f.crossover);
  if (c.further) {
    CHECK(s.residual < f.residual);
  } else {
    CHECK(s.residual <= f.residual);
  }
}
