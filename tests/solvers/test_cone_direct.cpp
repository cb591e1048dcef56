// The exact path on friction cones (solvers/cone/cone_direct.hpp): one contact's answers worked
// out by hand under both laws, the sliding box's law for it and nsgs (friction mu times the
// normal force, against the motion), pyramids whose W is singular, problems with free, boxed and
// fixed rows beside the cones checked against nsgs (an independent method), and the contract that
// it never calls an answer it has not verified solved.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <random>

#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/cone_problem.hpp"
#include "cbps/system/unit_free.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::cones_of;
using test::system_of;

namespace {

SolverOptions direct_options(double tolerance) {
  SolverOptions o;
  o.method = Method::Direct;
  o.tolerance = tolerance;
  return o;
}

/// One contact, W = I: its answers by hand (for W = I the CCP's answer is P_K(b), the nearest
/// point of the cone to b; Coulomb's slides with u_n = 0 and r_t = −mu r_n u_t / ‖u_t‖).
void check_one_contact(const Vec3& b3, FrictionLaw law, const Vec3& expected) {
  const SpMat A = Mat3::Identity().sparseView();
  const VecX b = b3;
  const VecX cmin = (VecX(3) << 0.0, -kInf, -kInf).finished();
  const VecX cmax = VecX::Constant(3, kInf);
  FrictionContacts cones;
  cones.normal = {0};
  cones.mu = VecX::Constant(1, 0.5);
  cones.law = law;
  BoxedProblem problem{A, b, cmin, cmax};
  problem.cones = &cones;
  VecX lambda;
  const SolverSummary s = solve(problem, lambda, direct_options(1e-12));
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  CHECK((lambda - expected).lpNorm<Eigen::Infinity>() <= 1e-10);
}

/// A problem with cones in units of force `force` times its own (λ → λ / force, A → force A),
/// solved by `direct` told 1e-10 as `cbps lcp` tells it on a Siconos or FCLIB file
/// (tolerance_unit_free): its summary, lambda in those units and its unit-free residual.
struct FileSolve {
  SolverSummary summary;
  VecX lambda;
  double unit_free = 0.0;
};
FileSolve direct_in_units(const BoxedProblem& p, const FrictionContacts& cones, double force) {
  const SpMat A = p.A * force;
  const VecX cmin = p.cmin / force, cmax = p.cmax / force;
  BoxedProblem problem{A, p.b, cmin, cmax};
  problem.cones = &cones;
  SolverOptions o = direct_options(1e-10);
  o.tolerance_unit_free = true;
  FileSolve r;
  r.summary = solve(problem, r.lambda, o);
  r.unit_free = unit_free_residual(problem, r.lambda).relative;
  return r;
}

}  // namespace

TEST_CASE("direct on cones finds one contact's answers worked out by hand", "[cone-direct]") {
  // Separating (b_n < 0): r = 0 under both laws.
  for (const FrictionLaw law : {FrictionLaw::CoulombCone, FrictionLaw::Relaxation})
    check_one_contact(Vec3(-1.0, 0.3, 0.2), law, Vec3::Zero());
  // Sticking (b inside K): r = b, u = 0.
  for (const FrictionLaw law : {FrictionLaw::CoulombCone, FrictionLaw::Relaxation})
    check_one_contact(Vec3(1.0, 0.3, -0.2), law, Vec3(1.0, 0.3, -0.2));
  // Sliding, b = (1, 2, 0), mu = 0.5. Coulomb: u_n = r_n − 1 = 0, and u_t = r_t − 2 < 0, so
  // r_t = +mu r_n = 0.5. CCP: P_K(b) = ((1 + 0.5·2)/1.25)(1, 0.5, 0) = (1.6, 0.8, 0).
  check_one_contact(Vec3(1.0, 2.0, 0.0), FrictionLaw::CoulombCone, Vec3(1.0, 0.5, 0.0));
  check_one_contact(Vec3(1.0, 2.0, 0.0), FrictionLaw::Relaxation, Vec3(1.6, 0.8, 0.0));
}

TEST_CASE("direct on cones judges each contact by its own rounding floor, guess or answer",
          "[cone-direct][tolerance]") {
  // Two contacts of compliances 1e6 and 1e-8 kg⁻¹ pressed shut with forces of 1/3 N and 1 N
  // (b_n = A_nn λ_n, no tangential push: both stick with λ_t = 0). A guess with the second
  // normal force 1.5 N leaves w_n = 5e-9 m/s there, below the first contact's rounding floor
  // (4.7e-9 m/s, the largest row's, which every contact was judged by) and far above its own: it
  // was returned as solved, unit-free residual 0.33. Both readings of the tolerance: N (cbps's
  // own problems) and unit-free (a file's units). Where the stages' target is read in N (unit
  // step), the relaxation's interior point stops with w_n of the second contact under the first
  // one's floor (its force 0.67 N): the measure cannot see it there, and the answer must say
  // "not verified"; everywhere else direct solves it.
  const SpMat A = (VecX(6) << 1e6, 1e6, 1e6, 1e-8, 1e-8, 1e-8)
                      .finished()
                      .asDiagonal()
                      .toDenseMatrix()
                      .sparseView();
  const VecX b = (VecX(6) << 1e6 / 3.0, 0.0, 0.0, 1e-8, 0.0, 0.0).finished();
  const VecX cmin = (VecX(6) << 0.0, -kInf, -kInf, 0.0, -kInf, -kInf).finished();
  const VecX cmax = VecX::Constant(6, kInf);
  FrictionContacts cones;
  cones.normal = {0, 3};
  cones.mu = VecX::Constant(2, 0.5);
  for (const FrictionLaw law : {FrictionLaw::CoulombCone, FrictionLaw::Relaxation}) {
    cones.law = law;
    BoxedProblem problem{A, b, cmin, cmax};
    problem.cones = &cones;
    for (const bool unit_free : {false, true}) {
      for (const bool warm : {true, false}) {
        SolverOptions o = direct_options(1e-10);
        o.tolerance_unit_free = unit_free;
        VecX lambda = VecX::Zero(6);
        if (warm) lambda << 1.0 / 3.0, 0.0, 0.0, 1.5, 0.0, 0.0;
        const SolverSummary s = solve(problem, lambda, o);
        const double relative = unit_free_residual(problem, lambda).relative;
        INFO(cone_law_name(law) << (unit_free ? ", unit-free" : ", N")
                                << (warm ? ", warm: " : ", cold: ") << s.message);
        CHECK(s.message.find("the guess already meets") == std::string::npos);
        CHECK((s.termination != Termination::Direct || relative <= 1e-10));
        if (law == FrictionLaw::Relaxation && !unit_free) continue;
        CHECK(s.termination == Termination::Direct);
        CHECK(lambda(3) == Approx(1.0).epsilon(1e-12));
        CHECK(relative <= 1e-12);
      }
    }
  }
}

TEST_CASE("nsgs and direct on a sliding box: Coulomb's friction is mu times the normal force",
          "[cone-direct][nsgs]") {
  // The slide scene: a box moving at 2 m/s along x on a plane, four contacts all sliding the same
  // way. Coulomb's law per contact: u_n = 0 and r_t = −mu r_n u_t / ‖u_t‖ (opposing the motion,
  // as strong as the cone allows), so summed friction −mu Σ r_n along x; the relaxation instead
  // lifts off, u_n = mu ‖u_t‖ > 0. Properties of the law, on sums neither method forms.
  const double mu = 0.3;
  const System sys = system_of("slide", {{"mu", "0.3"}}, 2);
  for (const Method method : {Method::Nsgs, Method::Direct}) {
    SolverOptions o = direct_options(1e-10);
    o.method = method;
    o.max_iterations = 20000;
    const Termination reached =
        method == Method::Direct ? Termination::Direct : Termination::ResidualTolerance;
    FrictionContacts cones = cones_of(sys, mu, FrictionLaw::CoulombCone);
    REQUIRE(cones.contacts() == 4);
    BoxedProblem problem = sys.problem();
    problem.cones = &cones;
    VecX lambda;
    const SolverSummary s = solve(problem, lambda, o);
    INFO(s.message);
    REQUIRE(s.termination == reached);
    CHECK(natural_map_residual(problem, lambda) <= 1e-10);
    const VecX w = sys.A * lambda - sys.b;
    double normal = 0.0;
    Eigen::Vector2d friction_t = Eigen::Vector2d::Zero();  // one plane: one tangent basis
    for (const int n : cones.normal) {
      normal += lambda(n);
      CHECK(std::abs(w(n)) <= 1e-9);
      const double u_t = std::hypot(w(n + 1), w(n + 2));
      REQUIRE(u_t > 1e-3);
      CHECK(lambda(n + 1) == Approx(-mu * lambda(n) * w(n + 1) / u_t).margin(1e-9));
      CHECK(lambda(n + 2) == Approx(-mu * lambda(n) * w(n + 2) / u_t).margin(1e-9));
      friction_t += Eigen::Vector2d(lambda(n + 1), lambda(n + 2));
    }
    CHECK(normal > 0.0);
    CHECK(friction_t.norm() == Approx(mu * normal).epsilon(1e-9));

    cones.law = FrictionLaw::Relaxation;
    VecX relaxed;
    const SolverSummary r = solve(problem, relaxed, o);
    INFO(r.message);
    REQUIRE(r.termination == reached);
    const VecX v = sys.A * relaxed - sys.b;
    for (const int n : cones.normal) {
      const double u_t = std::hypot(v(n + 1), v(n + 2));
      CHECK(v(n) == Approx(mu * u_t).margin(1e-9));
      CHECK(v(n) > 1e-3);
    }
  }
}

TEST_CASE("direct solves the relaxation on pyramids whose W is singular", "[cone-direct]") {
  // A pyramid's W = J M⁻¹ Jᵀ has far more rows than the bodies' 6n freedoms (base 5: 300 rows,
  // 15 bodies), its contacts at the corners carry no load yet do not move: complementarity is
  // not strict there, which the interior point alone cannot finish (docs/cones.md). The answer
  // is judged by the cone law's natural map, which is defined apart from the solver
  // (system/cone_problem.hpp, checked against FCLIB's merit in tests/io/test_fclib_file.cpp).
  for (const int base : {3, 5}) {
    const System sys = system_of("pyramid", {{"base", std::to_string(base)}}, 50);
    const FrictionContacts cones = cones_of(sys, 0.5, FrictionLaw::Relaxation);
    REQUIRE(cones.contacts() > 0);
    BoxedProblem problem = sys.problem();
    problem.cones = &cones;
    VecX lambda;
    const SolverSummary s = solve(problem, lambda, direct_options(1e-10));
    INFO("base " << base << ": " << s.message);
    CHECK(s.termination == Termination::Direct);
    CHECK(natural_map_residual(problem, lambda) <= 1e-10);
    const ConeMeasures m = cone_measures(cones, lambda, sys.A * lambda - sys.b, sys.b);
    CHECK(m.violation <= 1e-10);  // N, of forces up to tens of N
  }
}

TEST_CASE("direct on cones beside free, boxed and fixed rows agrees with nsgs", "[cone-direct]") {
  // Random problems A = J M⁻¹ Jᵀ with fewer rows (5 contacts, two free rows, a row boxed in
  // [−0.3, 0.4], a row fixed at 0.2: 19) than freedoms (24), so A is definite and lambda unique
  // for the relaxation: nsgs, run to 1e-12, is an independent method to compare it with.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 6; ++trial) {
    const int c = 19, dof = 24;
    MatX J(c, dof);
    for (int i = 0; i < c; ++i)
      for (int j = 0; j < dof; ++j) J(i, j) = u(rng);
    const SpMat A = (J * J.transpose() / dof).sparseView();
    VecX b(c);
    for (int i = 0; i < c; ++i) b(i) = u(rng) + (i % 3 == 0 && i < 15 ? 0.5 : 0.0);
    VecX cmin = VecX::Constant(c, -kInf), cmax = VecX::Constant(c, kInf);
    FrictionContacts cones;
    cones.law = FrictionLaw::Relaxation;
    cones.mu.resize(5);
    for (int i = 0; i < 5; ++i) {
      cones.normal.push_back(3 * i);
      cones.mu(i) = 0.2 + 0.4 * (u(rng) + 1.0);
      cmin(3 * i) = 0.0;
    }
    cmin(17) = -0.3;
    cmax(17) = 0.4;
    cmin(18) = cmax(18) = 0.2;
    BoxedProblem problem{A, b, cmin, cmax};
    problem.cones = &cones;
    VecX exact;
    const SolverSummary s = solve(problem, exact, direct_options(1e-12));
    INFO("trial " << trial << ": " << s.message);
    REQUIRE(s.termination == Termination::Direct);
    SolverOptions o;
    o.method = Method::Nsgs;
    o.max_iterations = 200000;
    o.tolerance = 1e-12;
    VecX by_nsgs;
    const SolverSummary n = solve(problem, by_nsgs, o);
    REQUIRE(n.termination == Termination::ResidualTolerance);
    CHECK((exact - by_nsgs).lpNorm<Eigen::Infinity>() <= 1e-8);
    CHECK(exact(18) == 0.2);

    // Coulomb's law on the same problem: whatever it reaches, it says Direct only when the
    // residual is within the tolerance (never an answer it has not verified).
    cones.law = FrictionLaw::CoulombCone;
    VecX coulomb;
    const SolverSummary k = solve(problem, coulomb, direct_options(1e-10));
    INFO(k.message);
    const double r = natural_map_residual(problem, coulomb);
    CHECK((k.termination == Termination::Direct) == (r <= 1e-10));
    CHECK(k.residual == r);
  }
}

TEST_CASE("direct on cones: a frictionless contact (mu = 0) and a non-finite b", "[cone-direct]") {
  // mu = 0: the cone is the ray r_t = 0, r_n ≥ 0, so with W = I the answer is (max(b_n, 0), 0, 0)
  // whatever b_t is.
  const SpMat A = Mat3::Identity().sparseView();
  VecX b = Vec3(1.0, 2.0, 0.5);
  const VecX cmin = (VecX(3) << 0.0, -kInf, -kInf).finished();
  const VecX cmax = VecX::Constant(3, kInf);
  FrictionContacts cones;
  cones.normal = {0};
  cones.mu = VecX::Zero(1);
  BoxedProblem problem{A, b, cmin, cmax};
  problem.cones = &cones;
  for (const FrictionLaw law : {FrictionLaw::CoulombCone, FrictionLaw::Relaxation}) {
    cones.law = law;
    VecX lambda;
    const SolverSummary s = solve(problem, lambda, direct_options(1e-12));
    INFO(s.message);
    CHECK(s.termination == Termination::Direct);
    CHECK((lambda - Vec3(1.0, 0.0, 0.0)).lpNorm<Eigen::Infinity>() <= 1e-12);
  }
  b(1) = std::nan("");
  VecX lambda;
  const SolverSummary s = solve(problem, lambda, direct_options(1e-12));
  CHECK(s.termination == Termination::NonFinite);
  CHECK(std::isnan(s.residual));
}

TEST_CASE("apgd, admm, pgs-nesterov on the relaxation's cones: the QP's A lambda, as direct has it",
          "[cone-direct][apgd][admm][pgs-nesterov]") {
  // The relaxation is the optimality condition of ½ λᵀAλ − bᵀλ over the cones: every minimiser
  // has the same A λ (A positive semidefinite), so the first-order methods Mazhar et al. and
  // Tasora et al. run on these cones, and PGS with momentum on nsgs's sweep, must reach direct's
  // w = A λ − b, whatever λ they pick on a singular A. Coulomb's law is no QP: all refuse it.
  const System sys = system_of("pyramid", {{"base", "3"}}, 50);
  FrictionContacts cones = cones_of(sys, 0.5, FrictionLaw::Relaxation);
  BoxedProblem problem = sys.problem();
  problem.cones = &cones;
  VecX exact;
  REQUIRE(solve(problem, exact, direct_options(1e-10)).termination == Termination::Direct);
  const VecX w_exact = sys.A * exact - sys.b;
  for (const Method method : {Method::Apgd, Method::Admm, Method::PgsNesterov}) {
    SolverOptions o = direct_options(1e-9);
    o.method = method;
    o.max_iterations = 50000;
    VecX lambda;
    const SolverSummary s = solve(problem, lambda, o);
    INFO(to_string(method) << ": " << s.message);
    CHECK(s.termination == Termination::ResidualTolerance);
    CHECK(natural_map_residual(problem, lambda) <= 1e-9);
    const ConeMeasures m = cone_measures(cones, lambda, sys.A * lambda - sys.b, sys.b);
    CHECK(m.violation <= 1e-12);  // every iterate is projected onto the cones
    CHECK((sys.A * lambda - sys.b - w_exact).lpNorm<Eigen::Infinity>() <= 1e-6);
  }
  cones.law = FrictionLaw::CoulombCone;
  for (const Method method : {Method::Apgd, Method::Admm, Method::PgsNesterov}) {
    SolverOptions o = direct_options(1e-9);
    o.method = method;
    VecX lambda;
    CHECK_THROWS_WITH(solve(problem, lambda, o), Catch::Contains("convex relaxation (ccp)"));
  }
}

TEST_CASE("direct on Coulomb's cones finishes a pile settling under the paper's box",
          "[cone-direct]") {
  // The states issue 31's peers were measured on: a pyramid stepped under the paper's box while
  // it settles, its step posed on Coulomb's cone (`cbps matrices pyramid --param base=B --step 3
  // --fclib F --cone coulomb`). Its answer has contacts opening, sticking and sliding at 1e-9
  // m/s on a singular A; the fixed point on De Saxcé's term stalls there (1.8e-9 N on base 3),
  // the interior point with the term refreshed at every iterate does not on bases 3 and 5. On
  // base 4 every stage before the averaged fixed point stops short (its message: "averaged
  // fixed-point rounds"), and that one finishes it. Judged by the law's natural map and its
  // measures, both defined apart from the solver.
  for (const int base : {3, 4, 5}) {
    const System sys = system_of("pyramid", {{"base", std::to_string(base)}, {"mu", "0.5"}}, 3);
    const FrictionContacts cones = contacts_in_cones(sys, FrictionLaw::CoulombCone);
    BoxedProblem problem = sys.problem();
    problem.cones = &cones;
    VecX lambda;
    const SolverSummary s = solve(problem, lambda, direct_options(1e-9));
    INFO("base " << base << ": " << s.message);
    CHECK(s.termination == Termination::Direct);
    CHECK(natural_map_residual(problem, lambda) <= 1e-9);  // N, of b up to 9.81 m/s²
    const ConeMeasures m = cone_measures(cones, lambda, sys.A * lambda - sys.b, sys.b);
    CHECK(m.violation <= 1e-9);
    CHECK(m.signorini <= 1e-8);
    CHECK(m.fclib_merit <= 1e-9);
  }
}

TEST_CASE(
    "direct's interior point with De Saxce's term differentiated finishes piles the "
    "refreshed one leaves short",
    "[cone-direct]") {
  // Piles settling under the paper's box (`cbps matrices pyramid --param base=5 --param mu=M
  // --step K --fclib F --cone coulomb`) whose answers the interior point with De Saxcé's term
  // only refreshed leaves short after its 80 iterations (7.0e-8 and 7.5e-9 scaled), and whose
  // later stages went on to the averaged fixed point (305 and 173 rounds, 5.8 s and 2.7 s);
  // with the term's derivative in the Newton matrix the interior point meets the law by itself.
  // Judged by the unit-free residual (unit_free.hpp), computed apart from the solver; 1e-10 is
  // issue 51's target.
  for (const auto& [mu, step] : {std::pair<const char*, int>{"0.5", 2}, {"0.8", 5}}) {
    const System sys = system_of("pyramid", {{"base", "5"}, {"mu", mu}}, step);
    const FrictionContacts cones = contacts_in_cones(sys, FrictionLaw::CoulombCone);
    BoxedProblem problem = sys.problem();
    problem.cones = &cones;
    VecX lambda;
    const SolverSummary s = solve(problem, lambda, direct_options(1e-10));
    INFO("mu " << mu << ", step " << step << ": " << s.message);
    CHECK(s.termination == Termination::Direct);
    CHECK(s.message.find("80 with De Saxce's term refreshed") != std::string::npos);
    CHECK(s.message.find(" 0 with it differentiated") == std::string::npos);
    CHECK(s.message.find("averaged fixed-point rounds") == std::string::npos);
    CHECK(unit_free_residual(problem, lambda).relative <= 1e-10);
  }
}

TEST_CASE("direct's averaged fixed point halves its weight where its rounds cycle",
          "[cone-direct]") {
  // A pile of base 6 settling under the paper's box with mu = 0.3, at step 2 (144 contacts):
  // both interior points with De Saxcé's term stop short, and so do stages 1 to 4; the averaged
  // fixed point's rounds at the first weight, 0.7, come to cycle above their least residual,
  // the weight halves, and the rounds meet the law. The message says so; the answer is judged
  // by the unit-free residual (unit_free.hpp), computed apart from the solver.
  const System sys = system_of("pyramid", {{"base", "6"}, {"mu", "0.3"}}, 2);
  const FrictionContacts cones = contacts_in_cones(sys, FrictionLaw::CoulombCone);
  BoxedProblem problem = sys.problem();
  problem.cones = &cones;
  VecX lambda;
  const SolverSummary s = solve(problem, lambda, direct_options(1e-10));
  INFO(s.message);
  CHECK(s.message.find("averaged fixed-point rounds (weight 0.7 halved") != std::string::npos);
  CHECK(unit_free_residual(problem, lambda).relative <= 1e-10);
}

TEST_CASE(
    "direct reads the tolerance of a problem in its simulator's units as a unit-free residual",
    "[cone-direct][unit-free]") {
  // The pile of base 6 settling under the paper's box with mu = 0.3, at step 3 (144 contacts),
  // as `cbps lcp` reads it from an FCLIB file (tolerance_unit_free), in four units of force:
  // λ → λ / s, A → s A. Read in N as well, the tolerance of 1e-10 lay below the answer's
  // residual in the file's units (3.2e-10 N at a unit-free 6.9e-13): the stages ran on to the
  // averaged fixed point for 20 s and called the answer not verified, where in units 100 times
  // smaller (forces above 1000 ulps' reach) it was verified in 0.5 s. Read as a unit-free residual
  // alone, every unit stops at the same verdict without the averaged fixed point. Judged by the
  // unit-free residual (unit_free.hpp, tested apart in tests/system/test_unit_free.cpp).
  const System sys = system_of("pyramid", {{"base", "6"}, {"mu", "0.3"}}, 3);
  const FrictionContacts cones = contacts_in_cones(sys, FrictionLaw::CoulombCone);
  for (const double force : {1e-3, 1.0, 10.0, 1e3}) {
    const FileSolve r = direct_in_units(sys.problem(), cones, force);
    INFO("unit of force " << force << " N: " << r.summary.message);
    CHECK(r.summary.termination == Termination::Direct);
    CHECK(r.summary.message.find("averaged fixed-point rounds") == std::string::npos);
    CHECK(r.summary.message.find("read as a unit-free residual alone") != std::string::npos);
    CHECK(r.unit_free <= 1e-10);
  }
}

TEST_CASE("direct takes the same path in any unit of force on a problem in its simulator's units",
          "[cone-direct][unit-free]") {
  // Siconos' Capsules-i125-1213 (W not symmetric), as `cbps lcp` reads it, in units
  // of force 1024 times smaller and larger than its own: λ → λ / s, A → s A. Scaling by a power
  // of two is exact in floating point, so a path that reads only unit-free quantities is the same
  // path, step for step. Before the stages read the scaled problem's own natural map (they read
  // the unit-step one in the file's units, and stopped the sweeps at a target in those units), the
  // file in units 1000 times smaller was not verified; in its own units it is. Each answer judged
  // by the unit-free residual (unit_free.hpp, tested apart) and against the answer in the file's
  // units.
  const StoredProblem p = read_problem((test::kFc3dDir / "Capsules-i125-1213.hdf5").string());
  VecX reference;
  std::string reference_counts;
  for (const double force : {1.0, 1.0 / 1024.0, 1024.0}) {
    const FileSolve r = direct_in_units(p.problem(), p.cones, force);
    INFO("unit of force " << force << ": " << r.summary.message);
    CHECK(r.summary.termination == Termination::Direct);
    CHECK(r.unit_free <= 1e-10);
    // The counts of each stage, up to the residual (which is in the problem's units).
    const std::string counts = r.summary.message.substr(0, r.summary.message.find("; residual"));
    if (force == 1.0) {
      reference = r.lambda;
      reference_counts = counts;
      continue;
    }
    CHECK(counts == reference_counts);
    CHECK((r.lambda * force - reference).lpNorm<Eigen::Infinity>() <=
          1e-12 * reference.lpNorm<Eigen::Infinity>());
  }
}

TEST_CASE("direct on cones factors in body space where J and Minv are known, as row space solves",
          "[cone-direct]") {
  // The same problem with and without J and Minv: in body space (M + Jᵀ Ω J, Woodbury) and in
  // row space (A + B). The relaxation's w = A λ − b is unique (the QP's objective is strictly
  // convex along A λ), so both answers must give the same w whatever λ they pick on a singular
  // A. On the pile settling under the paper's box the body-space solves lose accuracy late and
  // the interior point moves to row space (interior_system.hpp); the answer is solved either way.
  struct Case {
    int step;
    const char* moves;  // where the summary says the interior point ended
  };
  for (const Case c : {Case{50, "body"}, Case{3, "row"}}) {
    const System sys = system_of("pyramid", {{"base", "5"}, {"mu", "0.5"}}, c.step);
    const FrictionContacts cones = cones_of(sys, 0.5, FrictionLaw::Relaxation);
    BoxedProblem body = sys.problem();
    REQUIRE(body.has_factors());
    body.cones = &cones;
    BoxedProblem row = body;
    row.J = nullptr;
    row.Minv = nullptr;
    VecX lambda_body, lambda_row;
    const SolverSummary sb = solve(body, lambda_body, direct_options(1e-10));
    const SolverSummary sr = solve(row, lambda_row, direct_options(1e-10));
    INFO("step " << c.step << ": body " << sb.message << "; row " << sr.message);
    CHECK(sb.termination == Termination::Direct);
    CHECK(sr.termination == Termination::Direct);
    CHECK(sb.space == c.moves);
    CHECK(sr.space == "row");
    CHECK(sb.message.find("in body space") != std::string::npos);
    CHECK(sr.message.find("in body space") == std::string::npos);
    CHECK(natural_map_residual(body, lambda_body) <= 1e-10);
    const VecX w_body = sys.A * lambda_body - sys.b;
    const VecX w_row = sys.A * lambda_row - sys.b;
    CHECK((w_body - w_row).lpNorm<Eigen::Infinity>() <= 1e-8);  // m/s², of b up to 9.81
  }
}

TEST_CASE("direct solves Siconos' problems whose W is not symmetric, under both laws",
          "[cone-direct][siconos-fc3d]") {
  // Issue 51, item 1: W from the simulators themselves (a rover's wheels, an object on a
  // floor, a pile of capsules: max |W − Wᵀ| 2.7e-6, 6.7e-3, 1.6e-2), which direct refused. The
  // verdict is the law's natural map of the returned lambda on the true W, computed here. The
  // capsules need the relaxation on W's symmetric part, the interior point with De Saxcé's term
  // refreshed, Newton's steps on Alart–Curnier's function and proximal points around them.
  for (const char* name :
       {"Rover4396.dat", "OneObject-i1028-138.hdf5.dat", "Capsules-i125-1213.hdf5"}) {
    StoredProblem p = read_problem((test::kFc3dDir / name).string());
    REQUIRE(max_asymmetry(p.A) > symmetry_tolerance(p.A));
    for (const FrictionLaw law : {FrictionLaw::CoulombCone, FrictionLaw::Relaxation}) {
      p.cones.law = law;
      VecX lambda;
      const SolverSummary s = solve(p.problem(), lambda, direct_options(1e-10));
      INFO(name << ", " << cone_law_name(law) << ": " << s.message);
      CHECK(s.termination == Termination::Direct);
      const VecX w = p.A * lambda - p.b;
      CHECK(natural_map_residual(w, lambda, p.cmin, p.cmax, p.cones) <=
            1e-10 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>()));
    }
  }
}

TEST_CASE(
    "direct on a W that is not symmetric hands Newton's steps to proximal points, not to the "
    "fixed point on s",
    "[cone-direct][siconos-fc3d]") {
  // Guards the route on a file read as `cbps lcp` reads it (the tolerance a unit-free residual).
  // Siconos' Capsules-i125-1213 (286 contacts, W not symmetric): from the refreshed interior
  // point, Newton's steps on Alart–Curnier's function and proximal points around them finish
  // it. Before, the fixed point on s ran (from the relaxation's answer its rounds ended far from
  // the law) and 6,000 NSGS sweeps finished it, 322 factorizations.
  StoredProblem p = read_problem((test::kFc3dDir / "Capsules-i125-1213.hdf5").string());
  REQUIRE(max_asymmetry(p.A) > symmetry_tolerance(p.A));
  const FileSolve f = direct_in_units(p.problem(), p.cones, 1.0);
  INFO(f.summary.message);
  CHECK(f.summary.termination == Termination::Direct);
  CHECK(f.summary.message.find(" 0 fixed-point rounds") != std::string::npos);
  CHECK(f.summary.message.find(" 180 NSGS sweeps") != std::string::npos);  // stage 0's alone
  CHECK(f.summary.factorizations <= 200);
  CHECK(f.unit_free <= 1e-10);
  const VecX w = p.A * f.lambda - p.b;
  CHECK(natural_map_residual(w, f.lambda, p.cmin, p.cmax, p.cones) <=
        1e-10 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>()));
}

TEST_CASE(
    "direct on a W that is not symmetric finishes with proximal points in PROX's schedule where "
    "every other stage stops short",
    "[cone-direct][siconos-fc3d]") {
  // Siconos' Capsules-i101-404 (225 contacts, W not symmetric and singular) with every mu halved,
  // a problem no simulation wrote: stages 0 to 4 stop near 5e-8 (unit-free; before, direct said
  // "not verified" there), where Siconos' PROX solves it (4e-15 in 0.7 s). Stage 5 on such a W,
  // proximal points whose every answer is the next centre (proximal_points), finishes it. The
  // verdict is checked apart from the solver's own: Coulomb's natural map of the answer.
  StoredProblem p = read_problem((std::filesystem::path(CBPS_SOURCE_DIR) /
                                  "validation/data/siconos-fc3d/Capsules-i101-404.dat")
                                     .string());
  REQUIRE(max_asymmetry(p.A) > symmetry_tolerance(p.A));
  FrictionContacts halved = p.cones;
  halved.mu *= 0.5;
  const FileSolve f = direct_in_units(p.problem(), halved, 1.0);
  INFO(f.summary.message);
  CHECK(f.summary.termination == Termination::Direct);
  CHECK(f.summary.message.find("stage 5's, in PROX's schedule") != std::string::npos);
  CHECK(f.unit_free <= 1e-10);
  const VecX w = p.A * f.lambda - p.b;
  CHECK(natural_map_residual(w, f.lambda, p.cmin, p.cmax, halved) <=
        1e-10 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>()));
}

TEST_CASE(
    "direct follows its averaged fixed point with proximal points where A is symmetric and the "
    "rounds stop short",
    "[cone-direct]") {
  // The card house of `cbps scenes card-house` stepped 30 times under its own law (Coulomb's
  // box), that step posed on Coulomb's cone (`cbps matrices card-house --step 30 --fclib F
  // --cone coulomb`: 60 contacts, A singular, rank 90 of 180), each contact's mu spread over
  // [0.3, 0.8] by the golden ratio.
  // Every stage up to the averaged fixed point stops short (a unit-free 7.7e-7 was direct's
  // answer, "not verified"), where Siconos' PROX solves it; proximal points from the rounds' best
  // point finish it. The verdict is checked apart from the solver: the unit-free residual
  // (unit_free.hpp) and Coulomb's natural map of the answer.
  const System sys = system_of("card-house", {}, 30);
  FrictionContacts cones = contacts_in_cones(sys, FrictionLaw::CoulombCone);
  REQUIRE(cones.mu.size() == 60);
  for (Eigen::Index k = 0; k < cones.mu.size(); ++k)
    cones.mu(k) = 0.3 + 0.5 * std::fmod(0.6180339887498949 * double(k) + 0.5, 1.0);
  BoxedProblem problem = sys.problem();
  problem.cones = &cones;
  VecX lambda;
  SolverOptions o = direct_options(1e-10);
  o.tolerance_unit_free = true;
  const SolverSummary s = solve(problem, lambda, o);
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  CHECK(s.message.find("averaged fixed-point rounds") != std::string::npos);
  CHECK(s.message.find("stage 5's, in PROX's schedule") != std::string::npos);
  CHECK(unit_free_residual(problem, lambda).relative <= 1e-10);
  const VecX w = sys.A * lambda - sys.b;
  CHECK(natural_map_residual(w, lambda, problem.cmin, problem.cmax, cones) <=
        1e-8 * std::max(1.0, lambda.lpNorm<Eigen::Infinity>()));
}

TEST_CASE("direct's averaged fixed point stays off a W that is not symmetric",
          "[cone-direct][siconos-fc3d]") {
  // Stage 5's rounds are a map of s only where each relaxation is a QP (A symmetric). Siconos'
  // RockPile_tob1 (463 contacts, W not symmetric), which no solver measured brings to 1e-8, is
  // where stages 1 to 4 stop short: its answer must say so, with no averaged round (they ran 167
  // rounds in 54 s there, no better). Stage 5 there is proximal_points, which spends its own
  // budget (5,000 factorizations, 15 s) without finishing: the time limit stops it sooner.
  StoredProblem p = read_problem(
      (std::filesystem::path(CBPS_SOURCE_DIR) / "validation/data/siconos-fc3d/RockPile_tob1.dat")
          .string());
  REQUIRE(max_asymmetry(p.A) > symmetry_tolerance(p.A));
  VecX lambda;
  SolverOptions o = direct_options(1e-10);
  o.time_limit = 3.0;
  const SolverSummary s = solve(p.problem(), lambda, o);
  INFO(s.message);
  CHECK(s.termination != Termination::Direct);
  CHECK(s.message.find("averaged fixed-point rounds") == std::string::npos);
  // nor the interior point with De Saxcé's term differentiated (its matrix takes A's rows for
  // its columns)
  CHECK(s.message.find(" 0 with it differentiated") != std::string::npos);
  CHECK(s.message.find("not verified") != std::string::npos);
}

TEST_CASE(
    "direct chooses its first stage by size: the cheap start on a small W of low rank, the "
    "interior point on a large problem from zero",
    "[cone-direct][siconos-fc3d]") {
  // Guards the route, not a time: the stages that finish are the cheap ones (docs/cones.md).
  // Siconos' OneObject (69 rows, 23 contacts of one object: W of rank 6, Newton's matrix
  // singular at most points) is answered by stage 0, its sweeps, Newton's steps and proximal
  // points around them, within the short round's budget (4 + 25 factorizations), with no
  // interior iteration; before, the interior point's stages took 95 iterations.
  {
    StoredProblem p = read_problem((test::kFc3dDir / "OneObject-i1028-138.hdf5.dat").string());
    VecX lambda;
    const SolverSummary s = solve(p.problem(), lambda, direct_options(1e-10));
    INFO(s.message);
    CHECK(s.termination == Termination::Direct);
    CHECK(s.iterations == 0);
    CHECK(s.factorizations <= 29);
    const VecX w = p.A * lambda - p.b;
    CHECK(natural_map_residual(w, lambda, p.cmin, p.cmax, p.cones) <=
          1e-10 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>()));
    // The same file as `cbps lcp` reads it (the tolerance a unit-free residual): the short round
    // too. Its proximal subproblems end where Newton's steps crawl (kQuickPatience); before,
    // the first took the round's whole budget (25 steps, 6e-2 to 3.6e-3) and the long round of
    // 200 sweeps finished it, 51 factorizations.
    const FileSolve f = direct_in_units(p.problem(), p.cones, 1.0);
    INFO(f.summary.message);
    CHECK(f.summary.termination == Termination::Direct);
    CHECK(f.summary.iterations == 0);
    CHECK(f.summary.message.find(" 20 NSGS sweeps") != std::string::npos);
    CHECK(f.summary.factorizations <= 29);
    CHECK(f.unit_free <= 1e-10);
  }
  // A pyramid of 768 rows at rest (50 steps in the relaxation's cone) under Coulomb's law, from
  // zero: the relaxation's interior point is the answer (no contact slides), and stage 0's
  // sweeps are not run (with them first the base-20 pyramid took 0.72 s instead of 57 ms).
  {
    Scene scene = make_builtin_scene(
        "pyramid", {{"base", "8"}, {"friction", "cone"}, {"cone", "ccp"}, {"mu", "0.5"}});
    scene.solver.method = Method::Direct;
    Simulation sim(scene);
    for (int step = 0; step < 50; ++step) sim.step();
    const System sys = sim.build_system();
    const FrictionContacts cones = cones_of(sys, 0.5, FrictionLaw::CoulombCone);
    BoxedProblem problem = sys.problem();
    problem.cones = &cones;
    REQUIRE(problem.rows() > 500);
    VecX lambda;
    const SolverSummary s = solve(problem, lambda, direct_options(1e-10));
    INFO(s.message);
    CHECK(s.termination == Termination::Direct);
    CHECK(s.iterations > 0);
    CHECK(s.message.find("NSGS sweeps") == std::string::npos);
    CHECK(natural_map_residual(problem, lambda) <=
          1e-10 * std::max(1.0, sys.b.lpNorm<Eigen::Infinity>()));
  }
}

namespace {

/// Coulomb's law at each contact of a problem and its answer lambda (in the problem's units),
/// within `tol` of the largest force and of the velocity scale `velocity`: r in the cone, De
/// Saxcé's û in its dual, r ⟂ û.
void check_coulomb_contacts(const BoxedProblem& problem,
                            const FrictionContacts& cones,
                            const VecX& lambda,
                            double tol,
                            double velocity) {
  const VecX w = problem.A * lambda - problem.b;
  const double force = lambda.lpNorm<Eigen::Infinity>();
  for (long i = 0; i < cones.contacts(); ++i) {
    const int n = cones.normal[std::size_t(i)];
    const double mu = cones.mu(i);
    const Vec3 f = lambda.segment<3>(n), u = w.segment<3>(n);
    const double un_hat = u(0) + mu * u.tail<2>().norm();  // De Saxcé's û_n
    INFO("contact " << i << ": r " << f.transpose() << ", u " << u.transpose());
    CHECK(f.tail<2>().norm() <= mu * f(0) + tol * force);                        // r in the cone
    CHECK(un_hat >= -tol * velocity);                                            // û in its dual
    CHECK(std::abs(f.dot(Vec3(un_hat, u(1), u(2)))) <= tol * force * velocity);  // r ⟂ û
  }
}

}  // namespace

TEST_CASE("direct changes a contact's status where the stages stall on a singular W",
          "[cone-direct][status]") {
  // The card house with friction on cones after 5 steps (60 contacts, mu 0.7, A of rank 90 of
  // 180), as `cbps lcp` reads the FCLIB file of `cbps matrices card-house --param friction=cone
  // --step 5 --fclib F --cone coulomb` (tolerance_unit_free, no J or Minv). Stages 0 to 5 stop
  // at a unit-free 1.3e-10, where Siconos 4.4's PROX reaches 2e-16: contacts slide at 1e-9 m/s,
  // and one that slips at 4e-8 m/s at the stages' best point is open in the answer. The search
  // over statuses (stage 6) must find an answer and verify it. Judged by the unit-free residual
  // (unit_free.hpp, tested apart) and by Coulomb's law checked contact by contact here.
  const System sys = system_of("card-house", {{"friction", "cone"}}, 5);
  const FrictionContacts cones = contacts_in_cones(sys, FrictionLaw::CoulombCone);
  REQUIRE(cones.contacts() == 60);
  const BoxedProblem problem = sys.problem();
  const FileSolve r = direct_in_units(problem, cones, 1.0);
  INFO(r.summary.message);
  CHECK(r.summary.termination == Termination::Direct);
  CHECK(r.summary.message.find("statuses fixed") != std::string::npos);
  CHECK(r.unit_free <= 1e-10);
  check_coulomb_contacts(problem, cones, r.lambda, 1e-12, 1.0);  // SI: 1e-12 m/s
}

TEST_CASE("direct solves a W that is not symmetric from its symmetric part's answer",
          "[cone-direct][status]") {
  // The same card house with a skew part added to W, of the size a stored file's round-off
  // leaves (Siconos' Rover files: 1e-6 of max |W_ij|): W' = W + 1e-12 (K − Kᵀ), K_ij = s_ij W_ij
  // above the diagonal, s_ij in {−1, −1/2, 0, 1/2, 1} by (i + 2j) mod 5. W' is not symmetric in
  // cbps's measure (kSymmetryTolerance), so the stages of a symmetric W (the fixed points on De
  // Saxcé's term) do not run, and those of a W that is not, the status search (stage 6) on W'
  // among them, stop short (a unit-free 3e-10 with random skew parts of 1e-12 to 1e-8, where
  // Siconos 4.4's PROX reaches 3e-15 on the one of 1e-12). Stage 7 solves W's symmetric part by
  // the symmetric stages, then W' from that answer: it must verify an answer that keeps
  // Coulomb's law on W' contact by contact.
  const System sys = system_of("card-house", {{"friction", "cone"}}, 5);
  const FrictionContacts cones = contacts_in_cones(sys, FrictionLaw::CoulombCone);
  REQUIRE(cones.contacts() == 60);
  const BoxedProblem symmetric = sys.problem();
  std::vector<Triplet> skew;
  for (int j = 0; j < symmetric.A.outerSize(); ++j)
    for (SpMat::InnerIterator it(symmetric.A, j); it; ++it)
      if (it.row() < j) {
        const double s = 0.5 * double((it.row() + 2 * j) % 5 - 2);
        skew.emplace_back(int(it.row()), j, 1e-12 * s * it.value());
        skew.emplace_back(j, int(it.row()), -1e-12 * s * it.value());
      }
  SpMat K(symmetric.rows(), symmetric.rows());
  K.setFromTriplets(skew.begin(), skew.end());
  const SpMat A = symmetric.A + K;
  REQUIRE(max_asymmetry(A) > symmetry_tolerance(A));
  const BoxedProblem problem{A, symmetric.b, symmetric.cmin, symmetric.cmax};
  const FileSolve r = direct_in_units(problem, cones, 1.0);
  INFO(r.summary.message);
  CHECK(r.summary.termination == Termination::Direct);
  CHECK(r.summary.message.find("statuses fixed") != std::string::npos);
  CHECK(r.summary.message.find("stage 7") != std::string::npos);
  CHECK(r.unit_free <= 1e-10);
  check_coulomb_contacts(
      problem, cones, r.lambda, 1e-10, problem.b.lpNorm<Eigen::Infinity>());  // told 1e-10
}
