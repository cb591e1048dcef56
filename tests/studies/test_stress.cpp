// The stress issue: divergence guard, constraint-force mixing, condition estimates, the Euler
// reference, the catalogue and `cbps stress`, and byte-identical outputs.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>

#include "cbps/error.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/studies/conditioning.hpp"
#include "cbps/studies/euler_reference.hpp"
#include "cbps/studies/stress.hpp"
#include "fixture.hpp"

using namespace cbps;
using cbps::test::run_cli;
using cbps::test::scratch_dir;
using cbps::test::slurp;

namespace {

/// A ball falling freely (no rows) with a divergence speed limit of `limit` m/s.
Scene falling_ball(double limit) {
  Scene s;
  s.world.dt = 0.01;
  s.world.divergence_speed = limit;
  Body ball;
  ball.name = "ball";
  ball.collides = false;
  set_mass(ball, 2.0);
  s.bodies.push_back(ball);
  return s;
}

/// The tridiagonal matrix tridiag(−1, 2, −1) of size n: eigenvalues 2 − 2 cos(k π / (n + 1)).
SpMat laplacian(int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < n; ++k) {
    t.emplace_back(k, k, 2.0);
    if (k + 1 < n) {
      t.emplace_back(k, k + 1, -1.0);
      t.emplace_back(k + 1, k, -1.0);
    }
  }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

double laplacian_condition(int n) {
  const double pi = std::acos(-1.0);
  const double h = pi / (n + 1);
  return (2.0 - 2.0 * std::cos(n * h)) / (2.0 - 2.0 * std::cos(h));
}

}  // namespace

TEST_CASE("divergence guard: a speed beyond the limit stops at the step analysis predicts",
          "[stress][divergence]") {
  // v after step k (0-based) is g (k + 1) dt; the first step beyond 1 m/s is k = 10 (1.079 m/s).
  Simulation sim(falling_ball(1.0));
  long failed = -1;
  try {
    for (int k = 0; k < 100; ++k) sim.step();
  } catch (const DivergenceError& e) {
    failed = e.step();
    CHECK(e.body() == 0);
    CHECK(e.row() == -1);  // no row acts on a free body
    const std::string what = e.what();
    CHECK(what.find("step 10") != std::string::npos);
    CHECK(what.find("body 0 (ball)") != std::string::npos);
    CHECK(what.find("divergence_speed") != std::string::npos);
  }
  CHECK(failed == 10);
  // The step that failed did not move the body: it stands where step 9 left it.
  CHECK(sim.steps_done() == 10);
  CHECK(sim.bodies()[0].v().norm() == Approx(9.81 * 10 * 0.01).epsilon(1e-12));
}

TEST_CASE("divergence guard: an exploding solver is stopped naming a row", "[stress][divergence]") {
  // Jacobi (relaxation 1) on a 10-box stack diverges within one step (cbps converge).
  Scene s = make_builtin_scene("stack", {});
  s.solver.method = Method::Jacobi;
  Simulation sim(s);
  try {
    for (int k = 0; k < 5; ++k) sim.step();
    FAIL("no divergence reported");
  } catch (const DivergenceError& e) {
    CHECK(e.row() >= 0);
    CHECK(e.body() >= 1);  // a box, not the static ground
    CHECK(std::string(e.what()).find("lambda =") != std::string::npos);
  }
}

TEST_CASE("cbps run keeps the steps before a divergence and exits 1", "[stress][divergence][cli]") {
  const auto dir = scratch_dir("diverge");
  const auto r = run_cli("run stack --solver jacobi --out " + (dir / "out").string());
  CHECK(r.code == 1);
  CHECK(r.err.find("diverged: step 0") != std::string::npos);
  const auto summary = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  CHECK(summary["status"] == "diverged");
  CHECK(summary["divergence"]["step"] == 0);
  CHECK(summary["divergence"]["row"].get<int>() >= 0);
  CHECK(summary["steps"] == 0);
  // trajectory.csv holds the initial state of all 11 bodies: the header and 11 lines.
  const std::string trajectory = slurp(dir / "out" / "trajectory.csv");
  CHECK(std::count(trajectory.begin(), trajectory.end(), '\n') == 12);
}

TEST_CASE("cfm: the same row twice shares lambda, off A lambda = b by eps lambda",
          "[stress][cfm]") {
  // One pendulum row a, given twice: A = [[a + eps, a], [a, a + eps]], b = (b0, b0), so
  // lambda_1 = lambda_2 = b0 / (2 a + eps): unique, where without eps only the sum is.
  Scene s = make_builtin_scene("chain", {{"n", "1"}, {"link_length", "1"}});
  s.bodies[0].set_velocity(Vec3(0.5, 0.0, 0.0), Vec3::Zero());  // along the string: b0 ≠ 0
  const System single = Simulation(s).build_system();
  const double a = single.A.coeff(0, 0);
  const double b0 = single.b(0);
  REQUIRE(std::abs(b0) > 1.0);
  DistanceConstraint twin = s.distances.front();
  s.distances.push_back(twin);
  const double eps = 1e-3;
  const double share = b0 / (2 * a + eps);
  s.solver.cfm = eps;
  for (const char* method : {"pgs", "matrix-free", "direct"}) {
    INFO(method);
    s.solver.method = method_of(method);
    Simulation sim(s);
    const System& sys = sim.assemble();
    // A stays J Minv Jᵀ: eps is the solver's, not the system's.
    CHECK(sys.A.coeff(0, 0) == Approx(a).epsilon(1e-14));
    CHECK(sys.A.coeff(0, 1) == Approx(a).epsilon(1e-14));
    VecX lambda = VecX::Zero(2);
    sim.solve_system(sys, lambda);
    // Gauss-Seidel evens the split out only at 1 − eps/a a sweep; its last row holds exactly,
    // a S + eps lambda_2 = b0, so the sum S is off by at most eps |lambda_2| / a.
    CHECK(lambda.sum() == Approx(2 * share).epsilon(2 * eps / a));
    if (std::string(method) == "direct") {
      CHECK(lambda(0) == Approx(share).epsilon(1e-10));
      CHECK(lambda(1) == Approx(share).epsilon(1e-10));
    }
    const double reported = sim.step().cfm_acceleration_error;
    CHECK(reported == Approx(eps * lambda.cwiseAbs().maxCoeff()).epsilon(1e-9));
  }
}

TEST_CASE("cbps run reports the effect of cfm", "[stress][cfm][cli]") {
  const auto r = run_cli("run chain --steps 10 --cfm 1e-4 --json --quiet");
  REQUIRE(r.code == 0);
  const auto summary = nlohmann::json::parse(r.out);
  CHECK(summary["solver"]["cfm"] == 1e-4);
  CHECK(summary["regularization"]["max_acceleration_error"].get<double>() > 0.0);
  CHECK(summary["regularization"]["max_velocity_error"].get<double>() ==
        Approx(summary["regularization"]["max_acceleration_error"].get<double>() / 240.0));
  CHECK(run_cli("run chain --steps 10 --cfm -1").code != 0);
}

TEST_CASE("condition estimate: exact, singular and Lanczos/Cholesky against analysis",
          "[stress][condition]") {
  const ConditionEstimate small = estimate_condition(laplacian(50));
  CHECK(small.exact);
  CHECK(small.nullity == 0);
  CHECK(small.condition == Approx(laplacian_condition(50)).epsilon(1e-10));

  SpMat twice(2, 2);
  twice.insert(0, 0) = 1.0;
  twice.insert(0, 1) = 1.0;
  twice.insert(1, 0) = 1.0;
  twice.insert(1, 1) = 1.0;
  const ConditionEstimate singular = estimate_condition(twice);
  CHECK(singular.nullity == 1);
  CHECK(std::isinf(singular.condition));
  CHECK(singular.range_condition == Approx(1.0));

  const int n = 3000;  // beyond kExactConditionRows: the estimate
  REQUIRE(n > kExactConditionRows);
  const ConditionEstimate large = estimate_condition(laplacian(n));
  CHECK_FALSE(large.exact);
  CHECK(large.condition == Approx(laplacian_condition(n)).epsilon(0.02));
  CHECK(large.lambda_min == Approx(2.0 - 2.0 * std::cos(std::acos(-1.0) / (n + 1))).epsilon(1e-6));

  // A large singular matrix: the Laplacian with a zero row sum everywhere (free-free ends).
  SpMat free_free = laplacian(n);
  free_free.coeffRef(0, 0) = 1.0;
  free_free.coeffRef(n - 1, n - 1) = 1.0;
  CHECK(std::isinf(estimate_condition(free_free).condition));
}

TEST_CASE("Euler reference: a symmetric top precesses at (I3 − I1)/I1 omega3", "[stress][euler]") {
  const Vec3 I(1.0, 1.0, 2.0);
  const Vec3 omega0(0.3, 0.0, 5.0);
  const double dt = 0.01;
  const auto w = euler_reference(I, omega0, dt, 501);
  const double Omega = (I.z() - I.x()) / I.x() * omega0.z();
  for (std::size_t k = 0; k < w.size(); k += 50) {
    const double t = static_cast<double>(k) * dt;
    CHECK(w[k].x() == Approx(0.3 * std::cos(Omega * t)).margin(1e-9));
    CHECK(w[k].y() == Approx(0.3 * std::sin(Omega * t)).margin(1e-9));
    CHECK(w[k].z() == Approx(5.0).margin(1e-12));
  }
}

TEST_CASE("Euler reference: energy and |L| kept through Dzhanibekov flips", "[stress][euler]") {
  const Vec3 I(0.0241667, 0.0866667, 0.104167);
  const Vec3 omega0(1e-2, 10.0, 1e-2);
  const auto w = euler_reference(I, omega0, 0.01, 1001);
  const auto energy = [&](const Vec3& x) { return 0.5 * x.dot(I.cwiseProduct(x)); };
  const auto L2 = [&](const Vec3& x) { return I.cwiseProduct(x).squaredNorm(); };
  int flips = 0;
  for (std::size_t k = 1; k < w.size(); ++k) {
    CHECK(energy(w[k]) == Approx(energy(omega0)).epsilon(1e-9));
    CHECK(L2(w[k]) == Approx(L2(omega0)).epsilon(1e-9));
    if ((w[k - 1].y() > 0) != (w[k].y() > 0)) ++flips;
  }
  CHECK(flips >= 3);  // 10 s: the intermediate axis turns over several times
}

TEST_CASE("stress catalogue: every case says what stable means", "[stress]") {
  const auto cases = stress_catalogue();
  std::set<std::string> names;
  for (const StressCase& c : cases) {
    INFO(c.name);
    CHECK(names.insert(c.name).second);
    CHECK_FALSE(c.stable_means.empty());
    CHECK_FALSE(c.solvers.empty());
    CHECK(c.steps > 0);
  }
  // The groups the issue asks for.
  std::set<std::string> groups;
  for (const StressCase& c : cases) groups.insert(c.group);
  for (const char* g : {"mass ratio",
                        "size",
                        "time step",
                        "fast impact",
                        "redundant",
                        "near-degenerate",
                        "far from origin",
                        "extreme inertia"})
    CHECK(groups.count(g) == 1);
}

TEST_CASE("cbps stress: redundant rows, their nullity, and cfm's effect", "[stress][cli]") {
  const auto r = run_cli("stress --case '^row-twice' --json --quiet");
  REQUIRE(r.code == 0);
  const auto report = nlohmann::json::parse(r.out);
  REQUIRE(report["results"].size() == 4);  // row-twice, row-twice+cfm × pgs, direct
  for (const auto& result : report["results"]) {
    INFO(result.dump());
    CHECK(result["stable"] == true);  // v2 is unique though lambda is not
    if (result["case"] == "row-twice") {
      CHECK(result["condition"]["nullity"] == 1);
    } else {
      CHECK(result["condition"]["nullity"] == 0);
      CHECK(result["regularization"]["cfm"] == 1e-6);
    }
  }
  CHECK(run_cli("stress --case no-such-case").code == 2);
  CHECK(run_cli("stress --case '('").code == 2);
  const auto list = run_cli("stress --list");
  CHECK(list.code == 0);
  CHECK(list.out.find("stable means") != std::string::npos);
}

TEST_CASE("the same inputs give byte-identical outputs", "[stress][determinism][cli]") {
  const auto dir = scratch_dir("determinism");
  for (const char* args : {"run stack --param n=4 --steps 60 --solver pgs:order=random --seed 7",
                           "run stack --param n=4 --steps 60 --solver direct",
                           "run chain --steps 200 --solver block-pgs"}) {
    INFO(args);
    const std::string common = std::string(args) + " --no-timing --quiet --out ";
    REQUIRE(run_cli(common + (dir / "a").string()).code == 0);
    REQUIRE(run_cli(common + (dir / "b").string()).code == 0);
    for (const char* file : {"summary.json", "trajectory.csv", "steps.csv"}) {
      INFO(file);
      const std::string a = slurp(dir / "a" / file);
      CHECK_FALSE(a.empty());
      CHECK(a == slurp(dir / "b" / file));
    }
    CHECK(slurp(dir / "a" / "summary.json").find("wall_time") == std::string::npos);
  }
}

TEST_CASE("scene files set the divergence limits and cfm; bad values name their path",
          "[stress][divergence][cli]") {
  const auto dir = scratch_dir("diverge_json");
  const auto scene = [&](const std::string& world, const std::string& solver) {
    const auto path = dir / "scene.json";
    cbps::test::write_file(
        path,
        R"({"world": {"dt": 0.01)" + world + R"(}, "solver": {"method": "pgs")" + solver +
            R"(}, "bodies": [{"name": "ball", "mass": 2, "shape": {"type": "sphere", "radius": 0.1}}]})");
    return path.string();
  };
  // Free fall: v = 9.81 (k + 1) 0.01 m/s passes 1 m/s at step 10; steps 0..9 are kept.
  const auto r = run_cli("run " + scene(R"(, "divergence_speed": 1)", "") + " --steps 50 --out " +
                         (dir / "out").string());
  CHECK(r.code == 1);
  CHECK(r.err.find("step 10 ") != std::string::npos);
  CHECK(r.err.find("body 0 (ball)") != std::string::npos);
  const auto summary = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  CHECK(summary["divergence"]["step"] == 10);
  CHECK(summary["divergence"]["body"] == 0);
  CHECK(summary["steps"] == 10);
  CHECK(summary["steps_requested"] == 50);
  const std::string steps = slurp(dir / "out" / "steps.csv");
  CHECK(std::count(steps.begin(), steps.end(), '\n') == 11);  // header + steps 0..9
  const std::string trajectory = slurp(dir / "out" / "trajectory.csv");
  CHECK(std::count(trajectory.begin(), trajectory.end(), '\n') == 12);  // header, t = 0..0.1

  const auto bad_cfm = run_cli("run " + scene("", R"(, "cfm": -1)") + " --steps 1");
  CHECK(bad_cfm.code == 2);
  CHECK(bad_cfm.err.find("/solver/cfm") != std::string::npos);
  const auto bad_limit = run_cli("run " + scene(R"(, "divergence_spin": 0)", "") + " --steps 1");
  CHECK(bad_limit.code == 2);
  CHECK(bad_limit.err.find("/world/divergence_spin") != std::string::npos);
  const auto ok = run_cli("run " + scene("", R"(, "cfm": 1e-6)") + " --steps 3 --json");
  REQUIRE(ok.code == 0);
  CHECK(nlohmann::json::parse(ok.out)["solver"]["cfm"] == 1e-6);
}
