// The step (3.2 with all stages): which stages a scene runs, and warm starting by row id.
#include <algorithm>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::contact_scene;

namespace {

bool has_stage(const std::vector<std::string>& stages, const std::string& stage) {
  return std::find(stages.begin(), stages.end(), stage) != stages.end();
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// What a scene does not need is left out (4, 5.3, 5.4).

TEST_CASE("a scene runs only the stages and has only the columns it needs (4, 5.3, 5.4)",
          "[contact][eq4][eq5.3][eq5.4]") {
  SECTION("no contact pairs, no collision stage") {
    for (const char* name : {"pendulum-wave", "chain"}) {
      CAPTURE(name);
      Simulation sim(make_builtin_scene(name, {{"n", "5"}}));
      sim.step();
      CHECK(sim.stages().size() > 2);
      CHECK_FALSE(has_stage(sim.stages(), "collision (4)"));
      CHECK_FALSE(has_stage(sim.stages(), "contact_rows (5.3)"));
      CHECK(sim.manifolds().empty());
    }
  }
  SECTION("v-corner with mu = 0: contacts but no friction rows, 2 rows") {
    Simulation sim(contact_scene("v-corner", {{"mu", "0"}}));
    const StepReport r = sim.step();
    CHECK(has_stage(sim.stages(), "collision (4)"));
    CHECK(has_stage(sim.stages(), "contact_rows (5.3)"));
    CHECK_FALSE(has_stage(sim.stages(), "friction_rows (5.4)"));
    CHECK(r.rows == 2);
    CHECK(r.contacts == 2);
  }
  SECTION("static bodies get no columns") {
    // 3 boxes on a static ground plane: 3 movable bodies, 6 columns each.
    Simulation sim(contact_scene("stack", {{"n", "3"}}));
    const System& sys = sim.assemble();
    CHECK(sys.blocks() == 3);
    CHECK(sys.J.cols() == 18);
    CHECK(sys.block_of_body[0] == -1);
    CHECK(sys.Minv.rows() == 18);
  }
}

TEST_CASE("warm starting from last step's lambda by row id saves sweeps on a hanging chain",
          "[solver][simulation]") {
  Scene scene = make_builtin_scene("chain", {{"n", "20"}});
  // Hang it straight down and let it settle so consecutive steps have nearly equal lambda.
  for (std::size_t k = 0; k < scene.bodies.size(); ++k) {
    scene.bodies[k].x = Vec3(0.0, -0.1 * static_cast<double>(k + 1), 0.0);
  }
  scene.solver.tolerance = 1e-8;
  scene.solver.iterations = 100000;
  Scene cold_scene = scene;
  cold_scene.solver.warm = 0.0;
  Simulation warm(scene);
  Simulation cold(cold_scene);
  long warm_sweeps = 0;
  long cold_sweeps = 0;
  for (int s = 0; s < 20; ++s) {
    warm_sweeps += warm.step().solver.iterations;
    cold_sweeps += cold.step().solver.iterations;
  }
  INFO("sweeps over 20 steps: warm " << warm_sweeps << ", cold " << cold_sweeps);
  CHECK(warm_sweeps * 2 < cold_sweeps);
}
