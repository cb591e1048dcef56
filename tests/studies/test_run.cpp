// The one step loop (studies/run.hpp): its totals against the steps it ran, the observers'
// order and stop, and summary.json's numbers in the JSON convention of docs/outputs.md.
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "cbps/io/json_numbers.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/studies/run.hpp"

using namespace cbps;

namespace {

/// Records what it saw; stops the run after `stop_after` steps (never when negative).
class Watcher : public StepObserver {
 public:
  explicit Watcher(long stop_after = -1) : stop_after_(stop_after) {}
  void start(Simulation& /*sim*/) override { log.push_back("start"); }
  void before_step(Simulation& /*sim*/, long index) override {
    log.push_back("before " + std::to_string(index));
  }
  bool after_step(const Simulation& /*sim*/, const StepReport& report, long done) override {
    log.push_back("after " + std::to_string(done));
    residuals.push_back(report.solver.residual);
    return stop_after_ < 0 || done < stop_after_;
  }
  std::vector<std::string> log;
  std::vector<double> residuals;

 private:
  long stop_after_;
};

/// Adds up the contact points the collision found (StepReport::contacts) over the steps.
class PointCounter : public StepObserver {
 public:
  explicit PointCounter(long& n) : n_(n) {}
  bool after_step(const Simulation& /*sim*/, const StepReport& report, long /*done*/) override {
    n_ += report.contacts;
    return true;
  }

 private:
  long& n_;
};

}  // namespace

TEST_CASE("run_steps adds up the steps it ran, in the observers' order", "[run]") {
  Simulation sim(make_builtin_scene("chain", {{"n", "4"}}));
  const double energy = sim.energy();
  Watcher watcher;
  const RunTotals t = run_steps(sim, 3, {&watcher});
  CHECK(watcher.log ==
        std::vector<std::string>{
            "start", "before 0", "after 1", "before 1", "after 2", "before 2", "after 3"});
  CHECK(t.steps_requested == 3);
  CHECK(t.steps_done == 3);
  CHECK_FALSE(t.stopped);
  CHECK_FALSE(t.diverged);
  CHECK(t.energy_initial == energy);
  CHECK(t.energy_final == sim.energy());
  CHECK(t.time == sim.time());
  CHECK(t.final_residual == watcher.residuals.back());
  double max_residual = 0.0;
  for (double r : watcher.residuals) max_residual = std::max(max_residual, r);
  CHECK(t.max_residual == max_residual);
  CHECK(t.max_rows == 4);  // a 4-link chain: one distance row a link
}

TEST_CASE("an observer that returns false stops the run after that step", "[run]") {
  Simulation sim(make_builtin_scene("chain", {{"n", "3"}}));
  Watcher watcher(2);
  const RunTotals t = run_steps(sim, 10, {&watcher});
  CHECK(t.steps_done == 2);
  CHECK(t.stopped);
  CHECK(sim.steps_done() == 2);
  // Stopping at the last step is no early stop.
  Simulation again(make_builtin_scene("chain", {{"n", "3"}}));
  Watcher last(3);
  CHECK_FALSE(run_steps(again, 3, {&last}).stopped);
}

TEST_CASE("summary.json writes a value that is not finite as a string, never null", "[run]") {
  // docs/outputs.md, "JSON numbers": "inf", "-inf", "nan"; null means no value.
  const Scene scene = make_builtin_scene("chain", {{"n", "2"}});
  RunTotals t;
  t.max_residual = INFINITY;
  t.energy_final = NAN;
  t.max_constraint_error = -INFINITY;
  const nlohmann::json j = run_summary_json(scene, t, false, nlohmann::json::object());
  CHECK(j["max_residual"] == "inf");
  CHECK(j["energy_final"] == "nan");
  CHECK(j["max_constraint_error"] == "-inf");
  CHECK(j["energy_initial"] == 0.0);
  // The text is JSON: it parses back to the same strings.
  CHECK(nlohmann::json::parse(j.dump())["max_residual"] == "inf");
  CHECK(number_of_json(j["max_residual"]) == INFINITY);
  CHECK(std::isnan(number_of_json(j["energy_final"])));
}

TEST_CASE("the totals say which friction the steps solved: contacts, their mu and law", "[run]") {
  // A stack of two boxes: every contact point the collision finds gets friction rows at mu > 0,
  // so the contact-steps with friction are the points found, summed over the steps.
  for (const std::string friction : {"paper", "coulomb", "cone"}) {
    CAPTURE(friction);
    Simulation sim(make_builtin_scene(
        "stack", {{"n", "2"}, {"mu", "0.25"}, {"friction", friction}, {"cone", "ccp"}}));
    long points = 0;
    PointCounter counter(points);
    const RunTotals t = run_steps(sim, 4, {&counter});
    REQUIRE(points > 0);
    CHECK(t.friction_contact_steps == points);
    CHECK(t.solved_mu_min == 0.25);
    CHECK(t.solved_mu_max == 0.25);
    const std::string law = friction == "cone" ? "cone ccp" : friction;
    CHECK(t.solved_laws == std::map<std::string, long>{{law, points}});
  }
  // mu = 0: no friction rows, nothing solved under a friction law.
  Simulation frictionless(make_builtin_scene("stack", {{"n", "2"}, {"mu", "0"}}));
  const RunTotals t = run_steps(frictionless, 2, {});
  CHECK(t.friction_contact_steps == 0);
  CHECK(t.solved_laws.empty());
}
