// The divergence guard: a speed beyond the limit stops the run at the step analysis predicts, and
// an exploding solver is stopped naming a row.
#include <catch2/catch.hpp>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"

using namespace cbps;

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
