// The unit-free residual (system/unit_free.hpp): closed forms by hand, zero at a solution, and the
// same number whatever the units of force and of velocity, on Siconos' own problems (a boxed
// relay problem, a frictional contact problem whose W is not symmetric) under both cone laws.
#include <catch2/catch.hpp>
#include <cmath>

#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/cone_problem.hpp"
#include "cbps/system/unit_free.hpp"
#include "fixture.hpp"

using namespace cbps;

namespace {

/// The same problem and lambda in other units: force divided by `force` (λ, cmin, cmax → ·/s,
/// A → s A), then velocity multiplied by `velocity` (A → s A, b → s b).
struct Scaled {
  SpMat A;
  VecX b, cmin, cmax, lambda;
};
Scaled in_units(const StoredProblem& p, const VecX& lambda, double force, double velocity) {
  return {SpMat(p.A * (force * velocity)),
          p.b * velocity,
          p.cmin / force,
          p.cmax / force,
          lambda / force};
}

double relative(const Scaled& s, const FrictionContacts* cones) {
  BoxedProblem q{s.A, s.b, s.cmin, s.cmax};
  q.cones = cones;
  return unit_free_residual(q, s.lambda).relative;
}

}  // namespace

TEST_CASE("the unit-free residual of a row and of a contact, by hand", "[unit-free]") {
  // One row, A = 2, b = 4, [0, ∞), λ = 1: w = −2, ρ = 1/2, F = 1 − max(0, 1 + 1) = −1;
  // S = max(|λ|, ρ |b|) = 2.
  const SpMat A = (MatX(1, 1) << 2.0).finished().sparseView();
  const VecX b = VecX::Constant(1, 4.0), cmin = VecX::Zero(1), cmax = VecX::Constant(1, kInf);
  const BoxedProblem row{A, b, cmin, cmax};
  const UnitFreeResidual u = unit_free_residual(row, VecX::Constant(1, 1.0));
  CHECK(u.residual == 1.0);
  CHECK(u.scale == 2.0);
  CHECK(u.relative == 0.5);
  CHECK(unit_free_residual(row, VecX::Constant(1, 2.0)).relative == 0.0);  // the answer
  // Nothing asked and nothing given: 0.
  CHECK(unit_free_residual(BoxedProblem{A, VecX::Zero(1), cmin, cmax}, VecX::Zero(1)).relative ==
        0.0);
  // One contact, W = 4 I, b = (4, 8, 0), mu = 0.5, Coulomb: r = (1, 0.5, 0) slides (u_n = 0,
  // u_t = (−6, 0), r_t = −mu r_n u_t/|u_t|). At r = 0: ρ = 1/4, ρ û = (−1 + 0.5·2, −2, 0) =
  // (0, −2, 0), P_K((0, 2, 0)) = ((0 + 0.5·2)/1.25)(1, 0.5, 0) = (0.8, 0.4, 0), |F| = sqrt(0.8)
  // = 0.894...; S = ρ |b|∞ = 2.
  const SpMat W = (Mat3::Identity() * 4.0).sparseView();
  const VecX bc = (VecX(3) << 4.0, 8.0, 0.0).finished();
  const VecX cminc = (VecX(3) << 0.0, -kInf, -kInf).finished(), cmaxc = VecX::Constant(3, kInf);
  FrictionContacts cones;
  cones.normal = {0};
  cones.mu = VecX::Constant(1, 0.5);
  BoxedProblem contact{W, bc, cminc, cmaxc};
  contact.cones = &cones;
  const UnitFreeResidual at_zero = unit_free_residual(contact, VecX::Zero(3));
  CHECK(at_zero.residual == Approx(std::sqrt(0.8)).epsilon(1e-14));
  CHECK(at_zero.scale == 2.0);
  CHECK(unit_free_residual(contact, (VecX(3) << 1.0, 0.5, 0.0).finished()).relative <= 1e-16);
}

TEST_CASE("the unit-free residual does not change with the units of force and velocity",
          "[unit-free]") {
  // Siconos' relay problem (boxed rows) and a rover's frictional contacts (W not symmetric),
  // at a lambda that is not the answer; cbps's scale max(1, |b|inf, max |A_ij|) does change.
  const StoredProblem relay =
      read_problem((test::kSiconosDir / "relay" / "relay_4x4.dat").string());
  StoredProblem rover = read_problem((test::kFc3dDir / "Rover4396.dat").string());
  for (const FrictionLaw law : {FrictionLaw::CoulombCone, FrictionLaw::Relaxation}) {
    rover.cones.law = law;
    for (const StoredProblem* p : {&relay, static_cast<const StoredProblem*>(&rover)}) {
      VecX lambda(p->rows());
      for (Eigen::Index k = 0; k < lambda.size(); ++k) lambda(k) = 0.3 + std::sin(1.0 + k);
      if (!p->cones.empty())
        for (const int n : p->cones.normal) lambda(n) = 1.0 + std::abs(lambda(n));
      const FrictionContacts* cones = p->cones.empty() ? nullptr : &p->cones;
      const double base = relative(in_units(*p, lambda, 1.0, 1.0), cones);
      INFO("rows " << p->rows() << ", law " << cone_law_name(law) << ", relative " << base);
      REQUIRE(base > 1e-3);
      for (const auto& [force, velocity] :
           {std::pair{1e3, 1.0}, {1e-4, 1.0}, {1.0, 1e-2}, {1.0, 1e5}, {1e2, 1e-3}}) {
        const Scaled s = in_units(*p, lambda, force, velocity);
        CHECK(relative(s, cones) == Approx(base).epsilon(1e-12));
      }
      // cbps's own scale moves with the units: the reason for this residual.
      const Scaled far = in_units(*p, lambda, 1e3, 1e3);
      BoxedProblem q{far.A, far.b, far.cmin, far.cmax};
      q.cones = cones;
      const double scaled_old = natural_map_residual(q, far.lambda) / scale_of(q);
      const double old = natural_map_residual(p->problem(), lambda) / scale_of(p->problem());
      CHECK(std::abs(std::log10(scaled_old / old)) > 1.0);
    }
  }
}

TEST_CASE("the direct path's target bounds the unit-free residual, and the verdict reads it",
          "[unit-free]") {
  // unit_free_target turns a unit-free target into a natural-map residual with unit step: any
  // lambda whose natural map is at most target.newtons(t, lambda) has a unit-free residual of at
  // most t (a natural map's norm grows with its step and shrinks over it). Checked in units where
  // the steps 1/A_kk are far above 1 and far below it, at lambdas near and far from the answer.
  StoredProblem rover = read_problem((test::kFc3dDir / "Rover4396.dat").string());
  const StoredProblem relay =
      read_problem((test::kSiconosDir / "relay" / "relay_4x4.dat").string());
  for (const FrictionLaw law : {FrictionLaw::CoulombCone, FrictionLaw::Relaxation}) {
    rover.cones.law = law;
    for (const StoredProblem* p : {&relay, static_cast<const StoredProblem*>(&rover)}) {
      const FrictionContacts* cones = p->cones.empty() ? nullptr : &p->cones;
      for (const double force : {1e-6, 1.0, 1e6}) {
        for (const double size : {1e-9, 1e-3, 1.0}) {
          VecX lambda(p->rows());
          for (Eigen::Index k = 0; k < lambda.size(); ++k) lambda(k) = size * std::sin(2.0 + k);
          const Scaled s = in_units(*p, lambda, force, 1.0);
          BoxedProblem q{s.A, s.b, s.cmin, s.cmax};
          q.cones = cones;
          const UnitFreeTarget target = unit_free_target(q);
          const double natural = natural_map_residual(q, s.lambda);
          const UnitFreeResidual u = unit_free_residual(q, s.lambda);
          // The bound at t = natural / newtons(1, λ), the smallest t the target certifies.
          const double certified = natural / target.newtons(1.0, s.lambda);
          INFO("rows " << p->rows() << ", force unit " << force << ", |lambda| " << size
                       << ": unit-free " << u.relative << ", certified " << certified);
          CHECK(u.relative <= certified * (1.0 + 1e-12));
        }
      }
    }
  }
  // The verdict: at most kSolvedTolerance, finite; a lambda of the wrong size is never solved.
  const VecX one = VecX::Constant(1, 1.0);
  UnitFreeResidual u;
  u.relative = kSolvedTolerance;
  CHECK(is_solved(u, one));
  u.relative = 2.0 * kSolvedTolerance;
  CHECK_FALSE(is_solved(u, one));
  u.relative = std::nan("");
  CHECK_FALSE(is_solved(u, one));
  u.relative = 0.0;
  CHECK_FALSE(is_solved(u, VecX::Constant(1, std::nan(""))));
  const SpMat A = SpMat(Eigen::MatrixXd::Identity(2, 2).sparseView());
  const VecX b = VecX::Ones(2), lo = VecX::Zero(2), hi = VecX::Constant(2, kInf);
  CHECK_FALSE(is_solved(unit_free_residual(BoxedProblem{A, b, lo, hi}, one), one));
}

TEST_CASE("the unit-free residual from rows held apart, as ranks hold them, is the whole problem's",
          "[unit-free]") {
  // A boxed problem with free, bounded and one-sided rows, a zero diagonal entry (the fallback
  // step) and a lambda off its answer, cut into three parts of rows as MPI ranks hold them
  // (distributed/tao.cpp, exact.cpp): the maxima of the parts' residuals and scales, put together
  // by unit_free_of, are unit_free_residual of the whole problem; so is the direct path's target.
  const int c = 9;
  SpMat A = test::random_spd(c, 7);
  A.coeffRef(4, 4) = 0.0;  // not positive: that row takes 1 / max A_kk
  const VecX b = VecX::LinSpaced(c, -3.0, 5.0);
  VecX cmin = VecX::Constant(c, -kInf), cmax = VecX::Constant(c, kInf);
  cmin.segment(2, 4).setZero();
  cmax(3) = 0.25;
  const VecX lambda = VecX::LinSpaced(c, 0.5, -0.7);
  const BoxedProblem whole{A, b, cmin, cmax};
  const UnitFreeResidual expected = unit_free_residual(whole, lambda);
  REQUIRE(expected.relative > 0.0);
  const VecX w = A * lambda - b;
  const VecX diagonal = A.diagonal();
  const double largest = diagonal.maxCoeff();
  double residual = 0.0, scale = 0.0;
  UnitFreeTarget target;
  target.rho_max = 0.0;
  for (const auto& [first, n] : {std::pair{0, 3}, std::pair{3, 4}, std::pair{7, 2}}) {
    const UnitFreeResidual part = unit_free_rows(w.segment(first, n),
                                                 lambda.segment(first, n),
                                                 b.segment(first, n),
                                                 cmin.segment(first, n),
                                                 cmax.segment(first, n),
                                                 diagonal.segment(first, n),
                                                 largest);
    residual = std::max(residual, part.residual);
    scale = std::max(scale, part.scale);
    const UnitFreeTarget t =
        unit_free_target_rows(b.segment(first, n), diagonal.segment(first, n), largest);
    target.rho_b = std::max(target.rho_b, t.rho_b);
    target.rho_max = std::max(target.rho_max, t.rho_max);
  }
  const UnitFreeResidual joined = unit_free_of(residual, scale);
  CHECK(joined.residual == expected.residual);
  CHECK(joined.scale == expected.scale);
  CHECK(joined.relative == expected.relative);
  const UnitFreeTarget serial = unit_free_target(whole);
  CHECK(target.rho_b == serial.rho_b);
  CHECK(target.rho_max == serial.rho_max);
}

TEST_CASE("the sweeps stop where the residual is within the tolerance both ways, in any units",
          "[unit-free]") {
  // With tolerance_unit_free (`cbps lcp` on a Siconos or FCLIB file) the sweeps read the
  // tolerance as the direct path does: within τ N and within a unit-free τ. In units of force
  // 1e12 times cbps's and of velocity 1e-12 times (A as it is, b and λ 1e-12 times) the natural
  // map is 1e-12 times smaller and τ = 1e-10 is reached far from the answer: the unit-free
  // residual where they stop must be within τ in every unit (and without the flag, in those
  // units, it is not: they stop far from the answer, as nsgs did on LMGC90's dumps). Siconos'
  // relay problem under PGS and a rover's contacts (W not symmetric) under nsgs and both cone
  // laws.
  const StoredProblem relay =
      read_problem((test::kSiconosDir / "relay" / "relay_4x4.dat").string());
  StoredProblem rover = read_problem((test::kFc3dDir / "Rover4396.dat").string());
  const double tolerance = 1e-10;
  for (const FrictionLaw law : {FrictionLaw::CoulombCone, FrictionLaw::Relaxation}) {
    rover.cones.law = law;
    for (const StoredProblem* p : {&relay, static_cast<const StoredProblem*>(&rover)}) {
      const FrictionContacts* cones = p->cones.empty() ? nullptr : &p->cones;
      for (const double force : {1.0, 1e12}) {
        const Scaled s = in_units(*p, VecX::Zero(p->rows()), force, 1.0 / force);
        BoxedProblem q{s.A, s.b, s.cmin, s.cmax};
        q.cones = cones;
        for (const bool both : {true, false}) {
          SolverOptions o;
          o.method = cones != nullptr ? Method::Nsgs : Method::Pgs;
          o.max_iterations = 100000;
          o.tolerance = tolerance;
          o.tolerance_unit_free = both;
          VecX lambda;
          const SolverSummary summary = solve(q, lambda, o);
          const double unit_free = unit_free_residual(q, lambda).relative;
          INFO("rows " << p->rows() << ", law " << cone_law_name(law) << ", force unit " << force
                       << (both ? ", both ways: " : ", in N alone: ") << summary.iterations
                       << " sweeps, " << summary.residual << " N, unit-free " << unit_free);
          CHECK(summary.termination == Termination::ResidualTolerance);
          CHECK(summary.residual <= tolerance);
          if (both) CHECK(unit_free <= tolerance);
          if (!both && force == 1e12) CHECK(unit_free > 1e-3);
        }
      }
    }
  }
}
