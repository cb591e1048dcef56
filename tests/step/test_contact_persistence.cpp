// Contact persistence in the step (World::contact_persistence, collision/persistence.hpp): rows
// keep their ids across steps where their points stay, and the ids stay unique.
#include <catch2/catch.hpp>
#include <cstdint>
#include <set>
#include <string>

#include "cbps/rows/contact.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"

using namespace cbps;

namespace {

/// Rows of 100 steps of the default 10-box stack that start without last step's lambda (rows −
/// warm_rows, after the first step), with the given persistence distance, m; every step's row
/// ids are checked to be unique (a repeated id would hand one row's lambda to two).
long cold_rows(const std::string& persistence) {
  Simulation sim(make_builtin_scene("stack", {{"persistence", persistence}}));
  long cold = 0;
  for (int s = 0; s < 100; ++s) {
    const System& sys = sim.assemble();
    const std::set<std::uint64_t> ids(sys.ids.begin(), sys.ids.end());
    CAPTURE(s);
    REQUIRE(ids.size() == sys.ids.size());
    const StepReport r = sim.step();
    if (s > 0) cold += r.rows - r.warm_rows;
  }
  return cold;
}

}  // namespace

TEST_CASE("persistence keeps the warm start of the resting stack's rows (7)",
          "[persistence][step]") {
  // Measured over 100 steps: 1,377 rows start cold matching by feature id, 24 by position (all
  // 24 come in 7 steps, each a point new to its pair: the pair had one point fewer the step
  // before).
  const long by_feature = cold_rows("0");
  const long by_position = cold_rows("0.02");
  CHECK(by_feature > 1000);
  CHECK(by_position * 20 < by_feature);
}

TEST_CASE("without persistence a contact's rows are named by its feature id, as before",
          "[persistence][step]") {
  Scene scene = make_builtin_scene("stack", {{"n", "3"}, {"persistence", "0"}});
  Simulation sim(scene);
  for (int s = 0; s < 5; ++s) sim.step();
  std::vector<Row> rows;
  std::vector<Manifold> manifolds;
  sim.build_rows(rows, manifolds);
  std::set<std::uint64_t> want;
  for (const Manifold& m : manifolds)
    for (const ContactPoint& p : m.points) {
      CHECK(p.id == p.feature);
      for (int k = 0; k < 3; ++k) want.insert(contact_row_id(m.a, m.b, p.feature, k));
    }
  std::set<std::uint64_t> got;
  for (const Row& row : rows) got.insert(row.id);
  CHECK(got == want);

  // With persistence every point has a fresh or continued id, never a feature id.
  Simulation kept(make_builtin_scene("stack", {{"n", "3"}}));
  for (int s = 0; s < 5; ++s) kept.step();
  kept.build_rows(rows, manifolds);
  for (const Manifold& m : manifolds)
    for (const ContactPoint& p : m.points) CHECK(p.id >= ContactMemory::kFirstFreshContactId);
}
